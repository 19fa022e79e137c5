//! Change points of μ inside a sliding run: a least-squares split into a known number of steps, a
//! penalised split without one, the plan's timing, and the uncertainty of each boundary.

use super::prepare::Prepared;
use super::span::{Cut, Span};
use crate::config::IdentifyConfig;
use crate::expected::ExpectedStep;
use crate::signal::mad_sigma;
use crate::uncertainty::mean_standard_error;
use greybox_core::stats::median;
use greybox_core::{Error, Result, SourcePos};

/// Prefix sums of a series and its squares: the least-squares cost of a constant piece in O(1).
pub(super) struct PrefixSums {
    s1: Vec<f64>,
    s2: Vec<f64>,
}

impl PrefixSums {
    pub(super) fn new(x: &[f64]) -> Self {
        let mut s1 = vec![0.0; x.len() + 1];
        let mut s2 = vec![0.0; x.len() + 1];
        for (i, v) in x.iter().enumerate() {
            s1[i + 1] = s1[i] + v;
            s2[i + 1] = s2[i] + v * v;
        }
        PrefixSums { s1, s2 }
    }

    /// Sum of squared deviations from the mean over `[a, b)` (0 for an empty piece).
    pub(super) fn cost(&self, a: usize, b: usize) -> f64 {
        if b <= a {
            return 0.0;
        }
        let m = (b - a) as f64;
        let s = self.s1[b] - self.s1[a];
        (self.s2[b] - self.s2[a]) - s * s / m
    }
}

/// Residuals of `x` about the means of its pieces split at `bounds`.
pub(super) fn split_residuals(x: &[f64], bounds: &[usize]) -> Vec<f64> {
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

/// Residuals of `x` about the medians of its pieces split at `bounds`, over each piece's
/// middle half only: the disturbance inside the steps, without the ramps and settling at
/// their ends (which are transitions, not noise).
pub(super) fn inner_residuals(x: &[f64], bounds: &[usize]) -> Vec<f64> {
    let mut edges = vec![0];
    edges.extend_from_slice(bounds);
    edges.push(x.len());
    let mut resid = Vec::with_capacity(x.len() / 2);
    for w in edges.windows(2) {
        let (a, b) = (w[0] + (w[1] - w[0]) / 4, w[1] - (w[1] - w[0]) / 4);
        if b <= a {
            continue;
        }
        let piece = &x[a..b];
        let m = median(piece);
        resid.extend(piece.iter().map(|v| v - m));
    }
    resid
}

/// χ²(1) at 95 %: a boundary position whose cost exceeds the optimum by less than this many
/// noise variances is as good as the optimum.
pub(super) const CHI2_1_95: f64 = 3.84;

/// Uncertainty of each inner boundary of a piecewise-constant split of `x` at `bounds`, in
/// samples of `x`: the largest distance from the boundary of a position whose two-piece cost
/// (the neighbouring boundaries fixed) lies within χ²₁(95 %) noise variances of the optimum
/// (Hinkley 1970, "Inference about the change-point in a sequence of random variables",
/// likelihood-ratio confidence set). The noise variance is the residual variance of the
/// split, inflated by (1 + ρ₁)/(1 − ρ₁) for the lag-1 autocorrelation ρ₁ of the residuals
/// (a periodic disturbance such as spindle run-out is correlated noise, not signal).
pub(super) fn boundary_uncertainty(x: &[f64], bounds: &[usize]) -> Vec<usize> {
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
pub(super) fn split_into(x: &[f64], k: usize, min_len: usize) -> Option<Vec<usize>> {
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
pub(super) fn split_penalised(x: &[f64], min_len: usize) -> Vec<usize> {
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
pub(super) fn trim_transients(x: &[f64]) -> (usize, usize) {
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
pub(super) fn split_run(
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
        let (bounds, unc_blocks) = timed_bounds(&all_blocks, &d, block_s);
        let unc = vec![unc_blocks as f64 * block_s; bounds.len()];
        return Ok(spans_at(run, &bounds, b, &unc, 0.0, Cut::PlanTiming));
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
    let resid = inner_residuals(blocks, &bounds);
    let run_sem = mean_standard_error(&resid) * (resid.len() as f64 * block_s).sqrt();
    let cut = if bounds.is_empty() {
        Cut::Run
    } else {
        Cut::LevelChange
    };
    Ok(spans_at(run, &bounds, b, &unc, run_sem, cut))
}

/// The spans of `run` cut at block `bounds` (`b` samples a block) by `cut`, with each
/// boundary's uncertainty (s, none: sharp) and the run's disturbance.
pub(super) fn spans_at(
    run: Span,
    bounds: &[usize],
    b: usize,
    unc: &[f64],
    run_sem: f64,
    cut: Cut,
) -> Vec<Span> {
    let mut edges = vec![run.i];
    edges.extend(bounds.iter().map(|c| (run.i + c * b).min(run.j)));
    edges.push(run.j);
    edges
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[1] > w[0])
        .map(|(s, w)| {
            let mut span = Span::new(w[0], w[1], None).by(cut);
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
/// plan's, that best fits μ as a constant per planned step (least squares over prefix sums;
/// the surplus outside the planned steps is not counted, being unplanned). A run
/// longer than planned (an unplanned run-in before the first step, a late stop) gets the
/// surplus as a piece of its own, which the alignment then leaves unmatched, instead of
/// shifting every step's label.
///
/// With the boundaries, their uncertainty in blocks: the farthest offset whose cost lies
/// within χ²₁(95 %) noise variances of the best (the likelihood-ratio set of the one shared
/// offset, as [`boundary_uncertainty`] does per boundary; the noise variance inflated for
/// the residuals' lag-1 correlation), at least one block (the blocks' own granularity).
pub(super) fn timed_bounds(blocks: &[f64], durations: &[f64], block_s: f64) -> (Vec<usize>, usize) {
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
    // the planned steps' cost only: the surplus before and after them (the same number of
    // blocks whatever the offset) is unplanned material, free to hold anything (a run-in's
    // first, largest deviations would otherwise pull the plan onto it)
    let planned_cost = |off: i64| {
        let edges: Vec<usize> = planned
            .iter()
            .map(|c| (c + off as f64).round().clamp(0.0, n as f64) as usize)
            .collect();
        edges.windows(2).map(|w| sums.cost(w[0], w[1])).sum::<f64>()
    };
    let best = (lo..=hi)
        .min_by(|a, b| planned_cost(*a).total_cmp(&planned_cost(*b)))
        .unwrap_or(0);
    let bounds = at(best);
    let resid = split_residuals(blocks, &bounds);
    let ss: f64 = resid.iter().map(|r| r * r).sum();
    let var = ss / n.saturating_sub(bounds.len() + 1).max(1) as f64;
    let rho =
        (resid.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / ss.max(1e-300)).clamp(0.0, 0.95);
    let threshold = planned_cost(best) + CHI2_1_95 * var * (1.0 + rho) / (1.0 - rho);
    let unc = (lo..=hi)
        .filter(|o| planned_cost(*o) <= threshold)
        .map(|o| o.abs_diff(best) as usize)
        .max()
        .unwrap_or(0)
        .max(1);
    (bounds, unc)
}

/// The uncertainty, s, of each inner boundary of a run split at `bounds` (blocks of
/// `block_s` seconds), 0 where the boundary is well determined: its likelihood-ratio
/// confidence set ([`boundary_uncertainty`]) reaching two blocks or more; and, when the plan
/// gave the step count (`planned`), a step whose length differs by more than 30 % from the
/// median step (the plan's regular timing contradicted) makes both its boundaries uncertain
/// by that difference.
pub(super) fn weak_boundaries(
    blocks: &[f64],
    bounds: &[usize],
    planned: bool,
    block_s: f64,
) -> Vec<f64> {
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
}
