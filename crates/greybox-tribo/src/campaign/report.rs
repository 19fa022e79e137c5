//! Reports of an identification: per segment, per file, of the plan matching; the campaign's
//! inputs; a file's coverage from its segments; a segment's dataset row.

use crate::config::IdentifyConfig;
use crate::coverage::{Coverage, Dropped, SegmentTime};
use crate::expected::ExpectedStep;
use crate::plan::Plan;
use crate::reciprocating::Reciprocating;
use crate::steady_window::PlateauStats;
use greybox_contact::hertz::PinContact;
use greybox_core::dataset::{flags, FrictionDataset, FrictionRecord};
use greybox_core::Result;
use greybox_recording::{ReadReport, Recording};
use serde::Serialize;

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
    /// What cut the segment's boundaries: `step column`, `speed channel`, `plan timing`,
    /// `level change of μ` or `sliding run`.
    pub boundaries: &'static str,
    pub cof: Option<f64>,
    pub cof_std: Option<f64>,
    /// Standard error of μ's mean under serial correlation
    /// ([`crate::uncertainty::WindowMean`]).
    pub cof_sem: Option<f64>,
    /// Half-width of μ's 95 % confidence interval: Student's t at the effective sample size
    /// times `cof_sem`, plus μ's change when the window's ends move by their boundary's
    /// uncertainty (the dataset's `cof_apparent_ci95`).
    pub cof_ci95: Option<f64>,
    /// Effective number of independent samples behind μ (samples / integrated
    /// autocorrelation time).
    pub cof_n_eff: Option<f64>,
    pub n_samples: usize,
    /// Samples of the steady window masked as spikes (Hampel), not averaged.
    pub masked_samples: usize,
    /// What placed the segment on its plan step (`step-column`, `plan-timing`,
    /// `measured-speed`, `measured-load`, `duration`, `order`; see
    /// [`greybox_core::dataset::label_evidence`]); `None` before matching or when unmatched.
    pub label_evidence: Option<String>,
    pub flags: Vec<String>,
    /// Plan pin and step it was matched to.
    pub matched: Option<(u32, u32)>,
    /// Why this segment gave no row.
    pub problem: Option<String>,
    /// Run-in before the steady part, s from the segment start: the time until μ's running
    /// level enters, and stays in, the final stretch's band (ASTM G99-17 §9; `auto` rule only).
    pub run_in_s: Option<f64>,
    /// Why the steady window is not a settled steady state, where it is not: μ never settles
    /// (the mean after the warm-up, with its trend), or too few cycles to tell (see
    /// [`crate::steady_window::steady_stretch`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsettled: Option<String>,
    /// μ never settles in the window: the coverage counts it as unsettled, not steady.
    #[serde(skip)]
    pub(super) never_settles: bool,
    /// Slope of μ over the steady part, 1/h (a slow drift is reported, not cut away).
    pub drift_per_hour: Option<f64>,
    /// Slope of μ over the steady part per sliding distance, 1/km (when the speed is known).
    pub drift_per_km: Option<f64>,
    /// What the segment's own signal says against its cut (`label-contradicted`): two
    /// levels of μ inside it, with where they change.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contradiction: Option<String>,
    /// Uncertainty of the segment's boundaries where one is weakly determined, s (the larger
    /// of the two; rows then carry `uncertain-boundary`).
    pub boundary_uncertainty_s: Option<f64>,
    /// The direction of a test whose sliding reverses (`forward`: the first pass's, `reverse`,
    /// or `both`: a forward and a reverse pass, μ their mean; see [`super::passes`]); absent
    /// for a test in one direction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub direction: Option<&'static str>,
    /// Both directions' means and intervals of a `both` segment.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub passes: Option<PassPair>,
    /// A reciprocating test's strokes, cycles and μ per direction (ASTM G133; see
    /// [`crate::reciprocating`]); the row's μ is their mean over the steady cycles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reciprocating: Option<Reciprocating>,
    #[serde(skip)]
    pub(super) stats: Option<crate::steady_window::PlateauStats>,
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
    pub(super) rows: Vec<FrictionRecord>,
    /// Sliding spans left out before measuring (shorter than a step may be).
    #[serde(skip)]
    pub(super) too_short: Vec<Dropped>,
}

impl FileReport {
    /// Every segment, one line each: its span, its steady window and μ with its 95 %
    /// interval, and the planned step it was matched to or why it gave no row. A refusal
    /// lists them all beside the coverage line, so that it says what `--inspect` shows.
    pub fn segment_lines(&self) -> Vec<String> {
        self.segments
            .iter()
            .map(|s| {
                let steady = match (s.steady_start_s.zip(s.steady_end_s), s.cof) {
                    (Some((a, b)), Some(m)) => format!(
                        "steady {a:.3}–{b:.3} s, μ {m:.4} ± {:.4}",
                        s.cof_ci95.unwrap_or(f64::NAN)
                    ),
                    _ => "no steady window".to_string(),
                };
                let fate = match (&s.problem, s.matched) {
                    (Some(p), _) => format!("no row: {p}"),
                    (None, Some((pin, step))) => format!("pin {pin} step {step}"),
                    (None, None) if s.cof.is_some() => "no row: matched to no planned step".into(),
                    (None, None) => "no row".into(),
                };
                format!(
                    "segment {} {:.3}–{:.3} s: {steady}; {fate}",
                    s.index, s.start_s, s.end_s
                )
            })
            .collect()
    }
}

/// The reader's summary lines of a recording ([`ReadReport::warnings`]).
pub(super) fn read_warnings(rec: &Recording) -> Vec<String> {
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
    /// Rows whose step rests on the order of the segments alone (flag `label-by-order`).
    pub labels_by_order: usize,
    /// Segments another alignment nearly as good places elsewhere (flag
    /// `ambiguous-alignment`), one line each.
    pub ambiguous: Vec<String>,
}

/// The result of identifying a set of recordings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Identification {
    #[serde(skip)]
    pub dataset: FrictionDataset,
    pub files: Vec<FileReport>,
    pub matching: MatchReport,
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

/// A file's coverage from its segments' state: rows from the measured (and, once matched,
/// the matched) segments, dropped parts with reasons. Before matching (`flag`), a file
/// whose steady share is below `min_steady_share` flags its measured segments
/// `low-coverage`.
pub(super) fn update_coverage(f: &mut FileReport, cfg: &IdentifyConfig, flag: bool) {
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
                steady_s: s.passes.as_ref().map_or(b - a, |p| {
                    (p.forward.steady_end_s - p.forward.steady_start_s)
                        + (p.backward.steady_end_s - p.backward.steady_start_s)
                }),
                run_in_s: s.run_in_s.unwrap_or(0.0),
                unsettled: s.never_settles,
                masked_s: s.masked_samples as f64 / f.sample_rate_hz,
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

/// After matching, a file whose matched rows rest on less than `min_steady_share` of its
/// sliding time (segments left unmatched are dropped time now) flags those rows
/// `low-coverage`, in its segments and in `records`, where they are not flagged yet, and its
/// notes say so (as before matching).
pub(super) fn flag_low_coverage_after_matching(
    files: &mut [FileReport],
    records: &mut [FrictionRecord],
    cfg: &IdentifyConfig,
) {
    for f in files.iter_mut() {
        if f.coverage.steady_share() >= cfg.min_steady_share {
            continue;
        }
        let flagged_before = f.notes.iter().any(|n| n.starts_with("low coverage"));
        let mut flagged = 0;
        for s in f.segments.iter_mut() {
            let Some((pin, step)) = s.matched else {
                continue;
            };
            if s.flags.iter().any(|x| x == flags::LOW_COVERAGE) {
                continue;
            }
            s.flags.push(flags::LOW_COVERAGE.to_string());
            flagged += 1;
            for r in records
                .iter_mut()
                .filter(|r| r.pin == pin && r.step == step)
            {
                r.flags.push(flags::LOW_COVERAGE.to_string());
            }
        }
        if flagged > 0 && !flagged_before {
            f.notes.push(format!(
                "low coverage: the matched rows rest on {:.0} % of the sliding time (min_steady_share {:.0} %); {}",
                100.0 * f.coverage.steady_share(),
                100.0 * cfg.min_steady_share,
                f.coverage.line()
            ));
        }
    }
}

/// A dataset row from a measured segment (see [`crate::steady_window::PlateauStats::record`]), its
/// label's evidence taken from the segment's report.
pub(super) fn segment_record(
    c: &Campaign,
    (pin, step): (u32, u32),
    planned_n: Option<f64>,
    velocity_m_s: f64,
    s: &SegmentReport,
) -> Result<FrictionRecord> {
    let place = crate::steady_window::PlateauPlace {
        pin,
        step,
        planned_n,
        velocity_m_s,
        flags: s.flags.clone(),
        label_evidence: s.label_evidence.as_deref().and_then(|e| {
            greybox_core::dataset::label_evidence::ALL
                .into_iter()
                .find(|x| *x == e)
        }),
    };
    s.stats.as_ref().expect("measured").record(c.contact, place)
}

/// One direction's mean over its own steady window.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassMean {
    /// The pass's bounds and steady window on the recording's clock, s.
    pub start_s: f64,
    pub end_s: f64,
    pub steady_start_s: f64,
    pub steady_end_s: f64,
    /// μ as a magnitude, with its 95 % half-width and standard error.
    pub cof: f64,
    pub cof_ci95: f64,
    pub cof_sem: f64,
    pub n_samples: usize,
    pub normal_force_n: f64,
}

/// A test in both directions: the forward and the reverse pass's means (the row's μ is their
/// mean; see [`super::passes`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassPair {
    pub forward: PassMean,
    pub backward: PassMean,
    /// μ_forward − μ_backward and its 95 % half-width, √(h_f² + h_b²).
    pub difference: f64,
    pub difference_ci95: f64,
}

impl PassMean {
    pub(super) fn of(s: &SegmentReport, st: &PlateauStats) -> PassMean {
        PassMean {
            start_s: s.start_s,
            end_s: s.end_s,
            steady_start_s: s.steady_start_s.unwrap_or(s.start_s),
            steady_end_s: s.steady_end_s.unwrap_or(s.end_s),
            cof: st.mean,
            cof_ci95: st.ci95,
            cof_sem: st.interval.sem,
            n_samples: st.n_samples,
            normal_force_n: st.normal_force_n,
        }
    }
}
