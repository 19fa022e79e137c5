//! Per-file preparation: loaded samples, baseline offsets, sign of the forces and the sliding mask (steps 1–3 of the campaign), and the sample [`Span`]s the segmenters cut.

use super::report::{read_warnings, FileReport, SegmentReport};
use crate::coverage::Coverage;
use crate::identify::IdentifyConfig;
use crate::recording::Recording;
use crate::signal::{block_medians, median, runs};
use crate::sliding::quantile;
use greybox_core::{Error, Result, SourcePos};

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
    pub(super) no_baseline: bool,
    pub(super) report: FileReport,
}

impl Prepared<'_> {
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

/// Sample ranges of a segment, `[i, j)`, with its step label and the uncertainty of its
/// start and end boundaries, s (0 where the boundary is sharp).
#[derive(Debug, Clone, Copy)]
pub(super) struct Span {
    pub(super) i: usize,
    pub(super) j: usize,
    pub(super) label: Option<f64>,
    pub(super) unc: (f64, f64),
    /// The run's standard error of a one-second mean of μ, √s (0: from the segment alone).
    pub(super) run_sem: f64,
}

impl Span {
    pub(super) fn new(i: usize, j: usize, label: Option<f64>) -> Self {
        Span {
            i,
            j,
            label,
            unc: (0.0, 0.0),
            run_sem: 0.0,
        }
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
pub(super) fn normal_positive(
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
