//! Regression metrics and bootstrap confidence intervals.
//!
//! MAE = mean |y − ŷ|; MSE = mean (y − ŷ)²; MAPE = mean |y − ŷ| / max(|y|, ε) as a fraction
//! (scikit-learn's definition, ε = machine epsilon); R² = 1 − SS_res / SS_tot.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

pub fn mae(y: &[f64], p: &[f64]) -> f64 {
    y.iter().zip(p).map(|(a, b)| (a - b).abs()).sum::<f64>() / y.len() as f64
}
pub fn mse(y: &[f64], p: &[f64]) -> f64 {
    y.iter().zip(p).map(|(a, b)| (a - b).powi(2)).sum::<f64>() / y.len() as f64
}
pub fn mape(y: &[f64], p: &[f64]) -> f64 {
    y.iter()
        .zip(p)
        .map(|(a, b)| (a - b).abs() / a.abs().max(f64::EPSILON))
        .sum::<f64>()
        / y.len() as f64
}
pub fn r2(y: &[f64], p: &[f64]) -> f64 {
    let m = y.iter().sum::<f64>() / y.len() as f64;
    let ss_tot: f64 = y.iter().map(|a| (a - m).powi(2)).sum();
    let ss_res: f64 = y.iter().zip(p).map(|(a, b)| (a - b).powi(2)).sum();
    if ss_tot == 0.0 {
        return if ss_res == 0.0 { 1.0 } else { 0.0 };
    }
    1.0 - ss_res / ss_tot
}

/// Percentile with linear interpolation between order statistics (numpy's default).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return f64::NAN;
    }
    let pos = q / 100.0 * (n - 1) as f64;
    let lo = pos.floor() as usize;
    let hi = pos.ceil() as usize;
    sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64)
}

/// A value with its 95 % confidence interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WithCi {
    pub value: f64,
    /// The interval's ends; `None` (JSON `null`) when no bootstrap resamples were asked
    /// (`bootstrap` 0): the value stands without an interval, and says so when written.
    pub ci_low: Option<f64>,
    pub ci_high: Option<f64>,
}

impl WithCi {
    /// `value [low, high]`, each number written by `num`; `value (no interval: bootstrap 0)`
    /// without one.
    pub fn display(&self, num: impl Fn(f64) -> String) -> String {
        match (self.ci_low, self.ci_high) {
            (Some(lo), Some(hi)) => format!("{} [{}, {}]", num(self.value), num(lo), num(hi)),
            _ => format!("{} (no interval: bootstrap 0)", num(self.value)),
        }
    }

    /// The value and its interval times `k` (a share as per cent).
    pub fn scaled(&self, k: f64) -> WithCi {
        WithCi {
            value: k * self.value,
            ci_low: self.ci_low.map(|v| k * v),
            ci_high: self.ci_high.map(|v| k * v),
        }
    }
}

/// Metrics of a set of predictions.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    pub mae: WithCi,
    pub mse: WithCi,
    pub mape: WithCi,
    /// R² (point estimate, as the article reports it) with its bootstrap CI.
    pub r2: WithCi,
    pub n: usize,
}

/// Percentile-bootstrap 95 % CI of `metric` over (y, ŷ) pairs, `resamples` resamples (none
/// when 0: the value alone).
pub fn bootstrap_ci(
    y: &[f64],
    p: &[f64],
    metric: fn(&[f64], &[f64]) -> f64,
    resamples: usize,
    seed: u64,
) -> WithCi {
    let n = y.len();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut ys = vec![0.0; n];
    let mut ps = vec![0.0; n];
    let mut stats: Vec<f64> = (0..resamples)
        .map(|_| {
            for k in 0..n {
                let i = rng.gen_range(0..n);
                ys[k] = y[i];
                ps[k] = p[i];
            }
            metric(&ys, &ps)
        })
        .collect();
    stats.sort_by(f64::total_cmp);
    let bounded = resamples > 0;
    WithCi {
        value: metric(y, p),
        ci_low: bounded.then(|| percentile(&stats, 2.5)),
        ci_high: bounded.then(|| percentile(&stats, 97.5)),
    }
}

/// All four metrics with bootstrap CIs (each metric its own seeded stream).
pub fn metrics_with_ci(y: &[f64], p: &[f64], resamples: usize, seed: u64) -> Metrics {
    Metrics {
        mae: bootstrap_ci(y, p, mae, resamples, seed),
        mse: bootstrap_ci(y, p, mse, resamples, seed.wrapping_add(1)),
        mape: bootstrap_ci(y, p, mape, resamples, seed.wrapping_add(2)),
        r2: bootstrap_ci(y, p, r2, resamples, seed.wrapping_add(3)),
        n: y.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed: y = [1, 2, 4], ŷ = [1.5, 2, 3]: errors 0.5, 0, 1.
    #[test]
    fn hand_computed_values() {
        let y = [1.0, 2.0, 4.0];
        let p = [1.5, 2.0, 3.0];
        assert!((mae(&y, &p) - 0.5).abs() < 1e-15);
        assert!((mse(&y, &p) - 1.25 / 3.0).abs() < 1e-15);
        assert!((mape(&y, &p) - (0.5 + 0.0 + 0.25) / 3.0).abs() < 1e-15);
        // mean 7/3, SS_tot = 16/9 + 1/9 + 25/9 = 42/9, SS_res = 1.25
        assert!((r2(&y, &p) - (1.0 - 1.25 / (42.0 / 9.0))).abs() < 1e-15);
        assert_eq!(percentile(&[1.0, 2.0, 3.0, 4.0], 50.0), 2.5);
        assert_eq!(percentile(&[1.0, 2.0, 3.0, 4.0, 5.0], 25.0), 2.0);
    }

    /// The bootstrap CI of the mean absolute error of N(0, 1) errors covers E|e| = sqrt(2/π)
    /// with the textbook width ≈ 2 × 1.96 × sd(|e|)/sqrt(n).
    #[test]
    fn bootstrap_ci_on_a_known_distribution() {
        use rand_distr::Distribution;
        let n = 2000;
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let normal = rand_distr::Normal::new(0.0, 1.0).unwrap();
        let e: Vec<f64> = (0..n).map(|_| normal.sample(&mut rng)).collect();
        let y = vec![0.0; n];
        let ci = bootstrap_ci(&y, &e, mae, 1000, 42);
        let truth = (2.0 / std::f64::consts::PI).sqrt();
        assert!(
            ci.ci_low.unwrap() < truth && truth < ci.ci_high.unwrap(),
            "{ci:?}"
        );
        let sd_abs = (1.0 - 2.0 / std::f64::consts::PI).sqrt();
        let width = 2.0 * 1.96 * sd_abs / (n as f64).sqrt();
        let got = ci.ci_high.unwrap() - ci.ci_low.unwrap();
        assert!((got / width - 1.0).abs() < 0.15, "width {got} vs {width}");
    }
}
