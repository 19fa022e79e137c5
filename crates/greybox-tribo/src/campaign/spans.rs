//! Segments from a step column or a speed channel (runs of one step number or one speed level), and
//! the loaded-and-sliding runs the signal segmenter splits.

use super::prepare::Prepared;
use super::span::{Cut, Span};
use crate::config::IdentifyConfig;
use crate::expected::ExpectedStep;
use crate::signal::{block_medians, mad_sigma, runs};
use greybox_core::stats::median;

/// Runs of one step number, restricted to their loaded-and-sliding part.
pub(super) fn spans_from_steps(p: &Prepared, steps: &[f64]) -> Vec<Span> {
    let mut out = Vec::new();
    let mut s = 0;
    for k in 1..=steps.len() {
        if k == steps.len() || steps[k] != steps[s] {
            let slide: Vec<usize> = (s..k).filter(|i| p.sliding[*i]).collect();
            if let (Some(&a), Some(&b)) = (slide.first(), slide.last()) {
                out.push(Span::new(a, b + 1, Some(steps[s])).by(Cut::StepColumn));
            }
            s = k;
        }
    }
    out
}

/// How far a channel may stray and still hold one level: `rel` × |level| + `abs`.
#[derive(Debug, Clone, Copy)]
pub(super) struct LevelTolerance {
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
    pub(super) fn from_noise(
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

    pub(super) fn within(&self, a: f64, level: f64) -> bool {
        (a - level).abs() <= self.rel * level.abs() + self.abs
    }
}

/// The smallest relative step between distinct planned sliding velocities.
pub(super) fn plan_speed_step(expected: Option<&[ExpectedStep]>) -> Option<f64> {
    let mut v: Vec<f64> = expected?.iter().map(|e| e.sliding_velocity_m_s).collect();
    v.sort_by(f64::total_cmp);
    v.windows(2)
        .map(|w| (w[1] - w[0]) / w[1])
        .filter(|d| *d > 1e-6)
        .reduce(f64::min)
}

/// Runs of one level above rest in block medians `sm`: `(start, end, level)` in blocks, each
/// run grown while blocks stay within `tol` of its running median.
pub(super) fn level_runs(sm: &[f64], rest: f64, tol: LevelTolerance) -> Vec<(usize, usize, f64)> {
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
pub(super) fn merge_same_level(
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
pub(super) fn spans_from_speed(
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
        // only the loaded part of the run, gaps shorter than a stop closed
        for (a, e) in closed_runs(p, &p.sliding[i..j]) {
            out.push(Span::new(i + a, i + e, None).by(Cut::Speed));
        }
    }
    out
}

/// Runs of `mask` with gaps under 50 ms (or two of the rig's periods) closed: a dip of the
/// sliding evidence that short is noise, not a stop.
fn closed_runs(p: &Prepared, mask: &[bool]) -> Vec<(usize, usize)> {
    let gap = (0.05f64.max(2.0 * p.period_s.unwrap_or(0.0)) * p.fs) as usize;
    let mut out: Vec<(usize, usize)> = Vec::new();
    for (a, e) in runs(mask) {
        match out.last_mut() {
            Some(last) if a - last.1 <= gap => last.1 = e,
            _ => out.push((a, e)),
        }
    }
    out
}

/// Loaded-and-sliding runs (gaps under 50 ms, or two of the rig's periods, closed).
pub(super) fn sliding_runs(p: &Prepared) -> Vec<Span> {
    closed_runs(p, &p.sliding)
        .into_iter()
        .map(|(a, e)| Span::new(a, e, None))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_of_true() {
        assert_eq!(
            runs(&[false, true, true, false, true]),
            vec![(1, 3), (4, 5)]
        );
        assert!(runs(&[false, false]).is_empty());
    }
}
