//! The mean of a stationary but serially correlated series, with a confidence interval that
//! respects the correlation, and the pieces it is built from.
//!
//! A simulated cutting force (a serrated chip makes it periodic, its contacts make it
//! jitter) or a friction trace is one long, correlated record: the textbook σ/√n of its
//! samples is far too narrow. The estimator here is the method of **non-overlapping batch
//! means** (Law & Kelton, *Simulation Modeling and Analysis*, 5th ed., §9.5.3; Schmeiser
//! 1982, Oper. Res. 30:556): the record is cut into b batches of equal length, long
//! against the correlation, whose means are then nearly independent and nearly normal,
//! and the interval is
//!
//! ```text
//!   x̄ ± t(1 − α/2; b − 1) · s_b / √b,      s_b² = Σ (x̄_j − x̄)² / (b − 1)
//! ```
//!
//! * **Units.** The record is first reduced to *units*: the means over whole periods when
//!   the signal has one ([`period`]: averaging over a whole period removes the periodic
//!   part exactly, leaving its noise), else the samples themselves.
//! * **Batch length.** At least the integrated autocorrelation time τ of the units
//!   ([`integrated_autocorrelation_time`]: Geyer's initial monotone sequence, Geyer 1992,
//!   Stat. Sci. 7:473), and as few batches as [`MAX_BATCHES`] (Schmeiser: 10 to 30 batches
//!   lose little width and keep the coverage); fewer than [`MIN_BATCHES`] batches of that
//!   length give no interval: the record is too short to say how sure its mean is.
//! * **Warm-up.** A record that starts with a transient is truncated where the marginal
//!   standard error is least ([`mser_truncation`], White 1997, Simulation 69:323; MSER-5 of
//!   White, Cobb & Spratt 2000).
//!
//! * **Drift.** Batch means of a stationary record scatter about one level; a record that is
//!   still settling (a tool still warming) lines them up along a slope. Every interval
//!   states the change of its batch means across the record by their least-squares line,
//!   with its interval (t with b − 2 degrees of freedom; the batch means are the nearly
//!   independent observations the line is fitted to; the regression test of a trend in
//!   batch means, e.g. Law & Kelton §9.5.1), and a mean whose change is significant at the
//!   level is *drifting*: its interval describes the record, not a steady state. A short
//!   record cannot tell a slow drift from none; the change's interval says how large a drift
//!   it cannot exclude.
//!
//! The tests generate periodic, autoregressive, heavy-tailed and slowly wandering records
//! with a known mean and check that the 95 % interval covers it in 90–99 % of the seeds, and
//! records with a known drift whose change the drift's interval covers as often.

use serde::{Deserialize, Serialize};

/// Most batches an interval is formed from (longer batches: less correlation between them).
pub const MAX_BATCHES: usize = 10;
/// Fewest batches an interval is formed from (fewer: no interval).
pub const MIN_BATCHES: usize = 4;
/// The confidence level intervals are stated at.
pub const LEVEL: f64 = 0.95;

/// The half-width factor of a two-sided `level` interval from a Student t with `dof`
/// degrees of freedom: t(1 − (1 − level)/2; dof). `dof` ≥ 1.
pub fn t_factor(level: f64, dof: f64) -> f64 {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    let p = 1.0 - 0.5 * (1.0 - level);
    match StudentsT::new(0.0, 1.0, dof.max(1.0)) {
        Ok(t) => t.inverse_cdf(p),
        Err(_) => f64::INFINITY,
    }
}

/// Median of a slice (copies; NaN-free input expected). Empty → NaN.
pub fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mut v = values.to_vec();
    let mid = v.len() / 2;
    let (_, m, _) = v.select_nth_unstable_by(mid, f64::total_cmp);
    let m = *m;
    if v.len() % 2 == 1 {
        m
    } else {
        let lower = v[..mid].iter().copied().fold(f64::NEG_INFINITY, f64::max);
        0.5 * (lower + m)
    }
}

/// Arithmetic mean (NaN when empty).
pub fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

/// The sample standard deviation of `x` about its mean, s = √(Σ (x − x̄)²/(n − 1)) (NaN for
/// fewer than two values).
pub fn sample_sd(x: &[f64]) -> f64 {
    let m = mean(x);
    (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (x.len() as f64 - 1.0)).sqrt()
}

/// The half-width of the `level` t-interval of the mean of the independent values `x`,
/// t(1 − (1 − level)/2; n − 1) s/√n (`None` for fewer than two values).
pub fn t_half_width(x: &[f64], level: f64) -> Option<f64> {
    let n = x.len();
    (n >= 2).then(|| t_factor(level, (n - 1) as f64) * sample_sd(x) / (n as f64).sqrt())
}

/// The sample autocorrelation ρ_k of `x` (its mean removed; the biased estimator, each lag
/// over n) for k = 0..=max_lag (capped at n − 1); `None` for fewer than two samples or a
/// constant series.
pub fn autocorrelation(x: &[f64], max_lag: usize) -> Option<Vec<f64>> {
    let n = x.len();
    if n < 2 {
        return None;
    }
    let m = mean(x);
    let z: Vec<f64> = x.iter().map(|v| v - m).collect();
    let c0: f64 = z.iter().map(|v| v * v).sum();
    if !(c0 > 0.0) {
        return None;
    }
    Some(
        (0..=max_lag.min(n - 1))
            .map(|k| z.iter().zip(&z[k..]).map(|(a, b)| a * b).sum::<f64>() / c0)
            .collect(),
    )
}

/// The integrated autocorrelation time τ = 1 + 2 Σ_{k≥1} ρ_k of `x`, in samples, by
/// Geyer's initial monotone sequence estimator: the sums Γ_m = ρ_{2m} + ρ_{2m+1} are added
/// while positive, each capped at the one before (a stationary series' Γ_m is positive and
/// decreasing, Geyer 1992). At least 1 (an anti-correlated series is taken as independent);
/// 1 for a constant or too short series.
pub fn integrated_autocorrelation_time(x: &[f64]) -> f64 {
    let n = x.len();
    let Some(rho) = autocorrelation(x, n.saturating_sub(1)) else {
        return 1.0;
    };
    let mut tau = -1.0;
    let mut cap = f64::INFINITY;
    let mut m = 0;
    while 2 * m + 1 < rho.len() {
        let g = (rho[2 * m] + rho[2 * m + 1]).min(cap);
        if g <= 0.0 {
            break;
        }
        tau += 2.0 * g;
        cap = g;
        m += 1;
    }
    tau.max(1.0)
}

/// A period found in a series.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Period {
    /// In samples (fractional).
    pub samples: f64,
    /// The autocorrelation at it.
    pub correlation: f64,
}

/// The fundamental period of `x` in samples (fractional: the autocorrelation peak refined
/// by a parabola through it and its neighbours), or `None`: the first local maximum of the
/// autocorrelation, at a lag of at most `max_lag` (capped at a third of the length, so that
/// the period is seen three times), that reaches `min_correlation` after the
/// autocorrelation has fallen to half of it (a slowly decaying correlation is no period).
/// The first such peak is the fundamental: its multiples peak too, higher or lower.
pub fn period(x: &[f64], max_lag: usize, min_correlation: f64) -> Option<Period> {
    let max_lag = max_lag.min(x.len() / 3);
    if max_lag < 3 {
        return None;
    }
    let rho = autocorrelation(x, max_lag + 1)?;
    let mut lowest = f64::INFINITY;
    for k in 2..=max_lag.min(rho.len() - 2) {
        lowest = lowest.min(rho[k - 1]);
        let peak = rho[k] >= rho[k - 1] && rho[k] >= rho[k + 1];
        if peak && rho[k] >= min_correlation && lowest <= 0.5 * rho[k] {
            let (a, b, c) = (rho[k - 1], rho[k], rho[k + 1]);
            let curvature = a - 2.0 * b + c;
            let shift = if curvature < 0.0 {
                (0.5 * (a - c) / curvature).clamp(-0.5, 0.5)
            } else {
                0.0
            };
            return Some(Period {
                samples: k as f64 + shift,
                correlation: b,
            });
        }
    }
    None
}

/// The means of a sampled series over `count` consecutive whole stretches of `unit` (a
/// period, or one sampling interval) that end at `to`: the samples `(time, value)` with time
/// in (to − count·unit, to], each in stretch ⌊(time − from)/unit⌋ (its last instant belongs
/// to the stretch it ends). Stretches that hold no sample are left out.
pub fn unit_means(samples: &[(f64, f64)], to: f64, unit: f64, count: usize) -> Vec<f64> {
    let from = to - count as f64 * unit;
    let mut sums = vec![(0.0, 0usize); count];
    for &(t, v) in samples {
        if t > from && t <= to {
            let j = (((t - from) / unit).ceil() as usize).clamp(1, count) - 1;
            sums[j].0 += v;
            sums[j].1 += 1;
        }
    }
    sums.into_iter()
        .filter(|(_, c)| *c > 0)
        .map(|(s, c)| s / c as f64)
        .collect()
}

/// MSER truncation (White 1997; MSER-m of White, Cobb & Spratt 2000): the number of leading
/// samples of `x` to drop as warm-up, d\* = argmin_d (1/(n − d)²) Σ_{i ≥ d} (x_i − x̄_d)²,
/// evaluated on the means of `batch` consecutive samples (m = 5 is the usual choice) and over
/// the first half of the record only (a minimum later than that means the record has not
/// settled; the half is then returned).
pub fn mser_truncation(x: &[f64], batch: usize) -> usize {
    let b = batch.max(1);
    let y: Vec<f64> = x.chunks_exact(b).map(mean).collect();
    let n = y.len();
    if n < 4 {
        return 0;
    }
    // suffix sums of y and y², so each candidate costs O(1)
    let (mut s1, mut s2) = (vec![0.0; n + 1], vec![0.0; n + 1]);
    for i in (0..n).rev() {
        s1[i] = s1[i + 1] + y[i];
        s2[i] = s2[i + 1] + y[i] * y[i];
    }
    let score = |d: usize| {
        let m = (n - d) as f64;
        (s2[d] - s1[d] * s1[d] / m).max(0.0) / (m * m)
    };
    let half = n / 2;
    let best = (0..=half)
        .min_by(|a, b| score(*a).total_cmp(&score(*b)))
        .unwrap_or(0);
    best * b
}

/// The mean of a series with its confidence interval from batch means (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MeanInterval {
    pub mean: f64,
    /// Half-width of the interval at `level`, in the units of the mean (`None`: fewer than
    /// [`MIN_BATCHES`] batches as long as the correlation; the record is too short).
    pub half_width: Option<f64>,
    pub level: f64,
    /// Batches the interval rests on.
    pub batches: usize,
    /// Units (whole periods, or samples) per batch.
    pub units_per_batch: usize,
    /// Units in the record.
    pub units: usize,
    /// Integrated autocorrelation time of the units, in units.
    pub autocorrelation_time: f64,
    /// The change of the batch means across the record by their least-squares line, with
    /// its interval (`None` without an interval).
    #[serde(default)]
    pub drift: Option<Drift>,
}

/// The change of a record's batch means from its start to its end along their least-squares
/// line, and the half-width of its interval at the mean's level (units of the mean).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Drift {
    pub change: f64,
    pub half_width: f64,
}

impl Drift {
    /// The least-squares line through `batches` (equally spaced, in order): b·β̂ with
    /// half-width t(1 − α/2; b − 2)·b·s_res/√S_xx, s_res² = Σ residual²/(b − 2).
    fn of(batches: &[f64], level: f64) -> Option<Drift> {
        let b = batches.len();
        if b < 3 {
            return None;
        }
        let xm = (b - 1) as f64 / 2.0;
        let ym = mean(batches);
        let sxx: f64 = (0..b).map(|i| (i as f64 - xm).powi(2)).sum();
        let sxy: f64 = batches
            .iter()
            .enumerate()
            .map(|(i, y)| (i as f64 - xm) * (y - ym))
            .sum();
        let slope = sxy / sxx;
        let residual: f64 = batches
            .iter()
            .enumerate()
            .map(|(i, y)| (y - ym - slope * (i as f64 - xm)).powi(2))
            .sum();
        let se = (residual / (b - 2) as f64 / sxx).sqrt();
        Some(Drift {
            change: slope * b as f64,
            half_width: t_factor(level, (b - 2) as f64) * se * b as f64,
        })
    }

    /// Whether the change is significant at the level (the interval excludes zero).
    pub fn significant(&self) -> bool {
        self.change.abs() > self.half_width
    }
}

impl MeanInterval {
    /// The half-width relative to |mean| (`None` without an interval or for a zero mean).
    pub fn relative(&self) -> Option<f64> {
        self.half_width
            .filter(|_| self.mean != 0.0)
            .map(|h| h / self.mean.abs())
    }

    /// The standard error of the mean, s_b/√b (`None` without an interval).
    pub fn standard_error(&self) -> Option<f64> {
        let dof = self.batches.saturating_sub(1) as f64;
        self.half_width.map(|h| h / t_factor(self.level, dof))
    }

    /// Whether the record's batch means drift significantly ([`Drift`]): the mean is that of
    /// a record still settling.
    pub fn drifting(&self) -> bool {
        self.drift.is_some_and(|d| d.significant())
    }

    /// Whether `value` lies inside the interval (false without one).
    pub fn covers(&self, value: f64) -> bool {
        self.half_width
            .is_some_and(|h| (value - self.mean).abs() <= h)
    }
}

/// The mean of `units` and its `level` interval from batch means: batches of at least
/// ⌈τ⌉ units and at most [`MAX_BATCHES`] of them (the last b·k units; the few left over at
/// the start are the oldest and are dropped from the batches, not from the mean's record),
/// an interval only from [`MIN_BATCHES`] batches on. The mean is that of the batched units.
pub fn batch_means(units: &[f64], level: f64) -> MeanInterval {
    let m = units.len();
    let tau = integrated_autocorrelation_time(units);
    let k_min = (tau.ceil() as usize).max(1);
    let b = (m / k_min).min(MAX_BATCHES);
    if b < MIN_BATCHES {
        return MeanInterval {
            mean: mean(units),
            half_width: None,
            level,
            batches: b,
            units_per_batch: k_min,
            units: m,
            autocorrelation_time: tau,
            drift: None,
        };
    }
    let k = m / b;
    let batches: Vec<f64> = units[m - b * k..].chunks_exact(k).map(mean).collect();
    let grand = mean(&batches);
    let var = batches.iter().map(|v| (v - grand).powi(2)).sum::<f64>() / (b - 1) as f64;
    MeanInterval {
        mean: grand,
        half_width: Some(t_factor(level, (b - 1) as f64) * (var / b as f64).sqrt()),
        level,
        batches: b,
        units_per_batch: k,
        units: m,
        autocorrelation_time: tau,
        drift: Drift::of(&batches, level),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal, StudentT};

    #[test]
    fn t_factors_are_the_tabulated_ones() {
        // two-sided 95 %: t(0.975; 1) = 12.706, (9) = 2.262, (∞) → 1.960
        assert!((t_factor(0.95, 1.0) - 12.7062).abs() < 1e-3);
        assert!((t_factor(0.95, 9.0) - 2.2622).abs() < 1e-3);
        assert!((t_factor(0.95, 1e6) - 1.95996).abs() < 1e-3);
    }

    #[test]
    fn the_period_of_a_sawtooth_is_found_and_a_staircase_has_none() {
        let saw: Vec<f64> = (0..600).map(|k| (k as f64 / 17.3).fract()).collect();
        let p = period(&saw, 200, 0.3).expect("a period").samples;
        assert!((p - 17.3).abs() < 0.5, "{p}");
        let stairs: Vec<f64> = (0..600).map(|k| (k / 100) as f64).collect();
        assert_eq!(period(&stairs, 200, 0.3), None);
    }

    #[test]
    fn mser_drops_a_warm_up_ramp() {
        // 100 samples rising to the level, then 900 at it with noise
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let x: Vec<f64> = (0..1000)
            .map(|k| (k.min(100) as f64) / 100.0 * 50.0 + rng.gen_range(-1.0..1.0))
            .collect();
        let d = mser_truncation(&x, 5);
        assert!((80..=140).contains(&d), "{d}");
    }

    /// Samples k = 0..n at times k + 1 (each the end of its sampling interval).
    fn timed(x: &[f64]) -> Vec<(f64, f64)> {
        x.iter()
            .enumerate()
            .map(|(k, v)| ((k + 1) as f64, *v))
            .collect()
    }

    #[test]
    fn unit_means_average_whole_periods_ending_with_the_record() {
        let x: Vec<f64> = (0..10).map(|k| k as f64).collect();
        // three units of 3 samples ending at t = 10: the first sample is left out
        assert_eq!(unit_means(&timed(&x), 10.0, 3.0, 3), vec![2.0, 5.0, 8.0]);
        assert_eq!(unit_means(&timed(&x), 10.0, 1.0, 10), x);
    }

    /// AR(1) noise of unit variance.
    fn ar1(n: usize, rho: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
        let s = (1.0 - rho * rho).sqrt();
        let mut v = 0.0;
        (0..n)
            .map(|_| {
                let e: f64 = StandardNormal.sample(rng);
                v = rho * v + s * e;
                v
            })
            .collect()
    }

    /// Records with a known mean 0, of length `n`: the kinds a cut or a friction trace gives.
    fn record(kind: usize, n: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
        match kind {
            // white noise
            0 => (0..n)
                .map(|_| rng.sample::<f64, _>(StandardNormal))
                .collect(),
            // strongly correlated noise
            1 => ar1(n, 0.9, rng),
            // a serrated chip's sawtooth of random period and phase on correlated noise
            2 => {
                let p = rng.gen_range(10.0..25.0);
                let phase = rng.gen_range(0.0..1.0);
                let noise = ar1(n, 0.5, rng);
                (0..n)
                    .map(|k| 3.0 * ((k as f64 / p + phase).fract() - 0.5) + noise[k])
                    .collect()
            }
            // heavy tails (t with 3 degrees of freedom) on correlated noise
            _ => {
                let t = StudentT::new(3.0).expect("dof");
                let noise = ar1(n, 0.7, rng);
                (0..n).map(|k| 0.5 * t.sample(rng) + noise[k]).collect()
            }
        }
    }

    #[test]
    fn the_interval_covers_the_true_mean_at_its_level() {
        for kind in 0..4 {
            for n in [400usize, 1500] {
                let mut rng = ChaCha8Rng::seed_from_u64(1000 * kind as u64 + n as u64);
                let (mut covered, mut formed) = (0usize, 0usize);
                for _ in 0..300 {
                    let x = record(kind, n, &mut rng);
                    let unit = period(&x, n / 3, 0.3).map_or(1.0, |p| p.samples);
                    let count = (n as f64 / unit).floor() as usize;
                    let ci = batch_means(&unit_means(&timed(&x), n as f64, unit, count), LEVEL);
                    if ci.half_width.is_some() {
                        formed += 1;
                        covered += ci.covers(0.0) as usize;
                    }
                }
                let share = covered as f64 / formed as f64;
                assert!(
                    formed >= 250,
                    "kind {kind}, n {n}: {formed} intervals formed"
                );
                assert!(
                    (0.90..=0.99).contains(&share),
                    "kind {kind}, n {n}: coverage {share:.3} of {formed}"
                );
            }
        }
    }

    /// Records of every kind with a linear drift of known size d added (d = 0 in a third of
    /// them): the drift's interval covers the true change of the batched stretch at its level,
    /// and a stationary record is called drifting about as often as the level allows.
    #[test]
    fn the_drift_interval_covers_the_true_change_at_its_level() {
        let (mut covered, mut formed, mut false_alarms, mut stationary) = (0, 0, 0, 0);
        let mut rng = ChaCha8Rng::seed_from_u64(61);
        for trial in 0..1200 {
            let (kind, n) = (trial % 4, [400usize, 1500][trial / 4 % 2]);
            let d = if trial % 3 == 0 {
                0.0
            } else {
                rng.gen_range(-2.0..2.0)
            };
            let x: Vec<f64> = record(kind, n, &mut rng)
                .into_iter()
                .enumerate()
                .map(|(k, v)| v + d * k as f64 / n as f64)
                .collect();
            let unit = period(&x, n / 3, 0.3).map_or(1.0, |p| p.samples);
            let count = (n as f64 / unit).floor() as usize;
            let ci = batch_means(&unit_means(&timed(&x), n as f64, unit, count), LEVEL);
            let Some(drift) = ci.drift else { continue };
            formed += 1;
            let span = (ci.batches * ci.units_per_batch) as f64 * unit;
            let truth = d * span / n as f64;
            covered += ((drift.change - truth).abs() <= drift.half_width) as usize;
            if d == 0.0 {
                stationary += 1;
                false_alarms += ci.drifting() as usize;
            }
        }
        let share = covered as f64 / formed as f64;
        assert!(formed >= 1000, "{formed} drifts formed");
        assert!(
            (0.90..=0.99).contains(&share),
            "coverage {share:.3} of {formed}"
        );
        let alarms = false_alarms as f64 / stationary as f64;
        assert!(
            alarms <= 0.10,
            "{alarms:.3} of {stationary} stationary records drifting"
        );
        // and a drift several times the scatter is seen
        let mut rng = ChaCha8Rng::seed_from_u64(62);
        let x: Vec<f64> = (0..1000)
            .map(|k| rng.sample::<f64, _>(StandardNormal) + 3.0 * k as f64 / 1000.0)
            .collect();
        let ci = batch_means(&x, LEVEL);
        assert!(ci.drifting(), "{ci:?}");
    }

    #[test]
    fn too_short_a_record_gives_no_interval() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let x = ar1(30, 0.95, &mut rng);
        let ci = batch_means(&x, LEVEL);
        assert_eq!(ci.half_width, None);
        assert!(ci.batches < MIN_BATCHES);
    }
}
