//! Small robust signal-processing helpers used by plateau detection.

use greybox_core::stats::median;

/// Robust standard deviation: 1.4826 × median |x − center| (consistent for Gaussian noise).
pub fn mad_sigma(values: &[f64], center: f64) -> f64 {
    let dev: Vec<f64> = values.iter().map(|v| (v - center).abs()).collect();
    1.4826 * median(&dev)
}

/// Running median with a centered window of `2 h + 1` samples (shrinking at the edges).
pub fn running_median(x: &[f64], h: usize) -> Vec<f64> {
    let n = x.len();
    // A half-window past the slice's length covers the same samples as one of its length.
    let h = h.min(n);
    let mut out = Vec::with_capacity(n);
    let mut buf = Vec::with_capacity(2 * h + 1);
    for i in 0..n {
        let lo = i.saturating_sub(h);
        let hi = (i + h + 1).min(n);
        buf.clear();
        buf.extend_from_slice(&x[lo..hi]);
        let mid = buf.len() / 2;
        let (_, m, _) = buf.select_nth_unstable_by(mid, f64::total_cmp);
        out.push(*m);
    }
    out
}

/// Hampel outlier mask: `true` where |x − running median| > k · σ (Pearson 2002, "Outliers
/// in process modeling"), with σ the **local** robust spread of the residuals: their MAD over
/// the block of [`hampel_block`]`(h)` samples around each sample (a trace whose noise grows
/// along the test keeps its noisy part; one spread for the whole file would mask it as
/// spikes), at least the channel's quantisation step (a quantised trace whose residuals are
/// mostly 0 would otherwise lose every sample off the median).
pub fn hampel_outliers(x: &[f64], h: usize, k: f64) -> Vec<bool> {
    let rm = running_median(x, h);
    let resid: Vec<f64> = x.iter().zip(&rm).map(|(a, b)| a - b).collect();
    let floor = quantum(x).max(1e-12);
    let l = hampel_block(h);
    let sigmas: Vec<f64> = resid
        .chunks(l)
        .map(|c| mad_sigma(c, 0.0).max(floor))
        .collect();
    resid
        .iter()
        .enumerate()
        .map(|(i, r)| r.abs() > k * sigmas[i / l])
        .collect()
}

/// Samples per block of the Hampel filter's local noise estimate at half window `h`: 20
/// windows, at least 200 samples (enough for a MAD, short against a change of noise level).
pub fn hampel_block(h: usize) -> usize {
    (20 * (2 * h + 1)).max(200)
}

/// Centered moving average over `w` samples (shrinking at the edges).
pub fn moving_average(x: &[f64], w: usize) -> Vec<f64> {
    let n = x.len();
    let h = w / 2;
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0);
    for v in x {
        prefix.push(prefix.last().copied().unwrap_or(0.0) + v);
    }
    (0..n)
        .map(|i| {
            let lo = i.saturating_sub(h);
            let hi = (i + h + 1).min(n);
            (prefix[hi] - prefix[lo]) / (hi - lo) as f64
        })
        .collect()
}

/// Least-squares line y = a + b t. Returns (a, b, standard error of b).
pub fn linear_fit(t: &[f64], y: &[f64]) -> (f64, f64, f64) {
    let n = t.len() as f64;
    let tm = t.iter().sum::<f64>() / n;
    let ym = y.iter().sum::<f64>() / n;
    let sxx: f64 = t.iter().map(|ti| (ti - tm).powi(2)).sum();
    let sxy: f64 = t.iter().zip(y).map(|(ti, yi)| (ti - tm) * (yi - ym)).sum();
    if sxx <= 0.0 || n < 3.0 {
        return (ym, 0.0, f64::INFINITY);
    }
    let b = sxy / sxx;
    let a = ym - b * tm;
    let rss: f64 = t
        .iter()
        .zip(y)
        .map(|(ti, yi)| (yi - a - b * ti).powi(2))
        .sum();
    let se = (rss / (n - 2.0) / sxx).sqrt();
    (a, b, se)
}

/// Mean and sample standard deviation.
pub fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let var = if x.len() > 1 {
        x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (m, var.sqrt())
}

/// The quantisation step of a recorded channel: the smallest non-zero change between
/// consecutive samples (0 for a constant channel).
pub fn quantum(raw: &[f64]) -> f64 {
    let q = raw
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    if q.is_finite() {
        q
    } else {
        0.0
    }
}

/// Block medians of `x` over blocks of `b` samples.
pub fn block_medians(x: &[f64], b: usize) -> Vec<f64> {
    x.chunks(b).map(median).collect()
}

/// Two levels of a signal that switches between them (a normal force loaded and unloaded).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TwoLevels {
    /// Median of the lower class.
    pub low: f64,
    /// Median of the upper class.
    pub high: f64,
    /// The split between the classes.
    pub split: f64,
    /// Robust spread (MAD σ) of each class about its median: noise and slow drift.
    pub low_sigma: f64,
    pub high_sigma: f64,
    /// Share of the values in the lower class.
    pub low_share: f64,
}

/// The two levels of `x` by Otsu's criterion (Otsu 1979, "A threshold selection method from
/// gray-level histograms"): the split maximising the between-class variance, searched over
/// 256 thresholds between the 0.5 % and 99.5 % quantiles, with the values clipped to that
/// range first so that a few far outliers (a load cell's negative blips at lift-off, a spike)
/// neither form a class nor drag one. `None` for fewer than 4 values or a constant signal.
pub fn two_levels(x: &[f64]) -> Option<TwoLevels> {
    if x.len() < 4 {
        return None;
    }
    let mut v: Vec<f64> = x.iter().copied().filter(|v| v.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n < 4 {
        return None;
    }
    let q = |p: f64| v[((n - 1) as f64 * p).round() as usize];
    let (lo, hi) = (q(0.005), q(0.995));
    if !(hi > lo) {
        return None;
    }
    let c: Vec<f64> = v.iter().map(|x| x.clamp(lo, hi)).collect();
    let mut prefix = Vec::with_capacity(n + 1);
    prefix.push(0.0);
    for x in &c {
        prefix.push(prefix.last().copied().unwrap_or(0.0) + x);
    }
    let total = prefix[n];
    let mut best = (f64::NEG_INFINITY, lo);
    for g in 1..256 {
        let t = lo + (hi - lo) * g as f64 / 256.0;
        let k = c.partition_point(|x| *x <= t);
        if k == 0 || k == n {
            continue;
        }
        let (w0, w1) = (k as f64 / n as f64, (n - k) as f64 / n as f64);
        let (m0, m1) = (prefix[k] / k as f64, (total - prefix[k]) / (n - k) as f64);
        let between = w0 * w1 * (m1 - m0).powi(2);
        if between > best.0 {
            best = (between, t);
        }
    }
    let split = best.1;
    let k = v.partition_point(|x| *x <= split).clamp(1, n - 1);
    let (low, high) = (median(&v[..k]), median(&v[k..]));
    Some(TwoLevels {
        low,
        high,
        split,
        low_sigma: mad_sigma(&v[..k], low),
        high_sigma: mad_sigma(&v[k..], high),
        low_share: k as f64 / n as f64,
    })
}

/// Contiguous runs of `true`: `[start, end)`.
pub fn runs(mask: &[bool]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (k, m) in mask.iter().enumerate() {
        match (m, start) {
            (true, None) => start = Some(k),
            (false, Some(s)) => {
                out.push((s, k));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, mask.len()));
    }
    out
}

/// The dominant period of `x` in samples, from its autocorrelation (Wiener–Khinchin, via a
/// real FFT zero-padded to twice the length): among the lags in `[2, max_lag]` where the
/// autocorrelation of `x` about its slow trend (a moving average over `2 max_lag + 1`
/// samples, so that level steps do not count as periodic content) peaks above
/// `min_correlation` after having fallen below half that peak (a real oscillation, not the
/// slow decay of a smooth signal), the strongest, or the shortest that divides it nearly as
/// strongly (its fundamental), and around which `x` repeats in place. `max_lag` is capped at a third of the length, so that a
/// period found is seen at least three times; `None` when no lag qualifies.
///
/// Used to find a rig's revolution or stroke period in a friction trace (once-per-revolution
/// dips, run-out), over which the signal is then averaged.
pub fn dominant_period(x: &[f64], max_lag: usize, min_correlation: f64) -> Option<usize> {
    let n = x.len();
    let max_lag = max_lag.min(n / 3);
    if max_lag < 2 {
        return None;
    }
    let trend = moving_average(x, 2 * max_lag + 1);
    let hp: Vec<f64> = x.iter().zip(&trend).map(|(v, t)| v - t).collect();
    let acf = autocorrelation(&hp, max_lag)?;
    // every qualifying peak: a local maximum above min_correlation after a fall below half
    // its height, around which x repeats in place
    let mut peaks = Vec::new();
    let mut lowest = f64::INFINITY;
    for lag in 2..max_lag {
        lowest = lowest.min(acf[lag - 1]);
        let peak = acf[lag] >= acf[lag - 1] && acf[lag] >= acf[lag + 1];
        if peak && acf[lag] >= min_correlation && lowest <= 0.5 * acf[lag] {
            peaks.push(lag);
        }
    }
    // the fundamental: the strongest peak, or the shortest lag that divides it (within a
    // lag) with at least 80 % of its correlation (a true period correlates at its multiples
    // alike); a side peak of a revolution's harmonics (0.3 s on a disc
    // turning every 0.76 s) neither divides the revolution nor correlates as well
    let &best = peaks.iter().max_by(|a, b| acf[**a].total_cmp(&acf[**b]))?;
    peaks
        .iter()
        .copied()
        .filter(|&l| {
            let k = (best as f64 / l as f64).round();
            l == best
                || (k >= 2.0
                    && (k * l as f64 - best as f64).abs() <= 1.0 + 0.02 * best as f64
                    && acf[l] >= 0.8 * acf[best])
        })
        .find(|&l| repeats_in_place(x, l))
}

/// Whether `x` one `lag` later is, on average, where it was: the mean of x[k + lag] − x[k]
/// is under half their standard deviation. A revolution's dips or run-out repeat around one
/// level; a staircase of regularly timed steps also correlates at its step length, but moves
/// by a step each time, and is no period to average over.
fn repeats_in_place(x: &[f64], lag: usize) -> bool {
    let d: Vec<f64> = x.windows(lag + 1).map(|w| w[lag] - w[0]).collect();
    let (mean, std) = mean_std(&d);
    mean.abs() <= 0.5 * std
}

/// Normalised autocorrelation of `x` (its mean removed) at lags `0..=max_lag`; `None` for a
/// constant series.
pub fn autocorrelation(x: &[f64], max_lag: usize) -> Option<Vec<f64>> {
    use realfft::RealFftPlanner;
    let n = x.len();
    let m = x.iter().sum::<f64>() / n.max(1) as f64;
    let size = (2 * n).next_power_of_two();
    let mut planner = RealFftPlanner::<f64>::new();
    let fwd = planner.plan_fft_forward(size);
    let inv = planner.plan_fft_inverse(size);
    let mut buf = fwd.make_input_vec();
    for (b, v) in buf.iter_mut().zip(x) {
        *b = v - m;
    }
    let mut spec = fwd.make_output_vec();
    fwd.process(&mut buf, &mut spec).ok()?;
    for c in spec.iter_mut() {
        *c = realfft::num_complex::Complex::new(c.norm_sqr(), 0.0);
    }
    let mut out = inv.make_output_vec();
    inv.process(&mut spec, &mut out).ok()?;
    let zero = out[0];
    if !(zero > 0.0) {
        return None;
    }
    Some(
        out[..=max_lag.min(n - 1)]
            .iter()
            .map(|v| v / zero)
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A revolution of 76 samples with a once-per-turn dip and a strong third harmonic (three
    /// bumps a turn): the first correlation peak is at a third of the turn, the revolution
    /// is the period.
    #[test]
    fn the_period_is_the_revolution_not_a_side_peak() {
        let x: Vec<f64> = (0..3000)
            .map(|k| {
                let turn = (k % 76) as f64 / 76.0;
                let dip = if turn < 0.08 { -1.0 } else { 0.0 };
                let vib = 0.8 * (std::f64::consts::TAU * 3.0 * k as f64 / 76.0).sin();
                dip + vib + 0.05 * ((k * 7919 % 97) as f64 / 48.0 - 1.0)
            })
            .collect();
        assert_eq!(dominant_period(&x, 200, 0.3), Some(76));
    }

    /// A half-window far past the data (a spike window of 10⁹ s in a study) is the whole
    /// slice: the same medians, without a buffer of 2·10¹² samples.
    #[test]
    fn a_half_window_past_the_data_is_the_whole_slice() {
        let x = [5.0, 1.0, 4.0, 2.0, 3.0, 9.0];
        assert_eq!(
            running_median(&x, usize::MAX / 4),
            running_median(&x, x.len())
        );
        assert_eq!(running_median(&x, 6), vec![4.0, 4.0, 4.0, 4.0, 4.0, 4.0]);
    }

    #[test]
    fn basics() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        let x: Vec<f64> = (0..50).map(|i| (i as f64 * 0.7).sin() * 0.01).collect();
        let mut y = x.clone();
        y[20] += 5.0;
        let m = hampel_outliers(&y, 5, 6.0);
        assert!(m[20] && m.iter().filter(|b| **b).count() == 1);
        let t: Vec<f64> = (0..10).map(|i| i as f64).collect();
        let y: Vec<f64> = t.iter().map(|v| 2.0 + 0.5 * v).collect();
        let (a, b, _) = linear_fit(&t, &y);
        assert!((a - 2.0).abs() < 1e-12 && (b - 0.5).abs() < 1e-12);
        assert_eq!(moving_average(&[1.0, 2.0, 3.0], 3), vec![1.5, 2.0, 2.5]);
    }
}
