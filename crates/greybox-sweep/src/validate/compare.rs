//! Friction models compared on the same conditions: the paired differences of their held-out
//! errors, with intervals that say whether the difference is the models' or the cuts'
//! scatter, and how long the cuts would have to be to tell.
//!
//! For each material and tool model, every friction model is set against the first one the
//! suite lists (the baseline, usually `coulomb-calibrated`), on the held-out conditions both
//! were cut at. Per measure (F'c, F'f, chip ratio) and condition i the difference is
//! d_i = |e_model,i| − |e_base,i| (negative: the model is closer to the measurement), and
//!
//! * its mean d̄ over the n conditions, with the 95 % interval of the cuts' own scatter,
//!   d̄ ± 1.96 √(Σ (se_model,i² + se_base,i²)) / n, each se a cut's standard error from the
//!   batch means of its steady state ([`greybox_sim::steady`]; d|e| = sign(e) de, so |e|
//!   has e's standard error where the error is clear of zero; a cut that could not say is
//!   given the median of the others', and the verdict counts them). This is the
//!   **resolution**: a difference inside it cannot be told from the cuts' scatter;
//! * the measured values' share, 1.96 √(Σ se_d,i²)/n with se_d,i = |sign(e_m)(1 + e_m) −
//!   sign(e_b)(1 + e_b)| σ_m,i/m_i: both models are held against the same measured mean, so
//!   its scatter nearly cancels where their errors share a sign and doubles where they do
//!   not ([`super::goals`]). The verdict is taken on both intervals together;
//! * the paired t-interval across the conditions, d̄ ± t(0.975; n − 1) s_d/√n: whether the
//!   difference holds from condition to condition (it includes the scatter);
//! * the cut length at which the resolution would be ±[`RESOLVE`]: the interval narrows as
//!   1/√L with the steady stretch L, so L' = L̄ (Y/0.03)² plus the warm-up.

use super::{held_out_groups, imputed_errors, mean_ci95, Outcome, ToolModel};
use greybox_core::stats::t_half_width;
use serde::Serialize;

/// The difference a suite should be able to tell apart: 3 % of the measured value.
pub const RESOLVE: f64 = 0.03;

/// One measure's paired difference between a friction model and the baseline (fractions of
/// the measured values).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairedDifference {
    /// Mean over the conditions of |e_model| − |e_baseline| (negative: the model is closer).
    pub mean: f64,
    /// Half-width of its 95 % interval from the cuts' own scatter (`None`: a cut could not
    /// say how sure it is).
    pub ci95: Option<f64>,
    /// Half-width of its 95 % interval from the measured values' own scatter (0 where the
    /// data do not say what their dispersions are); the verdict uses both together.
    pub measured_ci95: f64,
    /// Half-width of the paired t-interval across the conditions (`None`: one condition).
    pub across_conditions_ci95: Option<f64>,
    /// Conditions where the model's |error| is the smaller.
    pub conditions_better: usize,
    pub conditions: usize,
    /// What the numbers allow one to say.
    pub verdict: String,
    /// The cut length (mm, warm-up included) at which the scatter's interval would be
    /// ±[`RESOLVE`].
    pub length_to_resolve_mm: Option<f64>,
}

/// A friction model against the baseline on one material and tool model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    pub material: String,
    pub tool: ToolModel,
    pub friction: String,
    pub baseline: String,
    pub cutting_force: PairedDifference,
    pub feed_force: PairedDifference,
    pub chip_ratio: Option<PairedDifference>,
}

/// Every friction model against its material's and tool model's first one.
pub fn compare(outcomes: &[Outcome]) -> Vec<Comparison> {
    let mut out = Vec::new();
    for (material, tool, rows, models) in held_out_groups(outcomes) {
        let Some((base, others)) = models.split_first() else {
            continue;
        };
        for model in others {
            let pairs: Vec<(&Outcome, &Outcome)> = rows
                .iter()
                .filter(|o| o.friction == *model)
                .filter_map(|m| {
                    rows.iter()
                        .find(|b| b.friction == *base && b.id == m.id)
                        .map(|b| (*m, *b))
                })
                .collect();
            if pairs.is_empty() {
                continue;
            }
            let ratios: Vec<(&Outcome, &Outcome)> = pairs
                .iter()
                .copied()
                .filter(|(m, b)| m.chip_ratio_error.is_some() && b.chip_ratio_error.is_some())
                .collect();
            out.push(Comparison {
                material: material.to_string(),
                tool,
                friction: model.to_string(),
                baseline: base.to_string(),
                cutting_force: paired(&pairs, 0),
                feed_force: paired(&pairs, 1),
                chip_ratio: (!ratios.is_empty()).then(|| paired(&ratios, 2)),
            });
        }
    }
    out
}

/// The error of measure `k` of an outcome (the pairs compared on the chip ratio all have one).
fn error(o: &Outcome, k: usize) -> f64 {
    o.error(k).unwrap_or(f64::NAN)
}

/// The paired difference of measure `k` over `pairs` (model, baseline).
fn paired(pairs: &[(&Outcome, &Outcome)], k: usize) -> PairedDifference {
    let n = pairs.len();
    let d: Vec<f64> = pairs
        .iter()
        .map(|(m, b)| error(m, k).abs() - error(b, k).abs())
        .collect();
    let mean = d.iter().sum::<f64>() / n as f64;
    let se: Vec<Option<f64>> = pairs
        .iter()
        .flat_map(|(m, b)| [m.error_se[k], b.error_se[k]])
        .collect();
    let imputed = imputed_errors(&se);
    let ci95 = imputed.as_ref().map(|(v, _)| mean_ci95(v, n));
    let across = t_half_width(&d, 0.95);
    let lengths: Vec<(f64, f64)> = pairs
        .iter()
        .flat_map(|(m, b)| [m, b])
        .filter_map(|o| o.steady_length_mm.zip(o.steady_from_mm))
        .collect();
    let length_to_resolve_mm = ci95.filter(|_| !lengths.is_empty()).map(|y| {
        let l = lengths.len() as f64;
        let (steady, warm_up) = (
            lengths.iter().map(|x| x.0).sum::<f64>() / l,
            lengths.iter().map(|x| x.1).sum::<f64>() / l,
        );
        warm_up + steady * (y / RESOLVE).powi(2)
    });
    let short = pairs
        .iter()
        .flat_map(|(m, b)| [m, b])
        .filter(|o| o.short_stretch)
        .count();
    // Both models are held against the same measured value m: a change δ of it moves
    // |e_model| − |e_base| by −(sign(e_m)(1 + e_m) − sign(e_b)(1 + e_b)) δ/m, which is small
    // where the errors share a sign and doubles where they do not.
    let measured_se: Vec<f64> = pairs
        .iter()
        .filter_map(|(m, b)| {
            let (sm, sb) = (m.measured_error_se[k]?, b.measured_error_se[k]?);
            Some((error(m, k).signum() * sm - error(b, k).signum() * sb).abs())
        })
        .collect();
    let measured_ci95 = mean_ci95(&measured_se, n);
    let mut verdict = verdict(mean, ci95.map(|c| c.hypot(measured_ci95)));
    if short > 0 && ci95.is_some() {
        verdict += &format!(
            " ({short} of {} cuts averaged fewer contact renewals than asked: the scatter may be larger)",
            2 * n
        );
    }
    if let Some((_, missing)) = imputed.filter(|(_, m)| *m > 0) {
        verdict += &format!(
            " ({missing} of {} cuts could not say how sure they are: their scatter taken as the median of the others')",
            2 * n
        );
    }
    PairedDifference {
        mean,
        ci95,
        measured_ci95,
        across_conditions_ci95: across,
        conditions_better: d.iter().filter(|x| **x < 0.0).count(),
        conditions: n,
        verdict,
        length_to_resolve_mm,
    }
}

/// "better by 2.1 ± 1.0 points", "worse by …", or "no difference can be seen at this
/// resolution (±4.2 points)".
fn verdict(mean: f64, ci95: Option<f64>) -> String {
    let pts = |x: f64| 100.0 * x;
    match ci95 {
        None => "cannot tell: a cut could not say how sure it is".to_string(),
        Some(y) if mean.abs() > y => format!(
            "{} by {:.1} ± {:.1} points",
            if mean < 0.0 { "better" } else { "worse" },
            pts(mean.abs()),
            pts(y)
        ),
        Some(y) => format!(
            "no difference can be seen at this resolution ({:+.1} ± {:.1} points)",
            pts(mean),
            pts(y)
        ),
    }
}

/// The cut length (mm, warm-up included) at which two cuts of one condition would tell F'f
/// values `RESOLVE` apart, from the median over `outcomes` of their F'f standard errors at
/// their steady lengths: 1.96 √2 se √(L/L') = RESOLVE. `None` without a cut that says.
pub fn feed_resolution_length_mm(outcomes: &[Outcome]) -> Option<f64> {
    let mut needed: Vec<f64> = outcomes
        .iter()
        .filter_map(|o| {
            let (se, l, from) = (o.error_se[1]?, o.steady_length_mm?, o.steady_from_mm?);
            Some(from + l * (1.96 * std::f64::consts::SQRT_2 * se / RESOLVE).powi(2))
        })
        .collect();
    if needed.is_empty() {
        return None;
    }
    needed.sort_by(f64::total_cmp);
    Some(needed[needed.len() / 2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validate::test_support::outcome;

    /// The measured value is common to both models: its scatter nearly cancels in the
    /// difference of two errors of one sign, and adds where the signs differ; the verdict
    /// counts it.
    #[test]
    fn the_measured_values_scatter_counts_where_the_models_errors_differ_in_sign() {
        // chip ratio errors +10 % and +6 %: se_d = |1.10 − 1.06| σ/m
        let (m, b) = (
            outcome(0.10, Some(0.001), Some(1.10 * 0.05)),
            outcome(0.06, Some(0.001), Some(1.06 * 0.05)),
        );
        let same = paired(&[(&m, &b)], 2);
        assert!((same.measured_ci95 - 1.96 * 0.04 * 0.05).abs() < 1e-12);
        assert!(same.verdict.starts_with("worse by 4.0"), "{}", same.verdict);
        // +3 % against −7 %: se_d = |1.03 + 0.93| σ/m, and the 4-point difference is lost in it
        let (m, b) = (
            outcome(0.03, Some(0.001), Some(1.03 * 0.05)),
            outcome(-0.07, Some(0.001), Some(0.93 * 0.05)),
        );
        let opposite = paired(&[(&m, &b)], 2);
        assert!((opposite.measured_ci95 - 1.96 * 1.96 * 0.05).abs() < 1e-12);
        assert!((opposite.mean + 0.04).abs() < 1e-12);
        assert!(
            opposite.verdict.starts_with("no difference can be seen"),
            "{}",
            opposite.verdict
        );
        // the cuts' resolution is kept apart from it
        assert!((opposite.ci95.unwrap() - 1.96 * 0.001 * 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_difference_inside_the_scatter_is_not_called() {
        assert!(verdict(-0.02, Some(0.05)).starts_with("no difference can be seen"));
        assert_eq!(verdict(-0.06, Some(0.02)), "better by 6.0 ± 2.0 points");
        assert_eq!(verdict(0.06, Some(0.02)), "worse by 6.0 ± 2.0 points");
        assert!(verdict(0.06, None).starts_with("cannot tell"));
    }
}
