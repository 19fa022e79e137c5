//! Whether a friction model's errors move with the cutting speed, and how sure that is.
//!
//! A model can meet a mean-|error| goal and still miss how a measure depends on speed: the
//! Ti6Al4V chips of a model whose chip ratio does not respond to speed are too thin at the
//! slowest speed and too thick at the fastest, errors of opposite sign that a mean |error|
//! averages away (docs/validation.md, "The chip's speed dependence: ablations"). The signed
//! relative errors e_i = s_i/m_i − 1 of a role's conditions are fitted by least squares to
//!
//!   e_i = α + β ln(v_i / v̄),
//!
//! with v_i the cutting speed and v̄ their geometric mean. β ln 2 is the change of the error per
//! doubling of the speed: zero where the simulated measure follows the measured one's speed
//! dependence (whatever either is), positive where the simulated value rises with speed
//! relative to the measured one. Its 95 % interval is the least-squares slope's,
//!
//!   ± t(0.975; n − 2) ln 2 · s / √Σ(ln v_i − mean)²,   s² = Σ r_i² / (n − 2),
//!
//! from the residual scatter about the line, which holds the cuts' scatter, the measured
//! values' scatter and whatever of the model's error is not linear in ln v (a line is
//! what is asked of the data, not a claim that the error is linear). The reading is **rises**
//! or **falls** where the whole interval lies on one side of zero, and otherwise **no trend
//! resolved**: the conditions cannot tell a trend within the interval from none.
//! Fewer than three conditions, or a single speed, give no trend.

use super::goals::MEASURES;
use super::Outcome;
use greybox_core::stats::{t_factor, LEVEL};
use serde::Serialize;

/// How the signed error moves with speed, as the conditions tell it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrendReading {
    Rises,
    Falls,
    NoneResolved,
}

greybox_core::choice!(TrendReading, "speed trend", [Rises => "rises with speed", Falls => "falls with speed", NoneResolved => "no trend resolved"]);

/// One measure's signed error against the cutting speed over a role's conditions.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpeedTrend {
    /// "F'c", "F'f" or "chip ratio".
    pub measure: String,
    /// The conditions the line rests on and their distinct speeds.
    pub conditions: usize,
    pub speeds: usize,
    /// Change of the signed relative error per doubling of the cutting speed (fraction) and
    /// the half-width of its 95 % interval.
    pub per_doubling: f64,
    pub per_doubling_ci95: f64,
    /// The line's signed error at the slowest and the fastest speed (fractions).
    pub at_slowest: f64,
    pub at_fastest: f64,
    pub reading: TrendReading,
}

/// The least-squares line e = α + β ln(v/v̄) through `(v, e)` pairs: the trend or `None`
/// (fewer than three pairs, one speed, or a speed or error that is not a finite number).
pub fn fit(measure: &str, points: &[(f64, f64)]) -> Option<SpeedTrend> {
    let n = points.len();
    let x: Vec<f64> = points.iter().map(|(v, _)| v.ln()).collect();
    let speeds = {
        let mut s = x.clone();
        s.sort_by(f64::total_cmp);
        s.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * b.abs().max(1.0));
        s.len()
    };
    let finite = x
        .iter()
        .chain(points.iter().map(|p| &p.1))
        .all(|v| v.is_finite());
    if n < 3 || speeds < 2 || !finite {
        return None;
    }
    let nf = n as f64;
    let x_mean = x.iter().sum::<f64>() / nf;
    let e_mean = points.iter().map(|p| p.1).sum::<f64>() / nf;
    let sxx: f64 = x.iter().map(|v| (v - x_mean).powi(2)).sum();
    let sxe: f64 = x
        .iter()
        .zip(points)
        .map(|(v, p)| (v - x_mean) * (p.1 - e_mean))
        .sum();
    let slope = sxe / sxx;
    let residual_ss: f64 = x
        .iter()
        .zip(points)
        .map(|(v, p)| (p.1 - e_mean - slope * (v - x_mean)).powi(2))
        .sum();
    // n ≥ 3: at least one degree of freedom is left for the scatter about the line
    let dof = (n - 2) as f64;
    let ci95 =
        t_factor(LEVEL, dof) * (residual_ss / dof).sqrt() / sxx.sqrt() * std::f64::consts::LN_2;
    let per_doubling = slope * std::f64::consts::LN_2;
    let reading = if per_doubling - ci95 > 0.0 {
        TrendReading::Rises
    } else if per_doubling + ci95 < 0.0 {
        TrendReading::Falls
    } else {
        TrendReading::NoneResolved
    };
    let at = |v: f64| e_mean + slope * (v - x_mean);
    let (lo, hi) = x
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    Some(SpeedTrend {
        measure: measure.to_string(),
        conditions: n,
        speeds,
        per_doubling,
        per_doubling_ci95: ci95,
        at_slowest: at(lo),
        at_fastest: at(hi),
        reading,
    })
}

/// The trend of each measure's signed error over `rows` (a measure without a trend left
/// out: too few conditions with it, or one speed).
pub fn trends(rows: &[&Outcome]) -> Vec<SpeedTrend> {
    MEASURES
        .iter()
        .enumerate()
        .filter_map(|(k, measure)| {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter_map(|o| o.error(k).map(|e| (o.cutting_speed_m_per_min, e)))
                .collect();
            fit(measure, &points)
        })
        .collect()
}

/// "+4.1 ± 2.0 (rises with speed; −9.0 % at the slowest, +3.1 % at the fastest)": a trend
/// for a table cell, in points per doubling of v_c.
pub fn describe(t: &SpeedTrend) -> String {
    format!(
        "{:+.1} ± {:.1} ({}; {:+.1} % at the slowest, {:+.1} % at the fastest)",
        100.0 * t.per_doubling,
        100.0 * t.per_doubling_ci95,
        t.reading,
        100.0 * t.at_slowest,
        100.0 * t.at_fastest
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    #[test]
    fn a_line_through_exact_points_is_found_with_no_scatter() {
        // e = 0.02 + 0.05 ln(v/10): +0.05 ln 2 per doubling
        let pts: Vec<(f64, f64)> = [5.0, 10.0, 20.0, 40.0]
            .iter()
            .map(|&v: &f64| (v, 0.02 + 0.05 * (v / 10.0).ln()))
            .collect();
        let t = fit("F'c", &pts).unwrap();
        assert!((t.per_doubling - 0.05 * 2f64.ln()).abs() < 1e-12);
        assert!(t.per_doubling_ci95 < 1e-9);
        assert_eq!(t.reading, TrendReading::Rises);
        assert!((t.at_slowest - (0.02 + 0.05 * 0.5f64.ln())).abs() < 1e-12);
        assert!((t.at_fastest - (0.02 + 0.05 * 4f64.ln())).abs() < 1e-12);
        assert_eq!((t.conditions, t.speeds), (4, 4));
    }

    #[test]
    fn too_few_conditions_or_one_speed_give_no_trend() {
        assert!(fit("F'c", &[(5.0, 0.1), (10.0, 0.2)]).is_none());
        assert!(fit("F'c", &[(5.0, 0.1), (5.0, 0.2), (5.0, -0.1)]).is_none());
        let t = fit("F'c", &[(5.0, 0.1), (5.0, 0.2), (10.0, -0.1)]).unwrap();
        assert_eq!(t.speeds, 2);
        // a cut that gave no number makes no trend, not a NaN one
        assert!(fit("F'c", &[(5.0, 0.1), (10.0, f64::NAN), (20.0, -0.1)]).is_none());
        assert!(fit("F'c", &[(0.0, 0.1), (10.0, 0.2), (20.0, -0.1)]).is_none());
    }

    /// Against an independent reference: the textbook slope interval, here from a
    /// hand-worked example (Montgomery & Runger, the least-squares slope's t-interval,
    /// computed by hand for these five points: x = ln v, Sxx, the residuals).
    #[test]
    fn the_interval_is_the_least_squares_slopes() {
        // v = 5, 10, 20, 40, 80 → ln v evenly spaced by ln 2; e = 0, 0.1, 0.1, 0.3, 0.3
        let pts = [
            (5.0, 0.0),
            (10.0, 0.1),
            (20.0, 0.1),
            (40.0, 0.3),
            (80.0, 0.3),
        ];
        let t = fit("F'f", &pts).unwrap();
        // with u = ln(v)/ln 2 − mean ∈ {−2, −1, 0, 1, 2}: Suu = 10, Sue = 0.8 → 0.08 per doubling
        assert!((t.per_doubling - 0.08).abs() < 1e-12);
        // fitted 0.16 + 0.08 u: residuals 0, 0.02, −0.06, 0.06, −0.02 → SS 0.008, s² 0.008/3
        let s = (0.008f64 / 3.0).sqrt();
        let t3 = 3.182_446_305_284_263; // t(0.975; 3)
        assert!((t.per_doubling_ci95 - t3 * s / 10f64.sqrt()).abs() < 1e-9);
        assert_eq!(t.reading, TrendReading::Rises);
    }

    /// Generated suites with every thing the rule leaves free varied (speeds, conditions,
    /// the noise's law and size, the true trend): the interval covers the true change per
    /// doubling about 95 % of the time, and a true trend of zero reads "no trend resolved"
    /// about 95 % of the time.
    #[test]
    fn the_interval_covers_the_true_trend_at_its_level() {
        let mut rng = ChaCha8Rng::seed_from_u64(61);
        let unit = Normal::new(0.0, 1.0).unwrap();
        let (mut covered, mut flat_read_flat, mut flat, trials) = (0, 0, 0, 3000);
        for trial in 0..trials {
            let n = rng.gen_range(6..=24);
            let true_slope = if trial % 2 == 0 {
                0.0
            } else {
                rng.gen_range(-0.15..0.15)
            };
            let sigma = rng.gen_range(0.01..0.1);
            let laplace = rng.gen_bool(0.5);
            let pts: Vec<(f64, f64)> = (0..n)
                .map(|_| {
                    let v: f64 = rng.gen_range(2.0f64.ln()..200.0f64.ln()).exp();
                    let noise = if laplace {
                        // Laplace with standard deviation sigma
                        let u: f64 = rng.gen_range(-0.5..0.5);
                        -sigma / 2f64.sqrt() * u.signum() * (1.0 - 2.0 * u.abs()).ln()
                    } else {
                        sigma * unit.sample(&mut rng)
                    };
                    (v, 0.05 + true_slope * v.ln() + noise)
                })
                .collect();
            let Some(t) = fit("chip ratio", &pts) else {
                continue;
            };
            let h = t.per_doubling_ci95;
            if (t.per_doubling - true_slope * 2f64.ln()).abs() <= h {
                covered += 1;
            }
            if true_slope == 0.0 {
                flat += 1;
                if t.reading == TrendReading::NoneResolved {
                    flat_read_flat += 1;
                }
            }
        }
        let coverage = covered as f64 / trials as f64;
        let specificity = flat_read_flat as f64 / flat as f64;
        eprintln!("coverage {coverage:.3}, a flat truth read flat {specificity:.3}");
        assert!((0.93..=0.97).contains(&coverage), "coverage {coverage}");
        assert!(
            (0.93..=0.97).contains(&specificity),
            "flat read flat {specificity}"
        );
    }

    #[test]
    fn a_suite_outcome_gives_one_trend_per_measure_it_has() {
        let rows: Vec<Outcome> = [(5.0, -0.1), (10.0, 0.0), (20.0, 0.12), (40.0, 0.2)]
            .iter()
            .map(|&(v, e)| {
                let mut o = crate::validate::test_support::outcome(0.0, None, None);
                o.cutting_speed_m_per_min = v;
                (o.cutting_force_error, o.feed_force_error) = (-e, e);
                o.chip_ratio_error = None;
                o
            })
            .collect();
        let refs: Vec<&Outcome> = rows.iter().collect();
        let t = trends(&refs);
        assert_eq!(t.len(), 2, "no chip ratio measured: F'c and F'f only");
        assert_eq!(t[0].measure, "F'c");
        assert_eq!(t[0].reading, TrendReading::Falls);
        assert_eq!(t[1].reading, TrendReading::Rises);
        let cell = describe(&t[1]);
        assert!(
            cell.starts_with('+') && cell.contains("(rises with speed; "),
            "{cell}"
        );
    }
}
