//! Passes of a test whose sliding reverses (a bidirectional test, no `--test-mode` needed):
//! where the direction changes, the friction force oriented so that μ is positive in every
//! pass, the segments split at the reversals, and a forward pass followed by a reverse one
//! reported as one row with both directions beside it.
//!
//! **Forward** is the direction of the file's first sliding pass (whatever the sign the rig
//! records it with), **reverse** the other. A pass is a stretch of one direction
//! ([`crate::sliding`]: the sign of the friction force over the sliding samples, a reversal
//! lasting at least `min_segment_s`).
//!
//! **The row of a forward pass followed by a reverse pass** (each one segment, at the same
//! load within `match_load_tolerance` and, where a speed channel measures both, the same
//! speed within `match_speed_tolerance`) is one test in two directions, and its μ is the mean of
//! the two directions' means, as ASTM G133 averages the two directions of a reciprocating
//! test: an offset δ left on the friction channel adds δ/F_N to one direction and takes it
//! from the other, and cancels in the mean. Its interval combines the two windows' own
//! standard errors, ½·√(s_f² + s_b²), with the degrees of freedom of Welch–Satterthwaite,
//! the normal channel's baseline error (common to both), what is left of the friction
//! channel's (a constant offset cancels, a drifting one partly) and the boundary widenings
//! ([`pair_interval`]). Both directions'
//! means and intervals stay in the segment's report ([`PassPair`]); when their difference
//! exceeds its own 95 % interval the file says so (a direction-dependent friction, or an
//! offset the baseline did not remove). A reverse pass that is cut into several steps, or
//! that follows no forward pass, is a row of its own (its segment says `reverse`).

use super::prepare::Prepared;
use super::report::{PassMean, PassPair, SegmentReport};
use super::span::Span;
use crate::config::IdentifyConfig;
use crate::steady_window::PlateauStats;
use crate::uncertainty::WindowMean;

/// `span` without the transition at its end — the friction force falling at a stop or into a
/// reversal, which a segment's steady window cannot find on its own, as it searches its final
/// stationary stretch from the end — and, at a reversal, without the rise out of it at its
/// start: the blocks (of [`Prepared::step_block`]) of μ's block medians outside the band of
/// the span's middle half ([`crate::steady_window::level_band`]: five robust standard deviations of
/// the blocks themselves, so that correlated noise widens it), from the end inwards (and
/// from the start outwards). Each end loses at most a fifth of the span (a slow drift is
/// reported as a trend, not cut).
pub(super) fn trim_ends(p: &Prepared, span: Span) -> Span {
    let at_start = p.passes.reversals.iter().any(|r| r.1 == span.i);
    let b = p.step_block();
    let mu: Vec<f64> = (span.i..span.j).map(|k| p.ft_c[k] / p.fn_c[k]).collect();
    let blocks: Vec<f64> = mu.chunks(b).map(greybox_core::stats::median).collect();
    let n = blocks.len();
    if n < 8 {
        return span;
    }
    let (level, band) = crate::steady_window::level_band(&blocks[n / 4..(3 * n) / 4], 0.0);
    let out = |k: usize| (blocks[k] - level).abs() > band;
    // from the end (at most a fifth), and at a reversal from the start, while outside
    let tb = (n - n / 5..n)
        .rev()
        .find(|k| !out(*k))
        .map_or(n - n / 5, |k| k + 1);
    let ta = if at_start {
        (0..n / 5).find(|k| !out(*k)).unwrap_or(n / 5)
    } else {
        0
    };
    Span {
        i: span.i + ta * b,
        j: (span.i + tb * b).min(span.j),
        ..span
    }
}

/// Replace each forward segment followed by a reverse one (each the only segment of its pass,
/// both measured, loads within `match_load_tolerance` and measured speeds, where both have
/// one, within `match_speed_tolerance`) by one segment of both directions; the
/// segments renumbered. Notes on pairs whose directions differ beyond their interval.
pub(super) fn pair_passes(
    segs: Vec<SegmentReport>,
    pass_of: &[u32],
    cfg: &IdentifyConfig,
    notes: &mut Vec<String>,
) -> Vec<SegmentReport> {
    let alone = |k: usize| pass_of.iter().filter(|q| **q == pass_of[k]).count() == 1;
    let mut out: Vec<SegmentReport> = Vec::with_capacity(segs.len());
    let mut it = segs.into_iter().enumerate().peekable();
    while let Some((k, s)) = it.next() {
        let pairs_with_next = |(k2, n): &(usize, SegmentReport)| {
            pass_of[k].is_multiple_of(2)
                && pass_of[*k2] == pass_of[k] + 1
                && alone(k)
                && alone(*k2)
                && s.stats.is_some()
                && n.stats.is_some()
                && same_level(s.normal_force_n, n.normal_force_n, cfg.match_load_tolerance)
                && match (s.sliding_velocity_m_per_min, n.sliding_velocity_m_per_min) {
                    (Some(a), Some(b)) => same_level(a, b, cfg.match_speed_tolerance),
                    _ => true,
                }
        };
        match it.next_if(pairs_with_next) {
            Some((_, back)) => {
                let pair = both_directions(s, back);
                if let Some(p) = &pair.passes {
                    if p.difference.abs() > p.difference_ci95 {
                        notes.push(format!(
                            "the forward and reverse pass of {:.3}–{:.3} s differ: μ {:.4} ± {:.4} forward, {:.4} ± {:.4} reverse (a direction-dependent friction, or an offset of the friction channel the baseline did not remove; their mean cancels such an offset)",
                            pair.start_s, pair.end_s, p.forward.cof, p.forward.cof_ci95, p.backward.cof, p.backward.cof_ci95
                        ));
                    }
                }
                out.push(pair);
            }
            None => out.push(s),
        }
    }
    for (k, s) in out.iter_mut().enumerate() {
        s.index = k + 1;
    }
    out
}

/// The standard error, degrees of freedom and 95 % half-width of the mean of two passes'
/// μ (module documentation): the windows' own errors add in quadrature (halved), with the
/// degrees of freedom of Welch–Satterthwaite; the normal channel's baseline error is common
/// to both; the friction channel's offset enters the reverse pass with the other sign, so
/// that of a baseline line, δ(λ) = (1 − λ)·e_start + λ·e_end, only (λ_b − λ_f)·(e_start −
/// e_end)/2 is left (a constant offset cancels); the boundary widenings are halved and added.
/// Without the parts, the two half-widths in quadrature, halved.
fn pair_interval(f: &PlateauStats, b: &PlateauStats) -> (f64, f64, f64) {
    let (Some(pf), Some(pb)) = (f.parts, b.parts) else {
        let sem = 0.5 * f.interval.sem.hypot(b.interval.sem);
        let nu = (f.interval.n_eff + b.interval.n_eff - 2.0).max(1.0);
        return (sem, nu, 0.5 * f.ci95.hypot(b.ci95));
    };
    let (wf, wb) = (pf.window, pb.window);
    let (a, c) = (wf.sem.powi(2), wb.sem.powi(2));
    let (na, nc) = ((wf.n_eff - 1.0).max(1.0), (wb.n_eff - 1.0).max(1.0));
    let nu = if a + c > 0.0 {
        (a + c).powi(2) / (a * a / na + c * c / nc)
    } else {
        na + nc
    };
    let tangential = match (pf.tangential_offset, pb.tangential_offset) {
        ((ta, te, Some(lf)), (_, _, Some(lb))) => 0.5 * (lb - lf).abs() * ta.hypot(te),
        _ => 0.0,
    };
    let sem = (0.25 * (a + c)
        + (0.5 * (pf.normal_offset + pb.normal_offset)).powi(2)
        + tangential.powi(2))
    .sqrt();
    let ci95 = greybox_core::stats::t_factor(0.95, nu) * sem + 0.5 * (pf.shift + pb.shift);
    (sem, nu, ci95)
}

/// Whether `a` and `b` agree within `tol` of the larger magnitude.
fn same_level(a: f64, b: f64, tol: f64) -> bool {
    (a.abs() - b.abs()).abs() <= tol * a.abs().max(b.abs())
}

/// One segment from a forward segment `f` and the reverse segment `b` after it (both
/// measured): μ the mean of the two, its interval combined (module documentation).
fn both_directions(f: SegmentReport, b: SegmentReport) -> SegmentReport {
    let (sf, sb) = (
        f.stats.clone().expect("measured"),
        b.stats.clone().expect("measured"),
    );
    let pair = PassPair {
        forward: PassMean::of(&f, &sf),
        backward: PassMean::of(&b, &sb),
        difference: sf.mean - sb.mean,
        difference_ci95: sf.ci95.hypot(sb.ci95),
    };
    let mean = 0.5 * (sf.mean + sb.mean);
    let (sem, nu, ci95) = pair_interval(&sf, &sb);
    let mut flags = sf.flags.clone();
    for x in &sb.flags {
        if !flags.contains(x) {
            flags.push(x.clone());
        }
    }
    let n_samples = sf.n_samples + sb.n_samples;
    let normal_force_n = (sf.normal_force_n * sf.n_samples as f64
        + sb.normal_force_n * sb.n_samples as f64)
        / n_samples.max(1) as f64;
    let std = (0.5 * (sf.std.powi(2) + sb.std.powi(2))).sqrt();
    let stats = PlateauStats {
        mean,
        std,
        n_samples,
        start_s: sf.start_s,
        end_s: sb.end_s,
        trend_per_s: 0.5 * (sf.trend_per_s + sb.trend_per_s),
        stationary: sf.stationary && sb.stationary,
        flags: flags.clone(),
        spikes: sf.spikes + sb.spikes,
        interval: WindowMean {
            mean,
            sem,
            n_eff: nu + 1.0,
            half_width_95: ci95,
        },
        ci95,
        normal_force_n,
        parts: None,
    };
    let mut seg_flags = f.flags.clone();
    for x in &b.flags {
        if !seg_flags.contains(x) {
            seg_flags.push(x.clone());
        }
    }
    SegmentReport {
        end_s: b.end_s,
        steady_end_s: b.steady_end_s,
        normal_force_n,
        cof: Some(mean),
        cof_std: Some(std),
        cof_sem: Some(sem),
        cof_ci95: Some(ci95),
        cof_n_eff: Some(nu + 1.0),
        n_samples,
        masked_samples: f.masked_samples + b.masked_samples,
        flags: seg_flags,
        run_in_s: match (f.run_in_s, b.run_in_s) {
            (None, None) => None,
            (x, y) => Some(x.unwrap_or(0.0) + y.unwrap_or(0.0)),
        },
        drift_per_hour: Some(stats.trend_per_s * 3600.0),
        boundary_uncertainty_s: match (f.boundary_uncertainty_s, b.boundary_uncertainty_s) {
            (None, None) => None,
            (x, y) => Some(x.unwrap_or(0.0).max(y.unwrap_or(0.0))),
        },
        contradiction: f.contradiction.clone().or(b.contradiction.clone()),
        unsettled: f.unsettled.clone().or(b.unsettled.clone()),
        never_settles: f.never_settles || b.never_settles,
        direction: Some("both"),
        passes: Some(pair),
        stats: Some(stats),
        ..f
    }
}
