//! Identification of recordings from any rig: segments found from what the recording
//! shows, matched to a plan when there is one.
//!
//! Per file:
//! 1. **Loaded samples**: block medians (10 ms) of F_N above the unloaded level plus
//!    `loaded_fraction` of the loaded range.
//! 2. **Baseline**: the unloaded windows at the start and end (where present) give a linear
//!    offset per channel; with one window the offset is constant; with none the rows carry
//!    the flag `no-baseline`.
//! 3. **Sign**: a tangential channel whose loaded median is negative is flipped (reported).
//! 4. **Segments**, from the best evidence available: a step column (runs of one step
//!    number), a speed channel (runs of constant speed above rest), or the signals
//!    (loaded-and-sliding runs, split at the level changes of μ into as many steps as the
//!    plan expects, or by a penalised least-squares criterion without one).
//! 5. **Steady part** of each segment from the signal ([`steady_span`]: μ, F_N and the
//!    speed within their bands), then today's spike masking and statistics
//!    ([`plateau_stats`]).
//!
//! Across files, segments are matched to the plan's steps by measured load and speed when
//! every segment has a speed, else by order; missing, extra and reordered steps are reported
//! by name. Without a plan, loads and velocities are the measured ones.

use crate::align::{Assigned, Candidate};
use crate::coverage::{Coverage, Dropped, SegmentTime};
use crate::hertz::PinContact;
use crate::identify::{identify_pin, IdentifyConfig};
use crate::identify_config::{SteadyRule, TestMode};
use crate::plan::Plan;
use crate::reciprocating::Reciprocating;
use crate::recording::{ReadReport, Recording, SpeedTrace};
use crate::signal::{block_medians, mad_sigma, median, moving_average, quantum, runs};
use crate::sliding::{quantile, SlidingEvidence};
use crate::steady::{
    final_stationary, mean_standard_error, plateau_stats, rule_span, steady_span, step_signals,
    windows, StepSignals,
};
use greybox_core::dataset::{flags, FrictionDataset, FrictionRecord};
use greybox_core::physics::{self, Quantity};
use greybox_core::units;
use greybox_core::{Error, Result, SourcePos};
use serde::Serialize;

pub use crate::expected::{expected_from_plan, read_expected_steps, ExpectedStep};
pub use crate::identify_config::Segmentation;

/// What was found in one segment of a recording.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SegmentReport {
    /// 1-based, in the file.
    pub index: usize,
    /// Segment bounds on the recording's clock, s.
    pub start_s: f64,
    pub end_s: f64,
    /// The steady part used for μ, s (absent when none was found).
    pub steady_start_s: Option<f64>,
    pub steady_end_s: Option<f64>,
    /// Mean measured normal force over the steady part (or the segment), N.
    pub normal_force_n: f64,
    /// Recorded speed over the steady part, in the channel's unit base (rpm or m/s).
    pub spindle_rpm: Option<f64>,
    pub sliding_velocity_m_per_min: Option<f64>,
    /// Step-column value, if the segment comes from one.
    pub step_label: Option<f64>,
    pub cof: Option<f64>,
    pub cof_std: Option<f64>,
    /// Standard error of μ's mean under serial correlation
    /// ([`crate::steady::mean_standard_error`]).
    pub cof_sem: Option<f64>,
    pub n_samples: usize,
    pub flags: Vec<String>,
    /// Plan pin and step it was matched to.
    pub matched: Option<(u32, u32)>,
    /// Why this segment gave no row.
    pub problem: Option<String>,
    /// Run-in before the steady part, s from the segment start: the time until μ's running
    /// level enters, and stays in, the final stretch's band (ASTM G99-17 §9; `auto` rule only).
    pub run_in_s: Option<f64>,
    /// Slope of μ over the steady part, 1/h (a slow drift is reported, not cut away).
    pub drift_per_hour: Option<f64>,
    /// Slope of μ over the steady part per sliding distance, 1/km (when the speed is known).
    pub drift_per_km: Option<f64>,
    /// Uncertainty of the segment's boundaries where one is weakly determined, s (the larger
    /// of the two; rows then carry `uncertain-boundary`).
    pub boundary_uncertainty_s: Option<f64>,
    /// A reciprocating test's strokes, cycles and μ per direction (ASTM G133; see
    /// [`crate::reciprocating`]); the row's μ is their mean over the steady cycles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reciprocating: Option<Reciprocating>,
    #[serde(skip)]
    stats: Option<crate::steady::PlateauStats>,
}

impl SegmentReport {
    /// A segment's bounds, mean load and label; nothing measured yet.
    fn bare(p: &Prepared, span: Span, index: usize) -> Self {
        let (i, j) = (span.i, span.j);
        SegmentReport {
            index,
            start_s: p.rec.time_s[i],
            end_s: p.rec.time_s[j - 1],
            steady_start_s: None,
            steady_end_s: None,
            normal_force_n: p.fn_c[i..j].iter().sum::<f64>() / (j - i) as f64,
            spindle_rpm: None,
            sliding_velocity_m_per_min: None,
            step_label: span.label,
            cof: None,
            cof_std: None,
            cof_sem: None,
            n_samples: 0,
            flags: Vec::new(),
            matched: None,
            problem: None,
            run_in_s: None,
            drift_per_hour: None,
            drift_per_km: None,
            boundary_uncertainty_s: None,
            reciprocating: None,
            stats: None,
        }
    }
}

/// What was found in one file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FileReport {
    pub source: String,
    /// Layout, mapped columns, footer and repairs, from the reader.
    pub read: Option<ReadReport>,
    pub sample_rate_hz: f64,
    pub samples: usize,
    pub duration_s: f64,
    /// The segmentation used.
    pub segmentation: String,
    /// `start and end`, `start only`, `end only` or `none`.
    pub baseline: String,
    pub drift_normal_n: f64,
    pub drift_tangential_n: f64,
    pub tangential_sign_flipped: bool,
    /// The normal force was recorded negative (compression as a negative force) and was
    /// flipped.
    pub normal_sign_flipped: bool,
    /// What decided which loaded samples slide (`speed channel` or `friction`; see
    /// [`crate::sliding`]).
    pub sliding: String,
    /// The rig's revolution or stroke period found in μ, s, if any.
    pub period_s: Option<f64>,
    /// How the sliding time was used: steady, run-in, transitions, dropped (with reasons).
    pub coverage: Coverage,
    pub segments: Vec<SegmentReport>,
    pub notes: Vec<String>,
    /// What was dropped, split, left unread or contradicts what was used, one line each: the
    /// reader's ([`ReadReport::warnings`]) and the segmentation's (a gap in time that splits a
    /// segment). Printed in the summary of every run and written into its JSON, never only
    /// under `--inspect`; dropped segments are in [`Coverage::dropped`], with their reasons.
    pub warnings: Vec<String>,
    /// Values outside their usual range ([`greybox_core::physics`]), with the number and the
    /// likely unit mistake: one line per quantity and file.
    pub unusual: Vec<String>,
    /// Rows already identified (plan-timed path).
    #[serde(skip)]
    rows: Vec<FrictionRecord>,
    /// Sliding spans left out before measuring (shorter than a step may be).
    #[serde(skip)]
    too_short: Vec<Dropped>,
}

/// The reader's summary lines of a recording ([`ReadReport::warnings`]).
fn read_warnings(rec: &Recording) -> Vec<String> {
    rec.provenance
        .as_ref()
        .map_or_else(Vec::new, |r| r.warnings.clone())
}

/// How segments were matched to a plan.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct MatchReport {
    /// `alignment by load, speed and duration` (the evidence the segments and plan share;
    /// see [`crate::align`]), `plan timing`, or `none` (no plan).
    pub method: String,
    /// Planned steps no segment was matched to.
    pub missing: Vec<String>,
    /// Segments matched to no planned step (an unplanned run-in, a repeated step).
    pub extra: Vec<String>,
    /// Planned steps that one segment spans together with the next step (the row is the
    /// later step's).
    pub merged: Vec<String>,
    pub reordered: Vec<String>,
}

/// The result of identifying a set of recordings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identification {
    #[serde(skip)]
    pub dataset: FrictionDataset,
    pub files: Vec<FileReport>,
    pub matching: MatchReport,
}

/// Per-file signals after baseline and sign correction.
struct Prepared<'a> {
    rec: &'a Recording,
    fn_c: Vec<f64>,
    ft_c: Vec<f64>,
    fs: f64,
    /// Loaded and sliding per sample.
    sliding: Vec<bool>,
    /// The rig's period in μ, s (revolution or stroke), if one was found.
    period_s: Option<f64>,
    /// Time above the loaded threshold, s.
    loaded_s: f64,
    no_baseline: bool,
    report: FileReport,
}

impl Prepared<'_> {
    /// Shortest step, s: `min_segment_s`, or three of the rig's periods if longer.
    fn min_step_s(&self, cfg: &IdentifyConfig) -> f64 {
        cfg.min_segment_s.max(3.0 * self.period_s.unwrap_or(0.0))
    }

    /// Samples per block of the change-point search: 50 ms, or one period if longer (each
    /// block then averages whole revolutions).
    fn step_block(&self) -> usize {
        ((0.05f64.max(self.period_s.unwrap_or(0.0)) * self.fs).round() as usize).max(1)
    }
}

/// Sample ranges of a segment, `[i, j)`, with its step label and the uncertainty of its
/// start and end boundaries, s (0 where the boundary is sharp).
#[derive(Debug, Clone, Copy)]
struct Span {
    i: usize,
    j: usize,
    label: Option<f64>,
    unc: (f64, f64),
    /// The run's standard error of a one-second mean of μ, √s (0: from the segment alone).
    run_sem: f64,
}

impl Span {
    fn new(i: usize, j: usize, label: Option<f64>) -> Self {
        Span {
            i,
            j,
            label,
            unc: (0.0, 0.0),
            run_sem: 0.0,
        }
    }
}

fn prepare<'a>(
    rec: &'a Recording,
    cfg: &IdentifyConfig,
    segmentation: &str,
    signed: bool,
) -> Result<Prepared<'a>> {
    rec.validate()?;
    let n = rec.len();
    let fs = rec.sample_rate_hz();
    let b = ((0.01 * fs).round() as usize).clamp(1, (n / 20).max(1));
    // a load cell that reads compression as a negative force: the normal force is flipped
    let (raw_n, bn, normal_flipped) =
        normal_positive(&rec.normal_n, block_medians(&rec.normal_n, b));
    let hi = quantile(&bn, 0.99);
    let lo = quantile(&bn, 0.01);
    if !(hi > 0.0) {
        return Err(Error::input(
            SourcePos::file(&rec.source).field("normal"),
            format!("the normal force never departs from zero (1st and 99th percentiles {lo:.3} and {hi:.3} N): check the channel mapping"),
        ));
    }
    // an unloaded level exists only if the low end is far below the loaded range
    let unloaded_level = if lo < 0.2 * hi { lo } else { 0.0 };
    let thr = unloaded_level + cfg.loaded_fraction * (hi - unloaded_level);
    let loaded_blocks: Vec<bool> = bn.iter().map(|v| *v > thr).collect();
    let loaded: Vec<bool> = (0..n).map(|k| loaded_blocks[k / b]).collect();

    // baseline from the unloaded runs at the start and the end
    let unloaded = runs(&loaded.iter().map(|l| !l).collect::<Vec<_>>());
    let min_len = ((0.05 * fs) as usize).max(5);
    let start_win = unloaded
        .first()
        .filter(|(s, e)| *s == 0 && e - s >= min_len)
        .map(|&(s, e)| (s, s + (e - s) * 8 / 10));
    let end_win = unloaded
        .last()
        .filter(|(s, e)| *e == n && e - s >= min_len && Some(&(*s, *e)) != unloaded.first())
        .map(|&(s, e)| (s + (e - s) * 2 / 10, e));
    let level = |x: &[f64], w: (usize, usize)| median(&x[w.0..w.1]);
    let mid = |w: (usize, usize)| 0.5 * (rec.time_s[w.0] + rec.time_s[w.1 - 1]);
    let line = |x: &[f64]| -> (f64, f64, f64) {
        match (start_win, end_win) {
            (Some(a), Some(e)) => {
                let (la, le) = (level(x, a), level(x, e));
                (la, (le - la) / (mid(e) - mid(a)), mid(a))
            }
            (Some(a), None) => (level(x, a), 0.0, 0.0),
            (None, Some(e)) => (level(x, e), 0.0, 0.0),
            (None, None) => (0.0, 0.0, 0.0),
        }
    };
    let (off_n, slope_n, t_n) = line(&raw_n);
    let (off_t, slope_t, t_t) = line(&rec.tangential_n);
    let fn_c: Vec<f64> = rec
        .time_s
        .iter()
        .zip(raw_n.iter())
        .map(|(t, v)| v - off_n - slope_n * (t - t_n))
        .collect();
    drop(raw_n);
    let mut ft_c: Vec<f64> = rec
        .time_s
        .iter()
        .zip(&rec.tangential_n)
        .map(|(t, v)| v - off_t - slope_t * (t - t_t))
        .collect();
    let baseline = match (start_win, end_win) {
        (Some(_), Some(_)) => "start and end",
        (Some(_), None) => "start only",
        (None, Some(_)) => "end only",
        (None, None) => "none",
    };
    let span = rec.duration_s();
    let mut notes = Vec::new();

    // sign of the tangential channel
    let loaded_idx: Vec<usize> = (0..n).filter(|k| loaded[*k]).collect();
    let mu_loaded: Vec<f64> = loaded_idx.iter().map(|&k| ft_c[k] / fn_c[k]).collect();
    // a reciprocating test's friction force changes sign by design: kept as recorded
    let flipped = !signed && median(&mu_loaded) < 0.0;
    if flipped {
        ft_c.iter_mut().for_each(|v| *v = -*v);
        notes.push(
            "the tangential force is negative while loaded: its sign was flipped".to_string(),
        );
    }
    if normal_flipped {
        notes.push("the normal force is negative while loaded (compression read as a negative force): its sign was flipped".to_string());
    }
    let blocks = crate::sliding::Blocks {
        b,
        loaded: &loaded_blocks,
        fs,
    };
    let slide = crate::sliding::sliding(rec.speed.as_ref(), &fn_c, &ft_c, &blocks, cfg);
    if let Some(thr) = slide.mu_threshold {
        notes.push(format!(
            "sliding where μ, averaged over {:.3} s, exceeds {thr:.4} (no measured speed channel)",
            cfg.sliding_smoothing_s.max(slide.period_s.unwrap_or(0.0))
        ));
    }
    if let Some(per) = slide.period_s {
        notes.push(format!(
            "μ repeats every {per:.3} s (the rig's revolution or stroke): averaged over it"
        ));
    }
    let sliding_s = slide.mask.iter().filter(|m| **m).count() as f64 / fs;
    let no_baseline = baseline == "none";
    if no_baseline {
        notes.push(
            "no unloaded window: offsets cannot be removed (rows flagged no-baseline)".to_string(),
        );
    }
    Ok(Prepared {
        rec,
        fn_c,
        ft_c,
        fs,
        sliding: slide.mask,
        period_s: slide.period_s,
        loaded_s: loaded.iter().filter(|l| **l).count() as f64 / fs,
        no_baseline,
        report: FileReport {
            source: rec.source.clone(),
            read: rec.provenance.clone(),
            warnings: read_warnings(rec),
            sample_rate_hz: fs,
            samples: n,
            duration_s: span,
            segmentation: segmentation.to_string(),
            baseline: baseline.to_string(),
            drift_normal_n: slope_n * span,
            drift_tangential_n: slope_t * span,
            tangential_sign_flipped: flipped,
            normal_sign_flipped: normal_flipped,
            sliding: slide.evidence.name().to_string(),
            period_s: slide.period_s,
            coverage: Coverage {
                sliding_s,
                ..Default::default()
            },
            segments: Vec::new(),
            notes,
            unusual: Vec::new(),
            rows: Vec::new(),
            too_short: Vec::new(),
        },
    })
}

/// The normal force with a positive load, and its block medians `bn`: both flipped (and
/// `true`) when the recording's loaded level is negative, i.e. the 1st percentile of the
/// block medians lies further below zero than their 99th lies above.
fn normal_positive(
    normal: &[f64],
    mut bn: Vec<f64>,
) -> (std::borrow::Cow<'_, [f64]>, Vec<f64>, bool) {
    let (lo, hi) = (quantile(&bn, 0.01), quantile(&bn, 0.99));
    if lo < 0.0 && -lo > hi.max(0.0) {
        bn.iter_mut().for_each(|v| *v = -*v);
        let flipped = normal.iter().map(|v| -v).collect();
        (std::borrow::Cow::Owned(flipped), bn, true)
    } else {
        (std::borrow::Cow::Borrowed(normal), bn, false)
    }
}

/// Runs of one step number, restricted to their loaded-and-sliding part.
fn spans_from_steps(p: &Prepared, steps: &[f64]) -> Vec<Span> {
    let mut out = Vec::new();
    let mut s = 0;
    for k in 1..=steps.len() {
        if k == steps.len() || steps[k] != steps[s] {
            let slide: Vec<usize> = (s..k).filter(|i| p.sliding[*i]).collect();
            if let (Some(&a), Some(&b)) = (slide.first(), slide.last()) {
                out.push(Span::new(a, b + 1, Some(steps[s])));
            }
            s = k;
        }
    }
    out
}

/// How far a channel may stray and still hold one level: `rel` × |level| + `abs`.
#[derive(Debug, Clone, Copy)]
struct LevelTolerance {
    rel: f64,
    abs: f64,
}

impl LevelTolerance {
    /// Tolerance of a speed (or load) channel from its own noise: the larger of
    /// `speed_tolerance` and four robust relative standard deviations of the block values
    /// (from the MAD of their first differences / √2 and of their residuals about a running
    /// median, so both white jitter and a slow wander count), plus 1.5 quantisation steps
    /// (the smallest non-zero change of the raw samples: a channel stepping by its LSB does
    /// not split). With a plan, at most 0.4 of its smallest relative step between distinct
    /// speeds, so that neighbouring planned levels stay apart. `sm` are block medians, `raw`
    /// the samples, `rest` the level below which the channel is at rest.
    fn from_noise(
        sm: &[f64],
        raw: &[f64],
        rest: f64,
        base_rel: f64,
        plan_step: Option<f64>,
    ) -> Self {
        let moving: Vec<usize> = (0..sm.len()).filter(|k| sm[*k].abs() >= rest).collect();
        let rel_diff: Vec<f64> = moving
            .windows(2)
            .filter(|w| w[1] == w[0] + 1)
            .map(|w| (sm[w[1]] - sm[w[0]]) / sm[w[1]].abs())
            .collect();
        let rm = crate::signal::running_median(sm, 5);
        let rel_resid: Vec<f64> = moving
            .iter()
            .map(|&k| (sm[k] - rm[k]) / sm[k].abs())
            .collect();
        let sigma = if rel_diff.len() >= 4 {
            (mad_sigma(&rel_diff, 0.0) / std::f64::consts::SQRT_2).max(mad_sigma(&rel_resid, 0.0))
        } else {
            0.0
        };
        let lsb = crate::signal::quantum(raw);
        let mut rel = base_rel.max(4.0 * sigma);
        if let Some(step) = plan_step {
            rel = rel.min(0.4 * step).max(base_rel.min(0.4 * step));
        }
        LevelTolerance {
            rel,
            abs: (0.1 * rest).max(1.5 * lsb),
        }
    }

    fn within(&self, a: f64, level: f64) -> bool {
        (a - level).abs() <= self.rel * level.abs() + self.abs
    }
}

/// The smallest relative step between distinct planned sliding velocities.
fn plan_speed_step(expected: Option<&[ExpectedStep]>) -> Option<f64> {
    let mut v: Vec<f64> = expected?.iter().map(|e| e.sliding_velocity_m_s).collect();
    v.sort_by(f64::total_cmp);
    v.windows(2)
        .map(|w| (w[1] - w[0]) / w[1])
        .filter(|d| *d > 1e-6)
        .reduce(f64::min)
}

/// Runs of one level above rest in block medians `sm`: `(start, end, level)` in blocks, each
/// run grown while blocks stay within `tol` of its running median.
fn level_runs(sm: &[f64], rest: f64, tol: LevelTolerance) -> Vec<(usize, usize, f64)> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < sm.len() {
        if sm[k].abs() < rest {
            k += 1;
            continue;
        }
        let start = k;
        let mut members = vec![sm[k]];
        k += 1;
        while k < sm.len() && tol.within(sm[k], median(&members)) {
            members.push(sm[k]);
            k += 1;
        }
        out.push((start, k, median(&members)));
    }
    out
}

/// Merge spurious splits: contiguous runs at the same level (within `tol`) join, and so do
/// two runs at the same level separated only by runs shorter than `min_blocks` (a jitter
/// excursion), which are absorbed.
fn merge_same_level(
    runs: Vec<(usize, usize, f64)>,
    tol: LevelTolerance,
    min_blocks: usize,
) -> Vec<(usize, usize, f64)> {
    let mut out: Vec<(usize, usize, f64)> = Vec::with_capacity(runs.len());
    for r in runs {
        // the latest run at r's level reachable across contiguous short runs only
        let mut back = out.len();
        let mut k = out.len();
        while k > 0 {
            let prev = out[k - 1];
            let next_start = if k == out.len() { r.0 } else { out[k].0 };
            if prev.1 != next_start {
                break;
            }
            if tol.within(prev.2, r.2) || tol.within(r.2, prev.2) {
                back = k - 1;
                break;
            }
            if prev.1 - prev.0 >= min_blocks {
                break;
            }
            k -= 1;
        }
        if back < out.len() {
            let first = out[back];
            let (n1, n2) = ((first.1 - first.0) as f64, (r.1 - r.0) as f64);
            let level = (first.2 * n1 + r.2 * n2) / (n1 + n2);
            out.truncate(back);
            out.push((first.0, r.1, level));
        } else {
            out.push(r);
        }
    }
    out
}

/// Runs of constant speed above rest, restricted to loaded samples: block medians (20 ms)
/// within a tolerance taken from the channel's own noise or the plan's steps
/// ([`LevelTolerance::from_noise`]), with spurious splits merged ([`merge_same_level`]).
fn spans_from_speed(
    p: &Prepared,
    speed: &[f64],
    cfg: &IdentifyConfig,
    expected: Option<&[ExpectedStep]>,
) -> Vec<Span> {
    let n = speed.len();
    let b = ((0.02 * p.fs).round() as usize).max(1);
    let sm = block_medians(speed, b);
    let rest = crate::sliding::speed_rest_level(&sm, cfg);
    let tol = LevelTolerance::from_noise(
        &sm,
        speed,
        rest,
        cfg.speed_tolerance,
        plan_speed_step(expected),
    );
    let min_blocks = ((cfg.min_segment_s * p.fs / b as f64).ceil() as usize).max(3);
    let levels = merge_same_level(level_runs(&sm, rest, tol), tol, min_blocks);
    let mut out = Vec::new();
    for (start, end, _) in levels {
        let (i, j) = (start * b, (end * b).min(n));
        // only the loaded part of the run
        for (a, e) in runs(&p.sliding[i..j]) {
            out.push(Span::new(i + a, i + e, None));
        }
    }
    out
}

/// Loaded-and-sliding runs (gaps under 50 ms, or two of the rig's periods, closed).
fn sliding_runs(p: &Prepared) -> Vec<Span> {
    let gap = (0.05f64.max(2.0 * p.period_s.unwrap_or(0.0)) * p.fs) as usize;
    let mut out: Vec<Span> = Vec::new();
    for (a, e) in runs(&p.sliding) {
        match out.last_mut() {
            Some(last) if a - last.j <= gap => last.j = e,
            _ => out.push(Span::new(a, e, None)),
        }
    }
    out
}

/// Prefix sums of a series and its squares: the least-squares cost of a constant piece in O(1).
struct PrefixSums {
    s1: Vec<f64>,
    s2: Vec<f64>,
}

impl PrefixSums {
    fn new(x: &[f64]) -> Self {
        let mut s1 = vec![0.0; x.len() + 1];
        let mut s2 = vec![0.0; x.len() + 1];
        for (i, v) in x.iter().enumerate() {
            s1[i + 1] = s1[i] + v;
            s2[i + 1] = s2[i] + v * v;
        }
        PrefixSums { s1, s2 }
    }

    /// Sum of squared deviations from the mean over `[a, b)` (0 for an empty piece).
    fn cost(&self, a: usize, b: usize) -> f64 {
        if b <= a {
            return 0.0;
        }
        let m = (b - a) as f64;
        let s = self.s1[b] - self.s1[a];
        (self.s2[b] - self.s2[a]) - s * s / m
    }
}

/// Residuals of `x` about the means of its pieces split at `bounds`.
fn split_residuals(x: &[f64], bounds: &[usize]) -> Vec<f64> {
    let mut edges = vec![0];
    edges.extend_from_slice(bounds);
    edges.push(x.len());
    let mut resid = Vec::with_capacity(x.len());
    for w in edges.windows(2) {
        let piece = &x[w[0]..w[1]];
        let m = piece.iter().sum::<f64>() / piece.len().max(1) as f64;
        resid.extend(piece.iter().map(|v| v - m));
    }
    resid
}

/// χ²(1) at 95 %: a boundary position whose cost exceeds the optimum by less than this many
/// noise variances is as good as the optimum.
const CHI2_1_95: f64 = 3.84;

/// Uncertainty of each inner boundary of a piecewise-constant split of `x` at `bounds`, in
/// samples of `x`: the largest distance from the boundary of a position whose two-piece cost
/// (the neighbouring boundaries fixed) lies within χ²₁(95 %) noise variances of the optimum
/// (Hinkley 1970, "Inference about the change-point in a sequence of random variables",
/// likelihood-ratio confidence set). The noise variance is the residual variance of the
/// split, inflated by (1 + ρ₁)/(1 − ρ₁) for the lag-1 autocorrelation ρ₁ of the residuals
/// (a periodic disturbance such as spindle run-out is correlated noise, not signal).
fn boundary_uncertainty(x: &[f64], bounds: &[usize]) -> Vec<usize> {
    let n = x.len();
    let sums = PrefixSums::new(x);
    let mut edges = vec![0];
    edges.extend_from_slice(bounds);
    edges.push(n);
    let resid = split_residuals(x, bounds);
    let var = resid.iter().map(|r| r * r).sum::<f64>()
        / (n.saturating_sub(edges.len() - 1)).max(1) as f64;
    let lag1 = resid.windows(2).map(|w| w[0] * w[1]).sum::<f64>()
        / resid.iter().map(|r| r * r).sum::<f64>().max(1e-300);
    let rho = lag1.clamp(0.0, 0.95);
    let threshold = CHI2_1_95 * var * (1.0 + rho) / (1.0 - rho);
    (1..edges.len() - 1)
        .map(|k| {
            let (lo, c, hi) = (edges[k - 1], edges[k], edges[k + 1]);
            let two = |m: usize| sums.cost(lo, m) + sums.cost(m, hi);
            let best = two(c);
            (lo + 1..hi)
                .filter(|m| two(*m) <= best + threshold)
                .map(|m| m.abs_diff(c))
                .max()
                .unwrap_or(0)
        })
        .collect()
}

/// Optimal split of `x` into `k` pieces of at least `min_len` by least squares (dynamic
/// programming over prefix sums). Returns the `k − 1` inner boundaries.
#[allow(clippy::needless_range_loop)] // a dynamic programme over index ranges
fn split_into(x: &[f64], k: usize, min_len: usize) -> Option<Vec<usize>> {
    let n = x.len();
    if k <= 1 {
        return Some(Vec::new());
    }
    if k * min_len > n {
        return None;
    }
    let sums = PrefixSums::new(x);
    let cost = |a: usize, b: usize| sums.cost(a, b);
    // best[j][e]: cost of splitting x[..e] into j + 1 pieces (indexed loops: the
    // recurrence reads best[j - 1][a] and writes best[j][e], clearest with indices)
    let inf = f64::INFINITY;
    let mut best = vec![vec![inf; n + 1]; k];
    let mut arg = vec![vec![0usize; n + 1]; k];
    for e in min_len..=n {
        best[0][e] = cost(0, e);
    }
    for j in 1..k {
        for e in (j + 1) * min_len..=n {
            let mut b = inf;
            let mut a_best = 0;
            for a in j * min_len..=e - min_len {
                let c = best[j - 1][a] + cost(a, e);
                if c < b {
                    b = c;
                    a_best = a;
                }
            }
            best[j][e] = b;
            arg[j][e] = a_best;
        }
    }
    let mut bounds = Vec::with_capacity(k - 1);
    let mut e = n;
    for j in (1..k).rev() {
        e = arg[j][e];
        bounds.push(e);
    }
    bounds.reverse();
    Some(bounds)
}

/// Binary segmentation with a penalty of `12 σ² ln n` per split (σ from the block-to-block
/// differences), for when the number of steps is unknown.
fn split_penalised(x: &[f64], min_len: usize) -> Vec<usize> {
    let n = x.len();
    if n < 2 * min_len {
        return Vec::new();
    }
    let d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let sigma = mad_sigma(&d, 0.0) / std::f64::consts::SQRT_2;
    let penalty = 12.0 * sigma.max(1e-6).powi(2) * (n as f64).ln();
    let mut bounds = Vec::new();
    let mut stack = vec![(0usize, n)];
    while let Some((a, b)) = stack.pop() {
        if b - a < 2 * min_len {
            continue;
        }
        let seg = &x[a..b];
        let total = {
            let m = seg.iter().sum::<f64>() / seg.len() as f64;
            seg.iter().map(|v| (v - m).powi(2)).sum::<f64>()
        };
        let Some(s) = split_into(seg, 2, min_len) else {
            continue;
        };
        let c = s[0];
        let part = |p: &[f64]| {
            let m = p.iter().sum::<f64>() / p.len() as f64;
            p.iter().map(|v| (v - m).powi(2)).sum::<f64>()
        };
        let gain = total - part(&seg[..c]) - part(&seg[c..]);
        if gain > penalty {
            bounds.push(a + c);
            stack.push((a, a + c));
            stack.push((a + c, b));
        }
    }
    bounds.sort_unstable();
    bounds
}

/// Blocks `[a, b)` of a run without the transients at its ends: from each end, blocks are
/// dropped while the mean over the last 0.2 s differs from the 0.2 s before it by more than
/// five standard errors (or 0.002), i.e. while μ still drifts.
fn trim_transients(x: &[f64]) -> (usize, usize) {
    const W: usize = 4;
    let n = x.len();
    if n < 6 * W {
        return (0, n);
    }
    let d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let sigma = mad_sigma(&d, 0.0) / std::f64::consts::SQRT_2;
    let thr = (5.0 * sigma * (2.0 / W as f64).sqrt()).max(0.002);
    let mean = |a: usize, b: usize| x[a..b].iter().sum::<f64>() / (b - a) as f64;
    let mut e = n;
    while e >= 2 * W + n / 2 && (mean(e - W, e) - mean(e - 2 * W, e - W)).abs() > thr {
        e -= 1;
    }
    let mut a = 0;
    while a + 2 * W <= n / 2 && (mean(a, a + W) - mean(a + W, a + 2 * W)).abs() > thr {
        a += 1;
    }
    (a, e)
}

/// Split a sliding run into the plan's steps for it (or as many as the signal says when
/// `steps` is `None`) at the level changes of μ (block means over 50 ms or the rig's period);
/// where every step has a planned duration, at the plan's timing instead ([`timed_bounds`]).
fn split_run(
    p: &Prepared,
    run: Span,
    steps: Option<&[ExpectedStep]>,
    cfg: &IdentifyConfig,
) -> Result<Vec<Span>> {
    let b = p.step_block();
    let mu: Vec<f64> = (run.i..run.j).map(|i| p.ft_c[i] / p.fn_c[i]).collect();
    let all_blocks: Vec<f64> = mu.chunks(b).map(median).collect();
    let block_s = b as f64 / p.fs;
    let durations: Option<Vec<f64>> = steps.and_then(|s| s.iter().map(|e| e.duration_s).collect());
    if let Some(d) = durations.filter(|d| d.len() > 1) {
        let bounds = timed_bounds(&all_blocks, &d, block_s);
        return Ok(spans_at(run, &bounds, b, &[], 0.0));
    }
    // the spindle's run-up and run-down and the run-in at the ends of a run are no steps
    let (ta, tb) = trim_transients(&all_blocks);
    let blocks = &all_blocks[ta..tb];
    let run = Span::new(run.i + ta * b, (run.i + tb * b).min(run.j), None);
    let min_abs = ((p.min_step_s(cfg) / block_s).ceil() as usize).max(2);
    let k = steps.map(<[ExpectedStep]>::len);
    let bounds = match k {
        Some(k) => {
            let min_len =
                ((cfg.min_segment_fraction * blocks.len() as f64 / k as f64) as usize).max(min_abs);
            split_into(blocks, k, min_len).ok_or_else(|| {
                Error::input(
                    SourcePos::file(&p.rec.source),
                    format!(
                        "the sliding run {:.3}–{:.3} s is too short for the {k} steps the plan expects",
                        p.rec.time_s[run.i],
                        p.rec.time_s[run.j - 1]
                    ),
                )
            })?
        }
        None => split_penalised(blocks, min_abs),
    };
    let unc = weak_boundaries(blocks, &bounds, k.is_some(), block_s);
    // the run's disturbance (noise and slow periodic parts such as run-out) as the standard
    // error of a mean over one second: SE(T) = run_sem / √T
    let resid = split_residuals(blocks, &bounds);
    let run_sem = mean_standard_error(&resid) * (resid.len() as f64 * block_s).sqrt();
    Ok(spans_at(run, &bounds, b, &unc, run_sem))
}

/// The spans of `run` cut at block `bounds` (`b` samples a block), with each boundary's
/// uncertainty (s, none: sharp) and the run's disturbance.
fn spans_at(run: Span, bounds: &[usize], b: usize, unc: &[f64], run_sem: f64) -> Vec<Span> {
    let mut edges = vec![run.i];
    edges.extend(bounds.iter().map(|c| (run.i + c * b).min(run.j)));
    edges.push(run.j);
    edges
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[1] > w[0])
        .map(|(s, w)| {
            let mut span = Span::new(w[0], w[1], None);
            span.run_sem = run_sem;
            span.unc = (
                s.checked_sub(1)
                    .and_then(|q| unc.get(q))
                    .copied()
                    .unwrap_or(0.0),
                unc.get(s).copied().unwrap_or(0.0),
            );
            span
        })
        .collect()
}

/// Step boundaries (in blocks of `block_s` s) from the plan's step durations: the planned
/// boundaries shifted by the offset, within the difference between the run's length and the
/// plan's, that best fits μ as a constant per piece (least squares over prefix sums). A run
/// longer than planned (an unplanned run-in before the first step, a late stop) gets the
/// surplus as a piece of its own, which the alignment then leaves unmatched, instead of
/// shifting every step's label.
fn timed_bounds(blocks: &[f64], durations: &[f64], block_s: f64) -> Vec<usize> {
    let n = blocks.len();
    let planned: Vec<f64> = std::iter::once(0.0)
        .chain(durations.iter().scan(0.0, |t, d| {
            *t += d;
            Some(*t / block_s)
        }))
        .collect();
    let total = *planned.last().unwrap_or(&0.0);
    let slack = n as f64 - total;
    let (lo, hi) = (slack.min(0.0).floor() as i64, slack.max(0.0).ceil() as i64);
    let sums = PrefixSums::new(blocks);
    // every edge of the plan shifted by `off`, inside the run, without the run's own ends
    let at = |off: i64| -> Vec<usize> {
        let mut e: Vec<usize> = planned
            .iter()
            .map(|c| (c + off as f64).round().clamp(0.0, n as f64) as usize)
            .filter(|c| *c > 0 && *c < n)
            .collect();
        e.dedup();
        e
    };
    let cost = |bounds: &[usize]| {
        let edges: Vec<usize> = std::iter::once(0)
            .chain(bounds.iter().copied())
            .chain(std::iter::once(n))
            .collect();
        edges.windows(2).map(|w| sums.cost(w[0], w[1])).sum::<f64>()
    };
    let best = (lo..=hi)
        .min_by(|a, b| cost(&at(*a)).total_cmp(&cost(&at(*b))))
        .unwrap_or(0);
    at(best)
}

/// The uncertainty, s, of each inner boundary of a run split at `bounds` (blocks of
/// `block_s` seconds), 0 where the boundary is well determined: its likelihood-ratio
/// confidence set ([`boundary_uncertainty`]) reaching two blocks or more; and, when the plan
/// gave the step count (`planned`), a step whose length differs by more than 30 % from the
/// median step (the plan's regular timing contradicted) makes both its boundaries uncertain
/// by that difference.
fn weak_boundaries(blocks: &[f64], bounds: &[usize], planned: bool, block_s: f64) -> Vec<f64> {
    let mut unc: Vec<f64> = boundary_uncertainty(blocks, bounds)
        .into_iter()
        .map(|u| if u >= 2 { u as f64 * block_s } else { 0.0 })
        .collect();
    if planned && bounds.len() >= 2 {
        let mut edges = vec![0];
        edges.extend_from_slice(bounds);
        edges.push(blocks.len());
        let lens: Vec<f64> = edges.windows(2).map(|w| (w[1] - w[0]) as f64).collect();
        let med = median(&lens);
        for (s, len) in lens.iter().enumerate() {
            let off = (len - med).abs();
            if off > 0.3 * med {
                for q in [s.checked_sub(1), (s < bounds.len()).then_some(s)]
                    .into_iter()
                    .flatten()
                {
                    unc[q] = unc[q].max(off * block_s);
                }
            }
        }
    }
    unc
}

/// The steady part of a segment, window-relative `[a, b)`, and the run-in end (`auto` only).
///
/// Under `auto`: F_N and the speed must be within their bands ([`steady_span`], which drops
/// load and speed ramps), and μ must be in its final stationary stretch
/// ([`final_stationary`]); the settle time and end margin are then dropped. Under
/// `last:P%` / `from:Ts` the window is the user's, as given.
fn steady_window(
    sig: &StepSignals,
    others: &[(&[f64], f64)],
    t_rel: &[f64],
    cfg: &IdentifyConfig,
    fs: f64,
) -> std::result::Result<(usize, usize, Option<usize>), String> {
    if let Some((a, b)) = rule_span(cfg.steady, t_rel, cfg.min_plateau_samples, "samples")? {
        return Ok((a, b, None));
    }
    let never =
        || "no steady part: μ, F_N or the speed never settle inside the segment".to_string();
    let (a0, b0) = steady_span(others, sig.w_smooth).ok_or_else(never)?;
    let fin = final_stationary(&sig.smooth[a0..b0], &t_rel[a0..b0], sig.w_smooth, 0.002)
        .ok_or_else(never)?;
    let (a, b) = (a0 + fin.a, a0 + fin.b);
    let settle = (cfg.settle_time_s * fs).round() as usize;
    let margin = (cfg.end_margin_s * fs).round() as usize;
    let run_in = (fin.run_in_end > 0).then_some(a0 + fin.run_in_end);
    Ok(((a + settle).min(b), b.saturating_sub(margin).max(a), run_in))
}

/// Identify one segment: steady part, statistics, speed.
fn measure(p: &Prepared, span: Span, index: usize, cfg: &IdentifyConfig) -> SegmentReport {
    let rec = p.rec;
    let (i, j) = (span.i, span.j);
    let unc = span.unc.0.max(span.unc.1);
    let mut rep = SegmentReport::bare(p, span, index);
    rep.boundary_uncertainty_s = (unc > 0.0).then_some(unc);
    let f_ref = rep.normal_force_n.abs().max(1e-9);
    let sig = match step_signals(&p.fn_c, &p.ft_c, i, j, cfg, p.fs, |k, f_n| {
        if f_n <= 0.1 * f_ref {
            Err(format!(
                "normal force {f_n:.3} N at t = {:.3} s: zero or negative inside a loaded segment",
                rec.time_s[k]
            ))
        } else {
            Ok(())
        }
    }) {
        Ok(s) => s,
        Err(m) => {
            rep.problem = Some(m);
            return rep;
        }
    };
    let (_, w) = windows(cfg, p.fs);
    let fn_s = moving_average(&p.fn_c[i..j], w);
    let speed: Option<Vec<f64>> = rec
        .speed
        .as_ref()
        .map(|s| moving_average(&s.values()[i..j], w));
    let mut others: Vec<(&[f64], f64)> = vec![(&fn_s, 0.02 * f_ref)];
    if let Some(v) = &speed {
        // a quantised channel (a 1 Hz export stepping 0.147/0.150 m/s) wanders by its LSB
        let lsb = rec
            .speed
            .as_ref()
            .map_or(0.0, |s| quantum(&s.values()[i..j]));
        others.push((v, 0.01 * median(v).abs() + 1.5 * lsb + 1e-9));
    }
    let t_rel: Vec<f64> = rec.time_s[i..j].iter().map(|t| t - rec.time_s[i]).collect();
    let (pa, pb, run_in) = match steady_window(&sig, &others, &t_rel, cfg, p.fs) {
        Ok(w) => w,
        Err(m) => {
            rep.problem = Some(m);
            return rep;
        }
    };
    let Some(st) = plateau_stats(&rec.time_s, &p.fn_c, &sig, pa, pb, 0.0, cfg) else {
        rep.problem = Some(format!(
            "only {} samples in the steady part (min {}): the segment is too short or never settles",
            pb.saturating_sub(pa),
            cfg.min_plateau_samples
        ));
        return rep;
    };
    if let Some(s) = &rec.speed {
        let v = median(&s.values()[i + pa..i + pb]);
        match s {
            SpeedTrace::SpindleRpm(_) => rep.spindle_rpm = Some(v),
            SpeedTrace::SlidingMPerS(_) => {
                rep.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(v))
            }
        }
    }
    if cfg.steady == SteadyRule::Auto {
        rep.run_in_s = Some(run_in.map_or(0.0, |k| t_rel[k]));
    }
    rep.drift_per_hour = Some(st.trend_per_s * 3600.0);
    rep.steady_start_s = Some(st.start_s);
    rep.steady_end_s = Some(st.end_s);
    rep.normal_force_n = st.normal_force_n;
    rep.cof = Some(st.mean);
    rep.cof_std = Some(st.std);
    rep.n_samples = st.n_samples;
    rep.flags = st.flags.clone();
    if p.no_baseline {
        rep.flags.push(flags::NO_BASELINE.to_string());
    }
    if boundary_matters(span, &sig, (pa, pb), p.fs, cfg) {
        rep.flags.push(flags::UNCERTAIN_BOUNDARY.to_string());
    }
    let used: Vec<f64> = (pa..pb)
        .filter(|k| sig.good[*k])
        .map(|k| sig.mu[k])
        .collect();
    // the window's own serial correlation, or the run's disturbance over the window's length
    // (a window on the crest of a slow run-out looks flat on its own)
    let sem =
        mean_standard_error(&used).max(span.run_sem / (st.end_s - st.start_s).max(1e-9).sqrt());
    rep.cof_sem = Some(sem);
    if 2.0 * sem > cfg.mean_uncertainty_tolerance {
        rep.flags.push(flags::UNCERTAIN_MEAN.to_string());
    }
    rep.stats = Some(st);
    rep
}

/// Whether a segment's uncertain boundaries matter for its μ: they reach into the steady
/// window `[pa, pb)` (segment-relative samples), and μ over the window without the reach
/// differs from μ over the whole window by more than half `mean_uncertainty_tolerance` (or
/// nothing is left).
fn boundary_matters(
    span: Span,
    sig: &StepSignals,
    (pa, pb): (usize, usize),
    fs: f64,
    cfg: &IdentifyConfig,
) -> bool {
    let len = span.j - span.i;
    let a = pa.max((span.unc.0 * fs).ceil() as usize);
    let b = pb.min(len.saturating_sub((span.unc.1 * fs).ceil() as usize));
    if (a, b) == (pa, pb) {
        return false;
    }
    let mean = |a: usize, b: usize| {
        let v: Vec<f64> = (a..b).filter(|k| sig.good[*k]).map(|k| sig.mu[k]).collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    match (mean(pa, pb), (a < b).then(|| mean(a, b)).flatten()) {
        (Some(all), Some(inner)) => (all - inner).abs() > 0.5 * cfg.mean_uncertainty_tolerance,
        _ => true,
    }
}

/// Drift per sliding distance (1/km) of every measured segment with a known speed, and a
/// note per segment with a run-in, a drift flagged `trend` or an uncertain boundary.
fn steady_notes(files: &mut [FileReport]) {
    for f in files.iter_mut() {
        for s in f.segments.iter_mut() {
            let (Some(per_h), Some(v)) = (s.drift_per_hour, s.sliding_velocity_m_per_min) else {
                continue;
            };
            // μ/h ÷ (km/h) = μ/km, with v in m/min → 0.06 v km/h
            if v.abs() > 0.0 {
                s.drift_per_km = Some(per_h / (0.06 * v.abs()));
            }
        }
        let mut notes = Vec::new();
        for s in &f.segments {
            let mut parts = Vec::new();
            if let Some(r) = s.run_in_s.filter(|r| *r > 0.0) {
                parts.push(format!("run-in {r:.1} s"));
            }
            if s.flags.iter().any(|x| x == flags::TREND) {
                let km = s
                    .drift_per_km
                    .map_or(String::new(), |k| format!(", {k:+.2e} /km"));
                parts.push(format!(
                    "μ drifts {:+.4} /h{km} over the steady part",
                    s.drift_per_hour.unwrap_or(0.0)
                ));
            }
            if let Some(u) = s.boundary_uncertainty_s {
                parts.push(format!("uncertain boundary (±{u:.3} s)"));
            }
            if !parts.is_empty() {
                notes.push(format!("segment {}: {}", s.index, parts.join("; ")));
            }
        }
        f.notes.extend(notes);
    }
}

/// Why a recording is identified as a reciprocating test, or `None` (see
/// [`crate::reciprocating::detect`]): the mode named in `[identify] mode` / `--test-mode`,
/// else the rig profile's mode and the strokes the signals show.
fn reciprocating_reason(rec: &Recording, cfg: &IdentifyConfig) -> Option<String> {
    let profile = rec.provenance.as_ref().and_then(|r| r.test_mode);
    crate::reciprocating::detect(
        &crate::reciprocating::Signals::of(rec),
        cfg.mode,
        profile,
        cfg,
    )
}

/// A reciprocating file's segments: one per test (or load/speed step), μ averaged over the
/// steady cycles with the strokes and cycles kept beside it (ASTM G133).
fn reciprocating_segments(p: &mut Prepared, why: &str, cfg: &IdentifyConfig) {
    let s = crate::reciprocating::Signals::with_forces(p.rec, &p.fn_c, &p.ft_c);
    let parts = crate::reciprocating::parts(&s, cfg);
    let mut segs = Vec::with_capacity(parts.len());
    for (k, &(i, j, label)) in parts.iter().enumerate() {
        let mut rep = SegmentReport::bare(p, Span::new(i, j, label), k + 1);
        match &p.rec.speed {
            Some(SpeedTrace::SpindleRpm(v)) => rep.spindle_rpm = Some(median(&v[i..j])),
            Some(SpeedTrace::SlidingMPerS(v)) => {
                let m = median(&v[i..j].iter().map(|x| x.abs()).collect::<Vec<_>>());
                rep.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(m));
            }
            None => {}
        }
        match crate::reciprocating::analyse(&s, i, j, cfg) {
            Ok(r) => reciprocating_stats(&mut rep, r, p, cfg),
            Err(m) => rep.problem = Some(m),
        }
        segs.push(rep);
    }
    p.report.segmentation = "reciprocating".into();
    p.report.notes.push(format!("reciprocating test (ASTM G133): {why}; μ per stroke over its middle 50 %, sign taken by direction"));
    if segs.is_empty() {
        p.report
            .notes
            .push("no loaded stretch: no stroke found".into());
    }
    p.report.segments = segs;
}

/// Fill a segment from a reciprocating result: the row's μ is the steady cycles' mean μ,
/// its spread the cycles' spread, its standard error that over the cycles.
fn reciprocating_stats(
    rep: &mut SegmentReport,
    r: Reciprocating,
    p: &Prepared,
    cfg: &IdentifyConfig,
) {
    let n_cycles = r.steady_cycles.1 - r.steady_cycles.0;
    let duration = r.end_s - r.start_s;
    let trend = (r.trend_per_s * duration).abs() > cfg.trend_tolerance;
    let mut fl = vec![flags::RECIPROCATING.to_string()];
    if trend {
        fl.push(flags::TREND.to_string());
    }
    if p.no_baseline {
        fl.push(flags::NO_BASELINE.to_string());
    }
    let sem = r.mu_std / (n_cycles.max(1) as f64).sqrt();
    if 2.0 * sem > cfg.mean_uncertainty_tolerance {
        fl.push(flags::UNCERTAIN_MEAN.to_string());
    }
    if let Some(v) = r.velocity_m_s {
        rep.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(v));
        rep.spindle_rpm = None;
    }
    if r.run_in_cycles.is_some() {
        rep.run_in_s = Some(r.start_s - rep.start_s);
    }
    rep.steady_start_s = Some(r.start_s);
    rep.steady_end_s = Some(r.end_s);
    rep.normal_force_n = r.normal_n;
    rep.cof = Some(r.mu_mean);
    rep.cof_std = Some(r.mu_std);
    rep.cof_sem = Some(sem);
    rep.n_samples = r.samples;
    rep.drift_per_hour = Some(r.trend_per_s * 3600.0);
    rep.flags = fl.clone();
    rep.stats = Some(crate::steady::PlateauStats {
        mean: r.mu_mean,
        std: r.mu_std,
        n_samples: r.samples,
        start_s: r.start_s,
        end_s: r.end_s,
        trend_per_s: r.trend_per_s,
        stationary: !trend,
        flags: fl,
        spikes: 0,
        normal_force_n: r.normal_n,
    });
    rep.reciprocating = Some(r);
}

/// Inputs of [`identify_recordings`] beyond the recordings.
#[derive(Debug, Clone, Copy)]
pub struct Campaign<'a> {
    /// Expected steps (a plan without timing, or a greybox plan's steps).
    pub expected: Option<&'a [ExpectedStep]>,
    /// A greybox plan with timing, for the plan-timing path and its track radius.
    pub plan: Option<&'a Plan>,
    pub contact: &'a PinContact,
    pub cfg: &'a IdentifyConfig,
    /// Track radius, mm: one value, one per segment of each file, or one per segment of the
    /// campaign (for rpm speed channels without a radius column).
    pub track_radius_mm: &'a [f64],
}

/// Which segmentation a file gets under `Auto`.
fn resolve(method: Segmentation, rec: &Recording, plan: Option<&Plan>) -> Segmentation {
    match method {
        Segmentation::Auto if rec.step.is_some() => Segmentation::StepColumn,
        Segmentation::Auto if rec.speed.is_some() => Segmentation::Speed,
        Segmentation::Auto if plan.is_some() && rec.trigger_v.is_some() => Segmentation::PlanTiming,
        Segmentation::Auto => Segmentation::Signals,
        m => m,
    }
}

/// Identify recordings (any layout: a file per step, per pin or for the whole campaign):
/// [`segment_recordings`], then [`match_segments`].
pub fn identify_recordings(recs: &[Recording], c: &Campaign) -> Result<Identification> {
    let mut files = segment_recordings(recs, c)?;
    let (dataset, matching) = match_segments(&mut files, c)?;
    Ok(Identification {
        dataset,
        files,
        matching,
    })
}

/// Segment every recording and measure every segment (no plan matching yet). The plan-timed
/// path also fills the matched pin and step.
pub fn segment_recordings(recs: &[Recording], c: &Campaign) -> Result<Vec<FileReport>> {
    let cfg = c.cfg;
    let recip: Vec<Option<String>> = recs.iter().map(|r| reciprocating_reason(r, cfg)).collect();
    let methods: Vec<Segmentation> = recs
        .iter()
        .zip(&recip)
        .map(|(r, why)| match why {
            Some(_) => Segmentation::Signals,
            None => resolve(cfg.segmentation, r, c.plan),
        })
        .collect();
    if methods.contains(&Segmentation::PlanTiming) {
        if methods.iter().any(|m| *m != Segmentation::PlanTiming) {
            return Err(Error::invalid(
                "identify",
                "some recordings have a trigger for the plan's timing and others do not: choose one segmentation for all with `segment`",
            ));
        }
        let plan = c.plan.ok_or_else(|| {
            Error::invalid(
                "identify",
                "`segment` plan-timing needs a plan with timing (`study`)",
            )
        })?;
        return plan_timed(recs, plan, c);
    }
    for (rec, m) in recs.iter().zip(&methods) {
        let missing = match m {
            Segmentation::StepColumn if rec.step.is_none() => {
                Some("a step column (`map` step=NAME)")
            }
            Segmentation::Speed if rec.speed.is_none() => {
                Some("a speed channel (`map` speed=NAME:UNIT)")
            }
            _ => None,
        };
        if let Some(what) = missing {
            return Err(Error::input(
                SourcePos::file(&rec.source),
                format!("`segment` {} needs {what}, and none was found", m.name()),
            ));
        }
    }
    let mut prepared: Vec<Prepared> = recs
        .iter()
        .zip(&methods)
        .zip(&recip)
        .map(|((r, m), why)| prepare(r, cfg, m.name(), why.is_some()))
        .collect::<Result<_>>()?;
    // segments per file
    let mut spans: Vec<Vec<Span>> = Vec::with_capacity(recs.len());
    let mut signal_runs: Vec<(usize, Span)> = Vec::new();
    for (f, (p, m)) in prepared.iter().zip(&methods).enumerate() {
        if recip[f].is_some() {
            spans.push(Vec::new());
            continue;
        }
        match m {
            Segmentation::StepColumn => {
                spans.push(spans_from_steps(p, p.rec.step.as_deref().expect("checked")))
            }
            Segmentation::Speed => spans.push(spans_from_speed(
                p,
                p.rec.speed.as_ref().expect("checked").values(),
                cfg,
                c.expected,
            )),
            _ => {
                spans.push(Vec::new());
                signal_runs.extend(sliding_runs(p).into_iter().map(|s| (f, s)));
            }
        }
    }
    // signal runs: split into the plan's steps when the run count says which pin each is
    if !signal_runs.is_empty() {
        let per_run = plan_steps_per_run(c.expected, signal_runs.len());
        if c.expected.is_some() && per_run.iter().all(Option::is_none) {
            let pins = c.expected.map_or(0, |e| pin_groups(e).len());
            for p in prepared.iter_mut() {
                p.report.notes.push(format!(
                    "{} loaded sliding runs in all files, the plan has {pins} pins and {} steps: runs split by the signal alone, then aligned with the plan",
                    signal_runs.len(),
                    c.expected.map_or(0, <[ExpectedStep]>::len)
                ));
            }
        }
        for ((f, run), steps) in signal_runs.iter().zip(per_run) {
            let parts = split_run(&prepared[*f], *run, steps, cfg)?;
            spans[*f].extend(parts);
        }
    }
    let min_len = |p: &Prepared| (cfg.min_segment_s * p.fs) as usize;
    for ((p, s), why) in prepared.iter_mut().zip(&spans).zip(&recip) {
        if let Some(why) = why {
            reciprocating_segments(p, why, cfg);
            continue;
        }
        let s = split_at_gaps(p, s);
        let (kept, short): (Vec<Span>, Vec<Span>) =
            s.iter().partition(|s| s.j - s.i >= min_len(p).max(4));
        p.report.too_short = too_short(p, &short, cfg);
        let segs: Vec<SegmentReport> = kept
            .iter()
            .enumerate()
            .map(|(k, sp)| measure(p, *sp, k + 1, cfg))
            .collect();
        p.report.segments = segs;
        if p.report.segments.is_empty() {
            let hint = no_segment_hint(p);
            p.report.notes.push(format!("no segment found: {hint}"));
        }
        if let Some(w) = forced_mode_contradicted(p, cfg) {
            p.report.warnings.push(w);
        }
    }
    let mut files: Vec<FileReport> = prepared.into_iter().map(|p| p.report).collect();
    resolve_velocities(&mut files, c)?;
    steady_notes(&mut files);
    for f in files.iter_mut() {
        update_coverage(f, cfg, true);
    }
    Ok(files)
}

/// Why a file gave no row under a test mode the user named (`--test-mode continuous` or
/// `stepped`) that its signals contradict: the separate sliding runs it holds, and whether its
/// friction force changes sign like a reciprocating test's. `None` when a row came out or the
/// mode was not named.
fn forced_mode_contradicted(p: &Prepared, cfg: &IdentifyConfig) -> Option<String> {
    let mode = cfg.mode.filter(|m| *m != TestMode::Reciprocating)?;
    if p.report.segments.iter().any(|s| s.stats.is_some()) {
        return None;
    }
    let runs = p
        .sliding
        .iter()
        .zip(std::iter::once(&false).chain(&p.sliding))
        .filter(|(now, before)| **now && !**before)
        .count();
    let profile = p.rec.provenance.as_ref().and_then(|r| r.test_mode);
    let recip = crate::reciprocating::detect(
        &crate::reciprocating::Signals::of(p.rec),
        None,
        profile,
        cfg,
    );
    Some(format!(
        "`test_mode` {} was named, but the recording has {runs} separate sliding run(s) and none gave a steady window{}",
        mode.name(),
        recip.map_or(String::new(), |why| format!(
            "; its signals look like a reciprocating test ({why}): try `test_mode` reciprocating or leave the mode to the signals"
        ))
    ))
}

/// A pause in the recording longer than this many (median) sample intervals splits the
/// segment it falls in: no steady window spans it (an 11-day pause inside one test is two
/// tests), and the split is a line of the summary.
pub const GAP_SPLIT_INTERVALS: f64 = 100.0;

/// The spans split at every gap in time longer than [`GAP_SPLIT_INTERVALS`] sample intervals,
/// each split a warning of the file's report.
fn split_at_gaps(p: &mut Prepared, spans: &[Span]) -> Vec<Span> {
    let t = &p.rec.time_s;
    let limit = GAP_SPLIT_INTERVALS / p.fs;
    let mut out = Vec::with_capacity(spans.len());
    for sp in spans {
        let mut start = sp.i;
        for k in sp.i + 1..sp.j {
            let gap = t[k] - t[k - 1];
            if gap > limit {
                p.report.warnings.push(format!(
                    "a gap of {} in time (t = {:.3} s to {:.3} s, {:.0} sample intervals, more than {GAP_SPLIT_INTERVALS}) splits a segment: no steady window spans it",
                    duration_text(gap),
                    t[k - 1],
                    t[k],
                    gap * p.fs
                ));
                out.push(Span {
                    i: start,
                    j: k,
                    unc: (if start == sp.i { sp.unc.0 } else { 0.0 }, 0.0),
                    ..*sp
                });
                start = k;
            }
        }
        out.push(Span {
            i: start,
            unc: (if start == sp.i { sp.unc.0 } else { 0.0 }, sp.unc.1),
            ..*sp
        });
    }
    out
}

/// A duration for messages: `42.0 s`, `3.5 h`, `11.0 days`.
fn duration_text(s: f64) -> String {
    if s >= 86_400.0 {
        format!("{:.1} days", s / 86_400.0)
    } else if s >= 3600.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{s:.1} s")
    }
}

/// Sliding pieces shorter than a step, as dropped parts: pieces less than `min_segment_s`
/// apart are one entry, and three or more such pieces in a row are a ramp cut into short
/// levels: transitions, not dropped data.
fn too_short(p: &Prepared, short: &[Span], cfg: &IdentifyConfig) -> Vec<Dropped> {
    let gap = (cfg.min_segment_s * p.fs) as usize;
    let mut groups: Vec<(usize, usize, usize, usize)> = Vec::new(); // first, last, samples, count
    for sp in short {
        match groups.last_mut() {
            Some(g) if sp.i <= g.1 + gap => {
                g.1 = sp.j;
                g.2 += sp.j - sp.i;
                g.3 += 1;
            }
            _ => groups.push((sp.i, sp.j, sp.j - sp.i, 1)),
        }
    }
    groups
        .into_iter()
        .filter(|g| g.3 < 3)
        .map(|(i, j, samples, count)| Dropped {
            what: format!(
                "{} {:.3}–{:.3} s",
                if count == 1 {
                    "a piece".to_string()
                } else {
                    format!("{count} pieces")
                },
                p.rec.time_s[i],
                p.rec.time_s[j - 1]
            ),
            reason: format!(
                "shorter than the shortest step (min_segment_s = {} s)",
                cfg.min_segment_s
            ),
            seconds: samples as f64 / p.fs,
        })
        .collect()
}

/// Why a file gave no segment, from what its signals showed.
fn no_segment_hint(p: &Prepared) -> String {
    let loaded_s = p.loaded_s;
    let sliding_s = p.report.coverage.sliding_s;
    match p.report.segmentation.as_str() {
        "step-column" => "no step of the step column is loaded and sliding".into(),
        "speed" => {
            "the speed channel never holds a constant speed above rest while loaded".into()
        }
        _ if sliding_s == 0.0 => format!(
            "the normal force is above its loaded threshold for {loaded_s:.1} s, but μ never exceeds the sliding threshold there (sliding_fraction × the 75th percentile, at least sliding_min_mu; sliding evidence: {}); a step column (`map` step=NAME) or a speed channel (`map` speed=NAME:UNIT) would segment it",
            p.report.sliding
        ),
        _ => format!(
            "{sliding_s:.1} s slide, but in pieces shorter than min_segment_s; a step column (`map` step=NAME) or a speed channel (`map` speed=NAME:UNIT) would segment it"
        ),
    }
}

/// A file's coverage from its segments' state: rows from the measured (and, once matched,
/// the matched) segments, dropped parts with reasons. Before matching (`flag`), a file
/// whose steady share is below `min_steady_share` flags its measured segments
/// `low-coverage`.
fn update_coverage(f: &mut FileReport, cfg: &IdentifyConfig, flag: bool) {
    let matched_any = f.segments.iter().any(|s| s.matched.is_some());
    let mut rows = Vec::new();
    let mut dropped = f.too_short.clone();
    for s in &f.segments {
        let what = format!("segment {}", s.index);
        let seconds = s.end_s - s.start_s;
        let reason = match (&s.problem, s.steady_start_s.zip(s.steady_end_s)) {
            (Some(p), _) => Some(p.clone()),
            (None, None) => Some("no steady part".to_string()),
            (None, Some(_)) if matched_any && s.matched.is_none() => {
                Some("matched to no planned step".to_string())
            }
            (None, Some(_)) => None,
        };
        match (reason, s.steady_start_s.zip(s.steady_end_s)) {
            (Some(reason), _) => dropped.push(Dropped {
                what,
                reason,
                seconds,
            }),
            (None, Some((a, b))) => rows.push(SegmentTime {
                start_s: s.start_s,
                end_s: s.end_s,
                steady_s: b - a,
                run_in_s: s.run_in_s.unwrap_or(0.0),
            }),
            (None, None) => {}
        }
    }
    f.coverage = Coverage::of(f.coverage.sliding_s, &rows, dropped);
    if flag && !rows.is_empty() && f.coverage.steady_share() < cfg.min_steady_share {
        for s in f.segments.iter_mut().filter(|s| s.stats.is_some()) {
            s.flags.push(flags::LOW_COVERAGE.to_string());
        }
        f.notes.push(format!(
            "low coverage: the rows rest on {:.0} % of the sliding time (min_steady_share {:.0} %); {}",
            100.0 * f.coverage.steady_share(),
            100.0 * cfg.min_steady_share,
            f.coverage.line()
        ));
    }
}

/// The plan's steps grouped by pin, in run order (a pin's steps are contiguous).
fn pin_groups(expected: &[ExpectedStep]) -> Vec<&[ExpectedStep]> {
    expected.chunk_by(|a, b| a.pin == b.pin).collect()
}

/// Which planned steps each of `runs` sliding runs holds: a pin's steps each when there are
/// as many runs as pins, one step each when there are as many runs as steps, else unknown
/// (`None`: the run is split by the signal alone and aligned afterwards).
fn plan_steps_per_run(
    expected: Option<&[ExpectedStep]>,
    runs: usize,
) -> Vec<Option<&[ExpectedStep]>> {
    let Some(e) = expected else {
        return vec![None; runs];
    };
    let pins = pin_groups(e);
    if pins.len() == runs {
        pins.into_iter().map(Some).collect()
    } else if e.len() == runs {
        e.chunks(1).map(Some).collect()
    } else {
        vec![None; runs]
    }
}

/// Sliding velocities of segments with a spindle speed: v = 2π R n / 60, R from the radius
/// column, the given radii, or the plan.
fn resolve_velocities(files: &mut [FileReport], c: &Campaign) -> Result<()> {
    let total: usize = files
        .iter()
        .map(|f| {
            f.segments
                .iter()
                .filter(|s| s.spindle_rpm.is_some())
                .count()
        })
        .sum();
    let radii = c.track_radius_mm;
    let mut global = 0usize;
    for f in files.iter_mut() {
        let in_file = f
            .segments
            .iter()
            .filter(|s| s.spindle_rpm.is_some())
            .count();
        let mut local = 0usize;
        for s in f.segments.iter_mut() {
            let Some(rpm) = s.spindle_rpm else { continue };
            let r_mm = match radii.len() {
                1 => Some(radii[0]),
                n if n > 1 && n == in_file => Some(radii[local]),
                n if n > 1 && n == total => Some(radii[global]),
                0 => c.plan.and_then(|p| p.spec.track_radius_mm),
                n => {
                    return Err(Error::invalid(
                        "track radius",
                        format!(
                            "{n} track radii given, but {} has {in_file} segments with a spindle speed and the campaign {total}: give one radius, one per segment of each file, or one per segment of the campaign",
                            f.source
                        ),
                    ))
                }
            };
            local += 1;
            global += 1;
            if let Some(r) = r_mm {
                let what = format!("track radius for {} segment {}", f.source, s.index);
                match physics::check(Quantity::TrackRadius, r * units::M_PER_MM, &what) {
                    Err(e) => return Err(Error::invalid("track radius", e)),
                    Ok(Some(flag)) if !f.unusual.contains(&flag.text) => f.unusual.push(flag.text),
                    Ok(_) => {}
                }
            }
            match r_mm {
                Some(r) if r > 0.0 => {
                    s.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(
                        units::velocity_for_rpm(rpm, r * units::M_PER_MM),
                    ))
                }
                _ => {
                    return Err(Error::input(
                        SourcePos::file(&f.source),
                        "the speed channel is a spindle speed (rpm) but no track radius is known: give `track_radii_mm` (one value or one per segment) or map a radius column",
                    ))
                }
            }
        }
    }
    Ok(())
}

/// Match segments to the plan (or number them without one) and build the dataset.
pub fn match_segments(
    files: &mut [FileReport],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    let (ds, report) = match_segments_unchecked(files, c)?;
    check_levels(&ds, files)?;
    check_physics(&ds, files)?;
    Ok((ds, report))
}

/// How far (as a factor) one pin's median μ may lie from the other pins' before its channels
/// are called implausible: friction coefficients of one campaign stay within a factor of a few
/// of each other, a channel read in the wrong unit (kN as N, mN as N) moves them by 1000.
pub const IMPLAUSIBLE_LEVEL_FACTOR: f64 = 20.0;

/// The fastest sliding a measured speed may give a row, m/s: the hard end of
/// [`Quantity::SlidingVelocity`] (12 000 m/min: above the cutting speeds of high-speed
/// machining and any pin-on-disc rig); a faster one is a unit mistake and is refused.
pub const MAX_SLIDING_VELOCITY_M_S: f64 = Quantity::SlidingVelocity.spec().hard.1;

/// Refuse a campaign whose median μ lies outside the possible range of
/// [`Quantity::CampaignMu`], with the numbers and the likely unit slip.
fn check_campaign_level(median_mu: f64, rows: usize, files: &[FileReport]) -> Result<()> {
    let what = format!("{rows} steps");
    let Err(e) = physics::check(Quantity::CampaignMu, median_mu, &what) else {
        return Ok(());
    };
    let hint = if median_mu < *Quantity::CampaignMu.hard().start() {
        "state the unit of the tangential channel: `map` tangential=NAME:kN"
    } else {
        "state the unit of the normal channel: `map` normal=NAME:kN"
    };
    let sources: Vec<&str> = files.iter().map(|f| f.source.as_str()).take(3).collect();
    Err(Error::input(
        SourcePos::file(sources.join(", ")).field("tangential / normal"),
        format!("{e}; {hint}"),
    ))
}

/// The file that holds (pin, step), for messages.
fn source_of(files: &[FileReport], pin: u32, step: Option<u32>) -> Option<usize> {
    files.iter().position(|f| {
        f.segments.iter().any(|s| {
            s.matched
                .is_some_and(|(p, k)| p == pin && step.is_none_or(|st| st == k))
        }) || f
            .rows
            .iter()
            .any(|r| r.pin == pin && step.is_none_or(|st| st == r.step))
    })
}

/// Check every step's μ, load, sliding velocity and pressure against the physics table
/// ([`greybox_core::physics`]): outside the possible range refused, outside the usual range
/// flagged in the file's [`FileReport::unusual`] (one line per quantity and file: the first
/// step's number and hint, and how many more steps).
pub fn check_physics(ds: &FrictionDataset, files: &mut [FileReport]) -> Result<()> {
    // (file, quantity) → first flag and how many
    let mut flagged: Vec<(Option<usize>, Quantity, String, usize)> = Vec::new();
    for r in &ds.records {
        let file = source_of(files, r.pin, Some(r.step));
        let at = format!("pin {} step {}", r.pin, r.step);
        let mut values = vec![
            (Quantity::Mu, r.cof_apparent.abs(), "tangential / normal"),
            (Quantity::NormalForce, r.normal_force_n.abs(), "normal"),
            (
                Quantity::SlidingVelocity,
                r.sliding_velocity_m_s.abs(),
                "speed",
            ),
        ];
        if r.hertz_pressure_pa != 0.0 {
            values.push((Quantity::ContactPressure, r.hertz_pressure_pa, "pressure"));
        }
        for (q, v, field) in values {
            match physics::check(q, v, &at) {
                Ok(None) => {}
                Ok(Some(flag)) => match flagged.iter_mut().find(|e| e.0 == file && e.1 == q) {
                    Some(e) => e.3 += 1,
                    None => flagged.push((file, q, flag.text, 0)),
                },
                Err(e) => {
                    let source = file.map_or_else(|| at.clone(), |f| files[f].source.clone());
                    return Err(Error::input(SourcePos::file(source).field(field), e));
                }
            }
        }
    }
    for (file, _, text, more) in flagged {
        let line = match more {
            0 => text,
            1 => format!("{text} (and 1 more step)"),
            _ => format!("{text} (and {more} more steps)"),
        };
        match file {
            Some(f) => files[f].unusual.push(line),
            None => {
                if let Some(f) = files.first_mut() {
                    f.unusual.push(line)
                }
            }
        }
    }
    Ok(())
}

/// Refuse a pin whose μ level is implausible against its neighbours (at least three pins):
/// its median μ more than [`IMPLAUSIBLE_LEVEL_FACTOR`] from the median of the other pins'.
///
/// Before that, the campaign as a whole: its median μ must lie in the possible range of
/// [`Quantity::CampaignMu`] (a channel
/// in the wrong unit in every pin moves all of them together, where no pin stands out).
pub fn check_levels(ds: &FrictionDataset, files: &[FileReport]) -> Result<()> {
    let median_of = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    if ds.records.is_empty() {
        return Ok(());
    }
    check_campaign_level(
        median_of(ds.records.iter().map(|r| r.cof_apparent.abs()).collect()),
        ds.records.len(),
        files,
    )?;
    let mut pins: Vec<u32> = ds.records.iter().map(|r| r.pin).collect();
    pins.sort_unstable();
    pins.dedup();
    if pins.len() < 3 {
        return Ok(());
    }
    let levels: Vec<(u32, f64)> = pins
        .iter()
        .map(|&p| {
            (
                p,
                median_of(
                    ds.records
                        .iter()
                        .filter(|r| r.pin == p)
                        .map(|r| r.cof_apparent.abs())
                        .collect(),
                ),
            )
        })
        .collect();
    for &(pin, level) in &levels {
        let others = median_of(
            levels
                .iter()
                .filter(|(p, _)| *p != pin)
                .map(|(_, l)| *l)
                .collect(),
        );
        let factor = level.max(1e-12) / others.max(1e-12);
        if !(1.0 / IMPLAUSIBLE_LEVEL_FACTOR..=IMPLAUSIBLE_LEVEL_FACTOR).contains(&factor) {
            let source = files
                .iter()
                .find(|f| {
                    f.segments
                        .iter()
                        .any(|s| s.matched.is_some_and(|(p, _)| p == pin))
                        || f.rows.iter().any(|r| r.pin == pin)
                })
                .map_or_else(|| format!("pin {pin}"), |f| f.source.clone());
            let hint = if factor < 1.0 {
                "is the tangential channel in kN (or the normal one in mN) read as N? state its unit: `map` tangential=NAME:kN"
            } else {
                "is the normal channel in kN (or the tangential one in mN) read as N? state its unit: `map` normal=NAME:kN"
            };
            return Err(Error::input(
                SourcePos::file(source).field("tangential / normal"),
                format!(
                    "pin {pin}'s median μ {level:.4} is {:.0}× {} the other pins' {others:.4}: {hint}",
                    if factor < 1.0 { 1.0 / factor } else { factor },
                    if factor < 1.0 { "below" } else { "above" }
                ),
            ));
        }
    }
    Ok(())
}

fn match_segments_unchecked(
    files: &mut [FileReport],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    if files
        .iter()
        .all(|f| f.segmentation == Segmentation::PlanTiming.name())
    {
        let records = files
            .iter_mut()
            .flat_map(|f| std::mem::take(&mut f.rows))
            .collect();
        return Ok((
            FrictionDataset { records },
            MatchReport {
                method: "plan timing".into(),
                ..Default::default()
            },
        ));
    }
    let segs = measured_segments(files);
    match c.expected {
        None => number_without_plan(files, c),
        Some(expected) => match_to_plan(files, &segs, expected, c),
    }
}

/// Every measured segment as (file, segment) indices, in campaign order.
fn measured_segments(files: &[FileReport]) -> Vec<(usize, usize)> {
    files
        .iter()
        .enumerate()
        .flat_map(|(f, file)| {
            file.segments
                .iter()
                .enumerate()
                .filter(|(_, s)| s.stats.is_some())
                .map(move |(k, _)| (f, k))
        })
        .collect()
}

/// A dataset row from a measured segment (see [`crate::steady::PlateauStats::record`]).
fn segment_record(
    c: &Campaign,
    (pin, step): (u32, u32),
    planned_n: Option<f64>,
    velocity_m_s: f64,
    s: &SegmentReport,
) -> Result<FrictionRecord> {
    let place = crate::steady::PlateauPlace {
        pin,
        step,
        planned_n,
        velocity_m_s,
        flags: s.flags.clone(),
    };
    s.stats.as_ref().expect("measured").record(c.contact, place)
}

/// Without a plan: pins and steps numbered from the recordings (a new pin where the load
/// changes by more than 10 % or a new multi-step file starts); speeds must be measured.
fn number_without_plan(
    files: &mut [FileReport],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    let mut records = Vec::new();
    let (mut pin, mut step) = (0u32, 0u32);
    let mut prev: Option<(usize, f64)> = None; // file, load
    let mut prev_label: Option<f64> = None; // the recording's own step number (step column, block)
    let mut pending: Vec<(usize, String)> = Vec::new(); // dropped steps whose number is kept
                                                        // a dropped segment keeps its place: the steps after it keep their numbers
    let all: Vec<(usize, usize)> = files
        .iter()
        .enumerate()
        .flat_map(|(f, file)| (0..file.segments.len()).map(move |k| (f, k)))
        .collect();
    for &(f, k) in &all {
        let s = &files[f].segments[k];
        if s.stats.is_none() {
            if s.problem.is_none() || !(s.normal_force_n > 0.0) {
                continue;
            }
            let same_pin = prev
                .is_some_and(|(pf, load)| pf == f && (s.normal_force_n / load - 1.0).abs() <= 0.1);
            if !same_pin {
                pin += 1;
                step = 0;
                // the dropped segments at the end of a pin shift no number: their dropped
                // notes say enough
                pending.clear();
            } else {
                step += labels_skipped(prev_label, s.step_label);
            }
            step += 1;
            prev = Some((f, s.normal_force_n));
            prev_label = s.step_label;
            let note = format!(
                "segment {} ({:.3}–{:.3} s) is pin {pin} step {step} but gave no row ({}): the step is left empty, the steps after it keep their numbers",
                s.index,
                s.start_s,
                s.end_s,
                s.problem.as_deref().unwrap_or_default()
            );
            pending.push((f, note));
            continue;
        }
        if let Some(v) = s
            .sliding_velocity_m_per_min
            .filter(|v| !(v.abs() <= units::m_per_s_to_m_per_min(MAX_SLIDING_VELOCITY_M_S)))
        {
            return Err(Error::input(
                SourcePos::file(&files[f].source).field("speed"),
                format!(
                    "segment {} ({:.3}–{:.3} s): a sliding velocity of {v:.4e} m/min is beyond any tribometer or cut (at most {:.0} m/min): is the speed channel's unit right (rpm against m/s, mm/s against m/s)?",
                    s.index,
                    s.start_s,
                    s.end_s,
                    units::m_per_s_to_m_per_min(MAX_SLIDING_VELOCITY_M_S)
                ),
            ));
        }
        let Some(v) = s.sliding_velocity_m_per_min else {
            return Err(Error::input(
                SourcePos::file(&files[f].source),
                "without a plan the sliding velocity must come from the recording: map a speed channel (`map` speed=NAME:UNIT, with `track_radii_mm` for rpm), state a constant one (`constant_sliding_velocity_m_per_s`) or give a plan (`study` or `plan_steps`)",
            ));
        };
        let single = |ff: usize| {
            files[ff]
                .segments
                .iter()
                .filter(|s| s.stats.is_some())
                .count()
                == 1
        };
        let new_pin = match prev {
            None => true,
            Some((pf, load)) => {
                let load_changed = (s.normal_force_n / load - 1.0).abs() > 0.1;
                let new_file = pf != f && !(single(pf) && single(f));
                load_changed || new_file
            }
        };
        let skipped = if new_pin {
            pin += 1;
            step = 0;
            pending.clear();
            0
        } else {
            labels_skipped(prev_label, s.step_label)
        };
        // a dropped step before this one in the pin: its number stays taken, and says so
        let kept = std::mem::take(&mut pending);
        step += 1 + skipped;
        prev = Some((f, s.normal_force_n));
        prev_label = s.step_label;
        if skipped > 0 {
            let note = format!(
                "the recording's steps jump from {} to {}: pin {pin} steps {}–{} have no segment and are left empty, the steps after them keep their numbers",
                prev_label.unwrap_or_default() - skipped as f64 - 1.0,
                prev_label.unwrap_or_default(),
                step - skipped,
                step - 1
            );
            files[f].warnings.push(note);
        }
        for (pf, note) in kept {
            files[pf].warnings.push(note);
        }
        files[f].segments[k].matched = Some((pin, step));
        let s = &files[f].segments[k];
        records.push(segment_record(
            c,
            (pin, step),
            None,
            units::m_per_min_to_m_per_s(v),
            s,
        )?);
    }
    let report = MatchReport {
        method: "none".into(),
        ..Default::default()
    };
    Ok((FrictionDataset { records }, report))
}

/// Steps the recording's own numbering (a step column, blocks) skips between two segments of
/// one pin: `prev` 2 and `label` 4 skip one. Only whole, increasing numbers count.
fn labels_skipped(prev: Option<f64>, label: Option<f64>) -> u32 {
    match (prev, label) {
        (Some(a), Some(b))
            if a.fract() == 0.0 && b.fract() == 0.0 && b > a + 1.0 && b - a < 1e4 =>
        {
            (b - a - 1.0) as u32
        }
        _ => 0,
    }
}

/// "pin P step S (F N, v m/min)" for reports.
fn describe_step(e: &ExpectedStep) -> String {
    format!(
        "pin {} step {} ({:.1} N, {:.1} m/min)",
        e.pin,
        e.step,
        e.normal_force_n,
        units::m_per_s_to_m_per_min(e.sliding_velocity_m_s)
    )
}

/// With a plan: segments aligned with the planned steps ([`crate::align`]), then rows for
/// the matched ones and a report of the missing, extra, merged and reordered steps.
fn match_to_plan(
    files: &mut [FileReport],
    segs: &[(usize, usize)],
    expected: &[ExpectedStep],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    let candidates: Vec<Candidate> = segs
        .iter()
        .enumerate()
        .map(|(si, &(f, k))| {
            let s = &files[f].segments[k];
            Candidate {
                file: f,
                load_n: s.normal_force_n,
                // a stated constant speed is no evidence of which step a segment is
                velocity_m_s: s
                    .sliding_velocity_m_per_min
                    .filter(|_| files[f].sliding == SlidingEvidence::SpeedChannel.name())
                    .map(units::m_per_min_to_m_per_s),
                duration_s: s.end_s - s.start_s,
                first_in_file: si == 0 || segs[si - 1].0 != f,
                running_in: s.run_in_s.is_some_and(|r| r > 0.0)
                    || s.flags.iter().any(|x| x == flags::TREND),
            }
        })
        .collect();
    let aligned = crate::align::align(&candidates, expected, c.cfg)
        .map_err(|m| Error::invalid("identify", m))?;
    let mut report = MatchReport {
        method: alignment_method(&candidates, expected),
        ..Default::default()
    };
    let given: Vec<usize> = {
        let mut v: Vec<usize> = segs.iter().map(|s| s.0).collect();
        v.dedup();
        v
    };
    if aligned.file_order != given {
        report.reordered.push(format!(
            "the files were aligned with the plan in the order {}",
            aligned
                .file_order
                .iter()
                .map(|f| files[*f].source.clone())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let mut records = Vec::new();
    let mut matched = vec![false; expected.len()];
    let mut last_ei: Option<usize> = None;
    for (si, &(f, k)) in segs.iter().enumerate() {
        let ei = match aligned.assigned[si] {
            Assigned::Step(ei) => ei,
            Assigned::Merged { earlier, later } => {
                matched[earlier] = true;
                let s = &files[f].segments[k];
                report.merged.push(format!(
                    "{} merged with the next step into {} segment {} ({:.3}–{:.3} s): the row is the later step's",
                    describe_step(&expected[earlier]),
                    files[f].source,
                    s.index,
                    s.start_s,
                    s.end_s
                ));
                later
            }
            Assigned::Extra => {
                let (file, s) = (&files[f], &files[f].segments[k]);
                let v = s
                    .sliding_velocity_m_per_min
                    .map_or(String::new(), |v| format!(", {v:.1} m/min"));
                report.extra.push(format!(
                    "{} segment {} ({:.3}–{:.3} s, {:.1} s) at {:.1} N{v}: no planned step fits (an unplanned run-in or repeat?)",
                    file.source,
                    s.index,
                    s.start_s,
                    s.end_s,
                    s.end_s - s.start_s,
                    s.normal_force_n
                ));
                continue;
            }
        };
        matched[ei] = true;
        let e = &expected[ei];
        if let Some(prev) = last_ei.filter(|p| ei < *p) {
            report.reordered.push(format!(
                "{} recorded after {}",
                describe_step(e),
                describe_step(&expected[prev])
            ));
        }
        last_ei = Some(last_ei.map_or(ei, |p| p.max(ei)));
        files[f].segments[k].matched = Some((e.pin, e.step));
        let s = &files[f].segments[k];
        records.push(segment_record(
            c,
            (e.pin, e.step),
            Some(e.normal_force_n),
            e.sliding_velocity_m_s,
            s,
        )?);
    }
    for (ei, e) in expected.iter().enumerate() {
        if !matched[ei] {
            report.missing.push(describe_step(e));
        }
    }
    for f in files.iter_mut() {
        update_coverage(f, c.cfg, false);
    }
    records.sort_by_key(|r| (r.pin, r.step));
    Ok((FrictionDataset { records }, report))
}

/// `alignment by load, speed and duration`: the evidence the segments and the plan share.
fn alignment_method(segs: &[Candidate], expected: &[ExpectedStep]) -> String {
    let mut by = vec!["load"];
    if !segs.is_empty() && segs.iter().all(|s| s.velocity_m_s.is_some()) {
        by.push("speed");
    }
    if expected.iter().all(|e| e.duration_s.is_some()) {
        by.push("duration");
    }
    let last = by.pop().expect("load");
    if by.is_empty() {
        format!("alignment by {last}")
    } else {
        format!("alignment by {} and {last}", by.join(", "))
    }
}

/// The greybox NC-program path: one recording per pin, the plan's timing from the trigger.
fn plan_timed(recs: &[Recording], plan: &Plan, c: &Campaign) -> Result<Vec<FileReport>> {
    if recs.len() != plan.pins.len() {
        return Err(Error::invalid(
            "identify",
            format!(
                "the plan has {} pins but {} recordings were given (plan-timing needs one recording per pin, in pin order)",
                plan.pins.len(),
                recs.len()
            ),
        ));
    }
    let mut files = Vec::with_capacity(recs.len());
    for (k, rec) in recs.iter().enumerate() {
        let (rows, d) = identify_pin(rec, plan, k as u32 + 1, c.contact, c.cfg)?;
        let ts = d.trigger_s + d.latency_s;
        let segments = rows
            .iter()
            .enumerate()
            .map(|(i, r)| SegmentReport {
                index: i + 1,
                start_s: ts + plan.pin_steps(r.pin)[i].step_start_s,
                end_s: ts + plan.pin_steps(r.pin)[i].plateau_end_s,
                steady_start_s: Some(ts + r.plateau_start_s),
                steady_end_s: Some(ts + r.plateau_end_s),
                normal_force_n: r.normal_force_n,
                spindle_rpm: None,
                sliding_velocity_m_per_min: Some(units::m_per_s_to_m_per_min(
                    r.sliding_velocity_m_s,
                )),
                step_label: None,
                cof: Some(r.cof_apparent),
                cof_std: Some(r.cof_apparent_std),
                cof_sem: None,
                n_samples: r.n_samples as usize,
                flags: r.flags.clone(),
                matched: Some((r.pin, r.step)),
                problem: None,
                run_in_s: None,
                drift_per_hour: Some(r.cof_trend_per_s * 3600.0),
                drift_per_km: None,
                boundary_uncertainty_s: None,
                reciprocating: None,
                stats: None,
            })
            .collect();
        files.push(FileReport {
            source: rec.source.clone(),
            read: rec.provenance.clone(),
            warnings: read_warnings(rec),
            sample_rate_hz: rec.sample_rate_hz(),
            samples: rec.len(),
            duration_s: rec.duration_s(),
            segmentation: Segmentation::PlanTiming.name().into(),
            baseline: "start and end".into(),
            drift_normal_n: d.drift_normal_n,
            drift_tangential_n: d.drift_tangential_n,
            tangential_sign_flipped: false,
            normal_sign_flipped: false,
            sliding: "plan timing".into(),
            period_s: None,
            coverage: Coverage::default(),
            segments,
            notes: vec![format!(
                "trigger at {:.4} s, NC-to-spindle latency {:.4} s, {} spikes removed",
                d.trigger_s, d.latency_s, d.spikes_removed
            )],
            unusual: Vec::new(),
            rows,
            too_short: Vec::new(),
        });
    }
    for f in files.iter_mut() {
        // the plan's steps are the sliding time
        f.coverage.sliding_s = f.segments.iter().map(|s| s.end_s - s.start_s).sum();
        update_coverage(f, c.cfg, true);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn least_squares_split_finds_level_changes() {
        let mut x = vec![0.40; 30];
        x.extend(vec![0.38; 20]);
        x.extend(vec![0.35; 25]);
        // a run-in at the very start must not take a boundary when lengths are bounded
        for (k, v) in x.iter_mut().take(4).enumerate() {
            *v += 0.1 * (-(k as f64)).exp();
        }
        let b = split_into(&x, 3, 10).unwrap();
        assert_eq!(b, vec![30, 50]);
        let b = split_penalised(&x[4..], 3);
        assert_eq!(b, vec![26, 46]);
    }

    #[test]
    fn runs_of_true() {
        assert_eq!(
            runs(&[false, true, true, false, true]),
            vec![(1, 3), (4, 5)]
        );
        assert!(runs(&[false, false]).is_empty());
    }
}
