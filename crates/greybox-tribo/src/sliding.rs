//! Where a loaded recording slides, and in which direction, from the signals' physics rather
//! than fixed fractions of the raw friction signal. Sliding is decided from the magnitudes
//! |F_t| and |μ|, never from the sign of μ: a reverse pass slides as much as a forward one.
//!
//! * **With a measured speed channel** (one that varies: a constant stated with
//!   `constant_sliding_m_s` is no evidence of motion), a loaded block slides while its speed
//!   is above rest ([`speed_rest_level`]: `speed_rest_fraction` of the channel's largest
//!   block speed, or five times its block-to-block noise if that is more).
//! * **Without one**, from the friction force F_t (10 ms block medians of the loaded blocks,
//!   signed), smoothed by a running median over the rig's own period — the revolution of a
//!   disc or the stroke of a reciprocating rig, found as the dominant lag of μ's
//!   autocorrelation ([`crate::signal::dominant_period`], up to `max_period_s`) — and over at
//!   least `sliding_smoothing_s`. Averaging over exactly one period removes once-per-revolution
//!   dips and run-out however deep they are, and the median removes noise and spikes. A slide
//!   starts where the smoothed |F_t| stands out of the noise a loaded contact at rest would
//!   show — more than `sliding_rest_sigmas` local standard deviations of the smoothed force
//!   ([`local_noise`]: from its changes over one smoothing window, per stretch of a few
//!   seconds, robust to the level changes between steps), and at least `sliding_min_mu` ×
//!   F_N — and lasts while it stays above [`HOLD_FRACTION`] of that threshold (a hysteresis:
//!   a noisy low-friction step is not cut by its own noise; a stop falls to rest). The same
//!   test over [`LONG_SCALE`] smoothing windows (at least a second), against that smoothing's
//!   own smaller noise, starts and holds a slide too weak to stand out in one window (μ 0.004
//!   under a noisy load cell); a stop shorter than half of it is then bridged, and the
//!   level-change split finds it.
//!   The test is on the force, not on μ = F_t/F_N, so that the noise of a load ramp's small
//!   F_N does not pass for sliding; no share of a "typical" μ enters, so a Stribeck sweep
//!   whose μ falls from 0.12 to 0.004 slides on every one of its steps.
//! * **Direction**: the sign of the smoothed friction force where it stands out of the same
//!   rest threshold — the friction force opposes the motion, so its sign is the direction of
//!   sliding; where it does not (passing through zero at a reversal), the direction before.
//!   A change of sign is a **reverse pass** ([`Sliding::direction`]; the campaign measures
//!   each pass on its own), however short: a reciprocating rig's strokes are passes too short
//!   for a step, never one slide of mixed sign.
//!
//! The period found also sets the shortest step the segmentation accepts (three periods, or
//! `min_segment_s` if longer) and the block length of the change-point search, so that every
//! block averages whole revolutions. All thresholds are settings of
//! [`crate::config::IdentifyConfig`] (docs/recordings.md, "Sliding and steps").

use crate::config::IdentifyConfig;
use crate::signal::dominant_period;
use greybox_core::stats::median;
use greybox_recording::SpeedTrace;
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
    /// The rest threshold on |F_t| (its median over the loaded blocks), N (friction
    /// evidence only).
    pub rest_threshold_n: Option<f64>,
    /// Per sample: the direction of sliding as recorded (+1: F_t positive, −1: negative), 0
    /// where the sample does not slide.
    pub direction: Vec<i8>,
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

/// Which loaded samples slide, and in which direction (see the module documentation).
pub(crate) fn sliding(
    speed: Option<&SpeedTrace>,
    fn_c: &[f64],
    ft_c: &[f64],
    blocks: &Blocks,
    cfg: &IdentifyConfig,
) -> Sliding {
    let n = fn_c.len();
    let mu = block_mu(fn_c, ft_c, blocks);
    let period = friction_period(&mu, blocks, cfg);
    let period_s = period.map(|p| p as f64 * blocks.b as f64 / blocks.fs);
    let smoothing = ((cfg.sliding_smoothing_s * blocks.fs / blocks.b as f64).ceil() as usize)
        .max(period.unwrap_or(1))
        .max(1);
    let loaded = blocks.loaded;
    let fb: Vec<f64> = fn_c.chunks(blocks.b).map(median).collect();
    let ftb: Vec<f64> = ft_c
        .chunks(blocks.b)
        .enumerate()
        .map(|(k, c)| if loaded[k] { median(c) } else { 0.0 })
        .collect();
    // the smoothed friction force, signed, and the rest threshold on its magnitude: the
    // level a loaded contact at rest does not leave (its local noise), and at least
    // `sliding_min_mu` of the load
    let signed = smooth_loaded(&ftb, loaded, smoothing);
    let noise = local_noise(&signed, loaded, smoothing);
    let thr: Vec<f64> = (0..fb.len())
        .map(|k| (cfg.sliding_rest_sigmas * noise[k]).max(cfg.sliding_min_mu * fb[k].abs()))
        .collect();
    let stands_out = |k: usize| loaded[k] && signed[k].abs() > thr[k];
    let (mask, evidence) = match measured_speed(speed) {
        Some(v) => {
            let vb: Vec<f64> = v
                .chunks(blocks.b)
                .map(|c| median(&c.iter().map(|x| x.abs()).collect::<Vec<_>>()))
                .collect();
            let rest = speed_rest_level(&vb, cfg);
            let mask: Vec<bool> = (0..vb.len()).map(|k| loaded[k] && vb[k] > rest).collect();
            (mask, SlidingEvidence::SpeedChannel)
        }
        None => {
            // hysteresis: a slide starts where the force stands out of the rest threshold and
            // lasts while it stays above a fifth of it (a noisy low-friction step whose force
            // is a few thresholds is not cut by a dip of its noise; a stop falls to rest)
            // over ten smoothing windows (at least a second), a slide too weak to stand out in
            // one (μ 0.004 under a noisy load cell) stands out of its own, smaller noise
            let long_w = LONG_SCALE * smoothing;
            let long = smooth_loaded(&ftb, loaded, long_w);
            let long_noise = local_noise(&long, loaded, long_w);
            let long_out = |k: usize| {
                loaded[k]
                    && long[k].abs()
                        > (cfg.sliding_rest_sigmas * long_noise[k])
                            .max(cfg.sliding_min_mu * fb[k].abs())
            };
            let high: Vec<bool> = (0..fb.len())
                .map(|k| stands_out(k) || long_out(k))
                .collect();
            let low: Vec<bool> = (0..fb.len())
                .map(|k| (loaded[k] && signed[k].abs() > HOLD_FRACTION * thr[k]) || long_out(k))
                .collect();
            let mut mask = hysteresis(&high, &low);
            let own: Vec<bool> = (0..fb.len()).map(|k| ftb[k].abs() > thr[k]).collect();
            sharpen_ends(&mut mask, &own);
            (mask, SlidingEvidence::Friction)
        }
    };
    let decided: Vec<i8> = (0..fb.len())
        .map(|k| match (stands_out(k), signed[k] < 0.0) {
            (false, _) => 0,
            (true, true) => -1,
            (true, false) => 1,
        })
        .collect();
    let dir = block_directions(&mask, &decided);
    let loaded_thr: Vec<f64> = (0..fb.len())
        .filter(|k| loaded[*k])
        .map(|k| thr[k])
        .collect();
    Sliding {
        mask: (0..n).map(|k| mask[k / blocks.b]).collect(),
        evidence,
        period_s,
        rest_threshold_n: (evidence == SlidingEvidence::Friction && !loaded_thr.is_empty())
            .then(|| median(&loaded_thr)),
        direction: (0..n).map(|k| dir[k / blocks.b]).collect(),
    }
}

/// A slide lasts while the smoothed friction force stays above this share of the rest
/// threshold (Schmitt trigger: it starts only above the threshold itself).
pub const HOLD_FRACTION: f64 = 0.4;

/// The second, longer smoothing of the friction force, in smoothing windows.
pub const LONG_SCALE: usize = 10;

/// Runs of `low` that hold at least one `high` (a hysteresis of two thresholds).
fn hysteresis(high: &[bool], low: &[bool]) -> Vec<bool> {
    let mut out = vec![false; low.len()];
    for (a, e) in crate::signal::runs(low) {
        if high[a..e].iter().any(|h| *h) {
            out[a..e].iter_mut().for_each(|m| *m = true);
        }
    }
    out
}

/// The local standard deviation of a smoothed series `x` (running medians over `w` blocks)
/// per block: over chunks of max(20 w, 200) blocks, the robust (MAD) spread of its changes
/// over `w` blocks — two windows that share no block — over √2, between loaded blocks. A step
/// change of the level is an outlier among those changes and leaves σ alone; a slow wander
/// adds to it only what it moves in one window; a chunk at rest has the rest noise, a chunk
/// sliding at a high load its friction noise (one σ for a file of 10 N and 1000 N steps would
/// take the light step for a rest). A chunk with fewer than 8 changes takes the file's.
pub(crate) fn local_noise(x: &[f64], loaded: &[bool], w: usize) -> Vec<f64> {
    let diffs = |a: usize, b: usize| -> Vec<f64> {
        (a.max(w)..b)
            .filter(|k| loaded[*k] && loaded[k - w])
            .map(|k| x[k] - x[k - w])
            .collect()
    };
    let sigma = |d: &[f64]| crate::signal::mad_sigma(d, 0.0) / std::f64::consts::SQRT_2;
    let all = diffs(0, x.len());
    let global = if all.len() >= 8 { sigma(&all) } else { 0.0 };
    let l = (20 * w).max(200);
    let mut out = Vec::with_capacity(x.len());
    for a in (0..x.len()).step_by(l) {
        let b = (a + l).min(x.len());
        let d = diffs(a, b);
        let s = if d.len() >= 8 { sigma(&d) } else { global };
        out.extend(std::iter::repeat_n(s, b - a));
    }
    out
}

/// Per block: +1 or −1 where `mask` slides, 0 elsewhere: the sign `decided` where the
/// smoothed friction force stands out of its rest threshold; a sliding block where it does
/// not (the force passing through zero at a reversal) takes the sign of the decided block
/// before it (after it, at the start). A running median over at least 0.1 s cannot leave
/// the noise on a few samples, so every decided run is a pass of its own, however short (a
/// reciprocating rig's stroke).
fn block_directions(mask: &[bool], decided: &[i8]) -> Vec<i8> {
    let first = (0..mask.len())
        .find(|k| mask[*k] && decided[*k] != 0)
        .map_or(1, |k| decided[k]);
    let mut current = first;
    (0..mask.len())
        .map(|k| {
            if !mask[k] {
                return 0;
            }
            if decided[k] != 0 {
                current = decided[k];
            }
            current
        })
        .collect()
}

/// The smoothing blurs a sharp start or stop: each sliding run's ends are moved in to the
/// first and last block that stands out on its `own` (dips inside the run stay averaged
/// over).
fn sharpen_ends(mask: &mut [bool], own: &[bool]) {
    for (a, e) in crate::signal::runs(mask) {
        let first = (a..e).find(|k| own[*k]).unwrap_or(e);
        let last = (a..e).rev().find(|k| own[*k]).map_or(a, |k| k + 1);
        for k in (a..first).chain(last.max(first)..e) {
            mask[k] = false;
        }
    }
}

/// Signed μ per block (block medians of F_t over those of F_N), 0 where unloaded.
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
        // one slide: a dip to a fifth of μ still stands far out of the noise, even the one
        // the recording starts in
        assert_eq!(
            crate::signal::runs(&s.mask),
            vec![(0, n)],
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
