//! Where a loaded recording slides, from the signals' physics rather than fixed fractions of
//! the raw friction signal.
//!
//! * **With a measured speed channel** (one that varies: a constant stated with
//!   `constant_sliding_m_s` is no evidence of motion), a loaded block slides while its speed
//!   is above rest ([`speed_rest_level`]: `speed_rest_fraction` of the channel's largest
//!   block speed, or five times its block-to-block noise if that is more).
//! * **Without one**, the friction coefficient μ = F_t/F_N of the loaded blocks (10 ms block
//!   medians) is first smoothed (a running median) over the rig's own period — the revolution of a disc or the
//!   stroke of a reciprocating rig, found as the dominant lag of μ's autocorrelation
//!   ([`crate::signal::dominant_period`], up to `max_period_s`) — and over at least
//!   `sliding_smoothing_s`. Averaging over exactly one period removes once-per-revolution
//!   dips and run-out however deep they are, and the smoothing removes white noise, so that a
//!   low-friction step (μ 0.04 beside 0.12) is not cut into pieces by its own noise. A loaded
//!   block then slides while the smoothed μ exceeds the larger of `sliding_fraction` × the
//!   smoothed μ's 75th percentile over the loaded blocks and `sliding_min_mu`.
//!
//! The period found also sets the shortest step the segmentation accepts (three periods, or
//! `min_segment_s` if longer) and the block length of the change-point search, so that every
//! block averages whole revolutions. All thresholds are settings of
//! [`crate::identify::IdentifyConfig`] (docs/recordings.md, "Sliding and steps").

use crate::identify::IdentifyConfig;
use crate::recording::SpeedTrace;
use crate::signal::{dominant_period, median};
use serde::Serialize;

/// What decided which loaded samples slide.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SlidingEvidence {
    /// A measured speed channel above rest.
    SpeedChannel,
    /// μ averaged over the rig's period (or the smoothing time) above its threshold.
    Friction,
}

impl SlidingEvidence {
    pub fn name(self) -> &'static str {
        match self {
            SlidingEvidence::SpeedChannel => "speed channel",
            SlidingEvidence::Friction => "friction",
        }
    }
}

/// Which samples slide, and what the signal showed on the way.
#[derive(Debug, Clone)]
pub(crate) struct Sliding {
    /// Per sample: loaded and sliding.
    pub mask: Vec<bool>,
    pub evidence: SlidingEvidence,
    /// The rig's period found in μ, s (revolution or stroke), if any.
    pub period_s: Option<f64>,
    /// The μ threshold used (friction evidence only).
    pub mu_threshold: Option<f64>,
}

/// Block layout of a recording: `b` samples per block, `loaded` per block.
pub(crate) struct Blocks<'a> {
    pub b: usize,
    pub loaded: &'a [bool],
    pub fs: f64,
}

/// A speed channel that varies (a constant one was stated, not measured).
pub(crate) fn measured_speed(speed: Option<&SpeedTrace>) -> Option<&[f64]> {
    let v = speed?.values();
    let first = *v.first()?;
    v.iter().any(|x| *x != first).then_some(v)
}

/// The speed below which a channel is at rest, from its block values `vb`: the larger of
/// `speed_rest_fraction` of its largest magnitude (a Stribeck sweep spans decades: 0.1 %
/// keeps a 0.01 m/s step of a 1 m/s sweep) and five times the block-to-block noise (robust
/// σ of first differences / √2), so that a channel jittering at rest does not slide.
pub(crate) fn speed_rest_level(vb: &[f64], cfg: &IdentifyConfig) -> f64 {
    let vmax = vb.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let d: Vec<f64> = vb.windows(2).map(|w| w[1].abs() - w[0].abs()).collect();
    let noise = if d.len() >= 4 {
        crate::signal::mad_sigma(&d, 0.0) / std::f64::consts::SQRT_2
    } else {
        0.0
    };
    (cfg.speed_rest_fraction * vmax).max(5.0 * noise)
}

/// Which loaded samples slide (see the module documentation).
pub(crate) fn sliding(
    speed: Option<&SpeedTrace>,
    fn_c: &[f64],
    ft_c: &[f64],
    blocks: &Blocks,
    cfg: &IdentifyConfig,
) -> Sliding {
    let n = fn_c.len();
    let per_sample = |per_block: &[bool]| (0..n).map(|k| per_block[k / blocks.b]).collect();
    let mu = block_mu(fn_c, ft_c, blocks);
    let period = friction_period(&mu, blocks, cfg);
    let period_s = period.map(|p| p as f64 * blocks.b as f64 / blocks.fs);
    if let Some(v) = measured_speed(speed) {
        let vb: Vec<f64> = v
            .chunks(blocks.b)
            .map(|c| median(&c.iter().map(|x| x.abs()).collect::<Vec<_>>()))
            .collect();
        let rest = speed_rest_level(&vb, cfg);
        let mask: Vec<bool> = (0..vb.len())
            .map(|k| blocks.loaded[k] && vb[k] > rest)
            .collect();
        return Sliding {
            mask: per_sample(&mask),
            evidence: SlidingEvidence::SpeedChannel,
            period_s,
            mu_threshold: None,
        };
    }
    let smoothing = ((cfg.sliding_smoothing_s * blocks.fs / blocks.b as f64).ceil() as usize)
        .max(period.unwrap_or(1))
        .max(1);
    let smooth = smooth_loaded(&mu, blocks.loaded, smoothing);
    let loaded_mu: Vec<f64> = (0..mu.len())
        .filter(|k| blocks.loaded[*k])
        .map(|k| smooth[k])
        .collect();
    let typical = quantile(&loaded_mu, 0.75);
    let thr = (cfg.sliding_fraction * typical).max(cfg.sliding_min_mu);
    let mut mask: Vec<bool> = (0..mu.len())
        .map(|k| blocks.loaded[k] && smooth[k] > thr)
        .collect();
    sharpen_ends(&mut mask, &mu, thr);
    Sliding {
        mask: per_sample(&mask),
        evidence: SlidingEvidence::Friction,
        period_s,
        mu_threshold: Some(thr),
    }
}

/// The smoothing blurs a sharp start or stop by half its window: each sliding run's ends
/// are moved in to the first and last block whose own μ exceeds the threshold (dips inside
/// the run stay averaged over).
fn sharpen_ends(mask: &mut [bool], mu: &[f64], thr: f64) {
    for (a, e) in crate::signal::runs(mask) {
        let first = (a..e).find(|k| mu[*k] > thr).unwrap_or(e);
        let last = (a..e).rev().find(|k| mu[*k] > thr).map_or(a, |k| k + 1);
        for k in (a..first).chain(last.max(first)..e) {
            mask[k] = false;
        }
    }
}

/// μ per block (block medians of F_t over those of F_N), 0 where unloaded.
fn block_mu(fn_c: &[f64], ft_c: &[f64], blocks: &Blocks) -> Vec<f64> {
    fn_c.chunks(blocks.b)
        .zip(ft_c.chunks(blocks.b))
        .enumerate()
        .map(|(k, (f, t))| {
            if blocks.loaded[k] {
                median(t) / median(f).max(1e-12)
            } else {
                0.0
            }
        })
        .collect()
}

/// The dominant period of μ over the loaded blocks (in blocks), up to `max_period_s`.
fn friction_period(mu: &[f64], blocks: &Blocks, cfg: &IdentifyConfig) -> Option<usize> {
    let loaded: Vec<f64> = (0..mu.len())
        .filter(|k| blocks.loaded[*k])
        .map(|k| mu[k])
        .collect();
    let max_lag = (cfg.max_period_s * blocks.fs / blocks.b as f64) as usize;
    dominant_period(&loaded, max_lag, cfg.period_min_correlation)
}

/// Centred running median of `x` over `w` blocks within each loaded run (unloaded blocks
/// neither contribute nor receive a value: they stay 0). A median, not a mean: one sample of
/// a heavy-tailed noise (or a spike) far below zero must not make a sliding stretch look
/// stopped, and a once-per-revolution dip shorter than half the period is outvoted.
fn smooth_loaded(x: &[f64], loaded: &[bool], w: usize) -> Vec<f64> {
    let mut out = vec![0.0; x.len()];
    for (a, e) in crate::signal::runs(loaded) {
        let s = crate::signal::running_median(&x[a..e], w / 2);
        out[a..e].copy_from_slice(&s);
    }
    out
}

/// The `q` quantile of `x` (nearest rank; NaN when empty).
pub(crate) fn quantile(x: &[f64], q: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut v = x.to_vec();
    let k = ((v.len() - 1) as f64 * q).round() as usize;
    *v.select_nth_unstable_by(k, f64::total_cmp).1
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blocks(loaded: &[bool]) -> Blocks<'_> {
        Blocks {
            b: 1,
            loaded,
            fs: 100.0,
        }
    }

    /// Sliding of a 100 Hz friction force `ft` under a constant, always loaded 100 N, no
    /// speed channel, default settings.
    fn sliding_of(ft: &[f64]) -> Sliding {
        let fn_c = vec![100.0; ft.len()];
        let loaded = vec![true; ft.len()];
        sliding(
            None,
            &fn_c,
            ft,
            &blocks(&loaded),
            &IdentifyConfig::default(),
        )
    }

    #[test]
    fn once_per_revolution_dips_do_not_cut_the_slide() {
        // 100 Hz, 60 s at μ 0.3 with a dip to 20 % of μ for 50 ms once per 1.3 s revolution
        let n = 6000;
        let ft_c: Vec<f64> = (0..n)
            .map(|k| if k % 130 < 5 { 6.0 } else { 30.0 })
            .collect();
        let s = sliding_of(&ft_c);
        // one slide; only the dip the recording starts in lies before its first block
        assert_eq!(
            crate::signal::runs(&s.mask),
            vec![(5, n)],
            "dips cut the slide"
        );
        let p = s.period_s.expect("the revolution is found");
        assert!((p - 1.3).abs() < 0.011, "{p}");
    }

    #[test]
    fn a_staircase_of_regular_steps_is_no_period() {
        // 9 steps of 0.8 s at 100 Hz, μ falling by 0.01 a step, a little noise
        let ft: Vec<f64> = (0..720)
            .map(|k| 30.0 - (k / 80) as f64 + 0.1 * (((k * 7919) % 13) as f64 / 6.0 - 1.0))
            .collect();
        let s = sliding_of(&ft);
        assert_eq!(s.period_s, None);
    }

    #[test]
    fn a_noisy_low_friction_step_stays_sliding_and_a_stop_does_not() {
        // μ 0.12 for 20 s, at rest (μ 0) 2 s, μ 0.04 ± 0.02 (uniform-ish) for 20 s
        let mut ft = vec![12.0; 2000];
        ft.extend(vec![0.0; 200]);
        ft.extend((0..2000).map(|k| 4.0 + 2.0 * (((k * 7919) % 13) as f64 / 6.0 - 1.0)));
        let s = sliding_of(&ft);
        let pieces = crate::signal::runs(&s.mask);
        assert_eq!(pieces.len(), 2, "{pieces:?}");
    }

    #[test]
    fn a_measured_speed_channel_decides_and_a_stated_one_does_not() {
        let n = 1000;
        let fn_c = vec![100.0; n];
        let ft_c = vec![30.0; n];
        let loaded = vec![true; n];
        let v: Vec<f64> = (0..n).map(|k| if k < 300 { 0.0 } else { 1.0 }).collect();
        let cfg = IdentifyConfig::default();
        let s = sliding(
            Some(&SpeedTrace::SlidingMPerS(v)),
            &fn_c,
            &ft_c,
            &blocks(&loaded),
            &cfg,
        );
        assert_eq!(s.evidence, SlidingEvidence::SpeedChannel);
        assert_eq!(s.mask.iter().filter(|m| **m).count(), 700);
        let stated = SpeedTrace::SlidingMPerS(vec![1.0; n]);
        let s = sliding(Some(&stated), &fn_c, &ft_c, &blocks(&loaded), &cfg);
        assert_eq!(s.evidence, SlidingEvidence::Friction);
    }
}
