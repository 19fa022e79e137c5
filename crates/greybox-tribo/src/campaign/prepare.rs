//! Per-file preparation: loaded samples, baseline offsets, sign of the forces and the sliding mask
//! (steps 1–3 of the campaign), and the sample [`Span`]s the segmenters cut.

use super::report::{read_warnings, FileReport, SegmentReport};
use super::reversals::Passes;
use super::span::Span;
use crate::config::IdentifyConfig;
use crate::coverage::Coverage;
use crate::signal::{block_medians, runs};
use crate::sliding::quantile;
use greybox_core::stats::median;
use greybox_core::{Error, Result, SourcePos};
use greybox_recording::Recording;

/// Per-file signals after baseline and sign correction.
pub(super) struct Prepared<'a> {
    pub(super) rec: &'a Recording,
    pub(super) fn_c: Vec<f64>,
    pub(super) ft_c: Vec<f64>,
    pub(super) fs: f64,
    /// Loaded and sliding per sample.
    pub(super) sliding: Vec<bool>,
    /// The rig's period in μ, s (revolution or stroke), if one was found.
    pub(super) period_s: Option<f64>,
    /// Time above the loaded threshold, s.
    pub(super) loaded_s: f64,
    /// Standard errors of the removed offsets of the normal and the tangential force, N
    /// ([`Baseline::offset_se`]): an error common to every sample of a window, which its
    /// own statistics cannot see.
    pub(super) baseline_se: ((f64, f64), (f64, f64)),
    /// Mid times of the start and end windows, s (where both are; see [`Baseline::mids`]).
    pub(super) baseline_mid_s: Option<(f64, f64)>,
    /// Where the sliding direction reverses ([`Passes`]); empty for a test in one direction.
    pub(super) passes: Passes,
    pub(super) report: FileReport,
}

impl Prepared<'_> {
    /// Standard errors of the normal and tangential offsets removed at time `t`, N: a line
    /// through the two windows' medians has (1 − λ)²·σ²_start + λ²·σ²_end at λ = the
    /// fraction of the way from the start window to the end window; one window's error
    /// where there is one.
    pub(super) fn offset_se_at(&self, t: f64) -> (f64, f64) {
        let ((na, ne), (ta, te)) = self.baseline_se;
        match self.baseline_mid_s {
            Some((a, e)) if e > a => {
                let l = ((t - a) / (e - a)).clamp(0.0, 1.0);
                let at = |s0: f64, s1: f64| ((1.0 - l) * s0).hypot(l * s1);
                (at(na, ne), at(ta, te))
            }
            _ => (na.max(ne), ta.max(te)),
        }
    }

    /// The baseline's standard errors as they enter a window at time `t`: of the normal
    /// offset there, N, and of the tangential windows' medians at the start and the end, N,
    /// with the fraction λ of the way from the start window to the end window (`None`: one
    /// window or none, a constant offset).
    pub(super) fn offset_parts_at(&self, t: f64) -> (f64, (f64, f64, Option<f64>)) {
        let (_, (ta, te)) = self.baseline_se;
        let lambda = self
            .baseline_mid_s
            .filter(|(a, e)| e > a)
            .map(|(a, e)| ((t - a) / (e - a)).clamp(0.0, 1.0));
        (self.offset_se_at(t).0, (ta, te, lambda))
    }

    /// Shortest step, s: `min_segment_s`, or three of the rig's periods if longer.
    pub(super) fn min_step_s(&self, cfg: &IdentifyConfig) -> f64 {
        cfg.min_segment_s.max(3.0 * self.period_s.unwrap_or(0.0))
    }

    /// Samples per block of the change-point search: 50 ms, or one period if longer (each
    /// block then averages whole revolutions).
    pub(super) fn step_block(&self) -> usize {
        ((0.05f64.max(self.period_s.unwrap_or(0.0)) * self.fs).round() as usize).max(1)
    }
}

impl SegmentReport {
    /// A segment's bounds, mean load and label; nothing measured yet.
    pub(super) fn bare(p: &Prepared, span: Span, index: usize) -> Self {
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
            boundaries: span.cut.name(),
            cof: None,
            cof_std: None,
            cof_sem: None,
            cof_ci95: None,
            cof_n_eff: None,
            n_samples: 0,
            masked_samples: 0,
            label_evidence: None,
            flags: Vec::new(),
            matched: None,
            problem: None,
            run_in_s: None,
            unsettled: None,
            never_settles: false,
            drift_per_hour: None,
            drift_per_km: None,
            boundary_uncertainty_s: None,
            contradiction: None,
            direction: p.passes.direction_name(span.pass),
            passes: None,
            reciprocating: None,
            stats: None,
        }
    }
}

/// Prepare one recording (steps 1–3 of the campaign): loaded samples, baseline offsets
/// removed, the signs of the forces, the sliding mask; `signed`: a reciprocating test,
/// whose friction force changes sign by design.
pub(super) fn prepare<'a>(
    rec: &'a Recording,
    cfg: &IdentifyConfig,
    segmentation: &str,
    signed: bool,
) -> Result<Prepared<'a>> {
    rec.validate()?;
    let n = rec.len();
    let fs = rec.sample_rate_hz();
    let b = ((0.01 * fs).round() as usize).clamp(1, (n / 20).max(1));
    let load = Loading::of(rec, cfg, b)?;
    let base = Baseline::of(rec, &load.loaded, fs);
    let (off_n, slope_n, t_n) = base.line(&load.normal);
    let (off_t, slope_t, t_t) = base.line(&rec.tangential_n);
    let fn_c = remove_line(&rec.time_s, &load.normal, (off_n, slope_n, t_n));
    let mut ft_c = remove_line(&rec.time_s, &rec.tangential_n, (off_t, slope_t, t_t));
    let baseline = base.name();
    let baseline_se = (
        base.offset_se(&load.normal),
        base.offset_se(&rec.tangential_n),
    );
    let baseline_mid_s = base.mids();
    let span = rec.duration_s();
    let mut notes = Vec::new();
    let blocks = crate::sliding::Blocks {
        b,
        loaded: &load.loaded_blocks,
        fs,
    };
    let slide = crate::sliding::sliding(rec.speed.as_ref(), &fn_c, &ft_c, &blocks, cfg);
    // a reciprocating test's friction force changes sign by design: kept as recorded
    let passes = if signed {
        Passes::default()
    } else {
        Passes::of(&slide.direction)
    };
    let flipped = !signed && passes.orient(&slide.direction, &mut ft_c);
    if flipped {
        notes.push(
            "the friction force of the first sliding pass is negative as recorded: its sign was flipped".to_string(),
        );
    }
    if load.normal_flipped {
        notes.push("the normal force is negative while loaded (compression read as a negative force): its sign was flipped".to_string());
    }
    notes.extend(sliding_notes(&slide, cfg));
    notes.extend(passes.note(&rec.time_s));
    let sliding_s = slide.mask.iter().filter(|m| **m).count() as f64 / fs;
    let mut warnings = read_warnings(rec);
    if baseline == "none" {
        // a file-wide fact, not a row's: one warning in every run's summary
        warnings.push(
            "no unloaded window at the start or end: the force channels' offsets cannot be removed; μ includes any offset of the tangential channel divided by the load".to_string(),
        );
    }
    Ok(Prepared {
        rec,
        fn_c,
        ft_c,
        fs,
        sliding: slide.mask,
        period_s: slide.period_s,
        loaded_s: load.loaded.iter().filter(|l| **l).count() as f64 / fs,
        baseline_se,
        baseline_mid_s,
        passes,
        report: FileReport {
            source: rec.source.clone(),
            read: rec.provenance.clone(),
            warnings,
            sample_rate_hz: fs,
            samples: n,
            duration_s: span,
            segmentation: segmentation.to_string(),
            baseline: baseline.to_string(),
            drift_normal_n: slope_n * span,
            drift_tangential_n: slope_t * span,
            tangential_sign_flipped: flipped,
            normal_sign_flipped: load.normal_flipped,
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

/// Which samples are loaded (step 1): the block medians (`b` samples) of the normal force
/// above the unloaded level plus `loaded_fraction` of the loaded range.
struct Loading<'a> {
    /// The normal force, made positive (flipped where the loaded level is negative).
    normal: std::borrow::Cow<'a, [f64]>,
    normal_flipped: bool,
    loaded_blocks: Vec<bool>,
    /// Per sample.
    loaded: Vec<bool>,
}

impl<'a> Loading<'a> {
    /// Loaded blocks from the two levels of the normal force's block medians
    /// ([`crate::signal::two_levels`]): the loaded level is the one farther from zero (a
    /// load cell reading compression as negative has it below: the channel is flipped); a
    /// block is loaded above the unloaded level plus the larger of `loaded_fraction` of the
    /// gap between the levels and five robust spreads of the unloaded level (its noise and
    /// drifting offset). Without an unloaded level (the lower one not below 20 % of the
    /// loaded, or under 1 % of the blocks) zero is the unloaded level.
    fn of(rec: &'a Recording, cfg: &IdentifyConfig, b: usize) -> Result<Self> {
        let n = rec.len();
        let bn = block_medians(&rec.normal_n, b);
        let (lo, hi) = (quantile(&bn, 0.01), quantile(&bn, 0.99));
        let none = || {
            Error::input(
                SourcePos::file(&rec.source).field("normal"),
                format!("the normal force never departs from zero (1st and 99th percentiles {lo:.3} and {hi:.3} N): check the channel mapping"),
            )
        };
        let levels = levels_of(&bn).ok_or_else(none)?;
        // the loaded level is the one farther from zero; below zero: compression read negative
        let normal_flipped = levels.low.abs() > levels.high.abs() && levels.low < 0.0;
        let (normal, bn, levels) = if normal_flipped {
            let flipped: Vec<f64> = rec.normal_n.iter().map(|v| -v).collect();
            let bn: Vec<f64> = bn.iter().map(|v| -v).collect();
            let levels = levels_of(&bn).ok_or_else(none)?;
            (std::borrow::Cow::Owned(flipped), bn, levels)
        } else {
            (std::borrow::Cow::Borrowed(&rec.normal_n[..]), bn, levels)
        };
        if !(levels.high > 0.0) {
            return Err(none());
        }
        let has_unloaded = levels.low < 0.2 * levels.high && levels.low_share >= 0.01;
        let (unloaded, spread) = if has_unloaded {
            (levels.low, levels.low_sigma)
        } else {
            (0.0, 0.0)
        };
        let thr = unloaded + (cfg.loaded_fraction * (levels.high - unloaded)).max(5.0 * spread);
        let mut loaded_blocks: Vec<bool> = bn.iter().map(|v| *v > thr).collect();
        // a blip (a noise spike while unloaded, a dip to or below zero while loaded) is no
        // change of state: runs shorter than 50 ms (and 5 blocks) take their neighbours' state
        let fs = rec.sample_rate_hz();
        let min_blocks = ((0.05 * fs / b as f64).ceil() as usize).max(5);
        drop_short_runs(&mut loaded_blocks, min_blocks);
        let loaded: Vec<bool> = (0..n).map(|k| loaded_blocks[k / b]).collect();
        Ok(Loading {
            normal,
            normal_flipped,
            loaded_blocks,
            loaded,
        })
    }
}

/// The two levels of the normal force's block medians ([`crate::signal::two_levels`]), or
/// one level for a constant force (a rig that logs its set load): no unloaded level.
fn levels_of(bn: &[f64]) -> Option<crate::signal::TwoLevels> {
    crate::signal::two_levels(bn).or_else(|| {
        let m = median(bn);
        (m != 0.0 && m.is_finite()).then_some(crate::signal::TwoLevels {
            low: m.min(0.0),
            high: m.max(0.0),
            split: 0.5 * m,
            low_sigma: 0.0,
            high_sigma: 0.0,
            low_share: if m < 0.0 { 1.0 } else { 0.0 },
        })
    })
}

/// Runs of either state shorter than `min` blocks flipped to their surroundings': first
/// the short loaded runs (noise spikes), then the short unloaded gaps (dips inside a load).
fn drop_short_runs(mask: &mut [bool], min: usize) {
    for state in [true, false] {
        let flipped: Vec<bool> = mask.iter().map(|m| *m == state).collect();
        for (a, e) in runs(&flipped) {
            // a run at the recording's very start or end is kept: it has one neighbour only
            if e - a < min && a > 0 && e < mask.len() {
                mask[a..e].iter_mut().for_each(|m| *m = !state);
            }
        }
    }
}

/// The unloaded windows at the start and the end of a recording (step 2), sample ranges:
/// the first 80 % of a leading unloaded run, the last 80 % of a trailing one (each at least
/// 50 ms, or 5 samples).
struct Baseline<'r> {
    rec: &'r Recording,
    start: Option<(usize, usize)>,
    end: Option<(usize, usize)>,
}

impl<'r> Baseline<'r> {
    fn of(rec: &'r Recording, loaded: &[bool], fs: f64) -> Self {
        let n = rec.len();
        let unloaded = runs(&loaded.iter().map(|l| !l).collect::<Vec<_>>());
        let min_len = ((0.05 * fs) as usize).max(5);
        let start = unloaded
            .first()
            .filter(|(s, e)| *s == 0 && e - s >= min_len)
            .map(|&(s, e)| (s, s + (e - s) * 8 / 10));
        let end = unloaded
            .last()
            .filter(|(s, e)| *e == n && e - s >= min_len && Some(&(*s, *e)) != unloaded.first())
            .map(|&(s, e)| (s + (e - s) * 2 / 10, e));
        Baseline { rec, start, end }
    }

    /// A channel's baseline as (offset at `t0`, slope per s, `t0`): the line through the
    /// medians of both windows, or one window's constant level, or zero without a window.
    fn line(&self, x: &[f64]) -> (f64, f64, f64) {
        let level = |w: (usize, usize)| median(&x[w.0..w.1]);
        let mid = |w: (usize, usize)| 0.5 * (self.rec.time_s[w.0] + self.rec.time_s[w.1 - 1]);
        match (self.start, self.end) {
            (Some(a), Some(e)) => {
                let (la, le) = (level(a), level(e));
                (la, (le - la) / (mid(e) - mid(a)), mid(a))
            }
            (Some(a), None) => (level(a), 0.0, 0.0),
            (None, Some(e)) => (level(e), 0.0, 0.0),
            (None, None) => (0.0, 0.0, 0.0),
        }
    }

    /// Standard errors of a channel's window medians at the start and the end, N: √(π/2)
    /// times the robust (MAD) standard deviation over the square root of the window's
    /// effective sample size under serial correlation ([`crate::uncertainty::WindowMean`];
    /// the median's error, robust to heavy tails); 0 for a window that is not there.
    fn offset_se(&self, x: &[f64]) -> (f64, f64) {
        let se = |w: (usize, usize)| {
            let v = &x[w.0..w.1];
            crate::uncertainty::WindowMean::of(v).map_or(0.0, |m| {
                (std::f64::consts::PI / 2.0).sqrt() * crate::signal::mad_sigma(v, median(v))
                    / m.n_eff.sqrt()
            })
        };
        (self.start.map_or(0.0, se), self.end.map_or(0.0, se))
    }

    /// Mid times of the start and end windows, s, when both are there.
    fn mids(&self) -> Option<(f64, f64)> {
        let mid = |w: (usize, usize)| 0.5 * (self.rec.time_s[w.0] + self.rec.time_s[w.1 - 1]);
        Some((mid(self.start?), mid(self.end?)))
    }

    /// `start and end`, `start only`, `end only` or `none` (for the file's report).
    fn name(&self) -> &'static str {
        match (self.start, self.end) {
            (Some(_), Some(_)) => "start and end",
            (Some(_), None) => "start only",
            (None, Some(_)) => "end only",
            (None, None) => "none",
        }
    }
}

/// `x` less its baseline line `(offset at t0, slope, t0)` at each sample time.
fn remove_line(time_s: &[f64], x: &[f64], (off, slope, t0): (f64, f64, f64)) -> Vec<f64> {
    time_s
        .iter()
        .zip(x)
        .map(|(t, v)| v - off - slope * (t - t0))
        .collect()
}

/// The notes on how sliding was told apart: μ's threshold (no speed channel) and the rig's
/// period, when found.
fn sliding_notes(slide: &crate::sliding::Sliding, cfg: &IdentifyConfig) -> Vec<String> {
    let mut notes = Vec::new();
    if let Some(thr) = slide.rest_threshold_n {
        notes.push(format!(
            "sliding where |F_t|, its running median over {:.3} s, stands out of its noise at rest ({thr:.4} N, the median threshold; no measured speed channel)",
            cfg.sliding_smoothing_s.max(slide.period_s.unwrap_or(0.0))
        ));
    }
    if let Some(per) = slide.period_s {
        notes.push(format!(
            "μ repeats every {per:.3} s (the rig's revolution or stroke): averaged over it"
        ));
    }
    notes
}
