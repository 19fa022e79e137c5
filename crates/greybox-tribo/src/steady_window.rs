//! What one step's samples give: spike masking, the smoothed friction signal, the steady
//! window found from the signal, and the plateau's statistics and quality flags.
//!
//! Shared by the plan-timed path ([`crate::plan_timing`]) and the plan-free segmentation
//! ([`crate::campaign`]).

use crate::config::{IdentifyConfig, SteadyRule};

use crate::signal::{
    hampel_outliers, linear_fit, mad_sigma, mean_std, moving_average, running_median,
};
use crate::uncertainty::WindowMean;
use greybox_core::dataset::flags;
use greybox_core::stats::median;

/// The friction signal of one window of samples `[i, j)`.
pub struct StepSignals {
    /// First sample of the window.
    pub i: usize,
    /// F_t / F_N per sample.
    pub mu: Vec<f64>,
    /// False where a spike was masked in either force.
    pub good: Vec<bool>,
    /// μ with spikes replaced by the running median, then a moving average over
    /// `smoothing_s`.
    pub smooth: Vec<f64>,
    /// Smoothing window, samples.
    pub w_smooth: usize,
}

/// Spike half window and smoothing window in samples at sample rate `fs`.
pub fn windows(cfg: &IdentifyConfig, fs: f64) -> (usize, usize) {
    let h_spike = ((cfg.spike_half_window_s * fs).round() as usize).max(2);
    let w_smooth = ((cfg.smoothing_s * fs).round() as usize).max(3);
    (h_spike, w_smooth)
}

/// Mask spikes (Hampel filter on both forces) and smooth μ over `[i, j)`. `check_force(k,
/// f_n)` is called for every unmasked sample and may reject a non-physical normal force.
pub fn step_signals<E>(
    fn_c: &[f64],
    ft_c: &[f64],
    i: usize,
    j: usize,
    cfg: &IdentifyConfig,
    fs: f64,
    mut check_force: impl FnMut(usize, f64) -> Result<(), E>,
) -> Result<StepSignals, E> {
    let (h_spike, w_smooth) = windows(cfg, fs);
    let outl_n = hampel_outliers(&fn_c[i..j], h_spike, cfg.spike_threshold_sigma);
    let outl_t = hampel_outliers(&ft_c[i..j], h_spike, cfg.spike_threshold_sigma);
    let mut mu = Vec::with_capacity(j - i);
    let mut good = Vec::with_capacity(j - i);
    for k in 0..(j - i) {
        let f_n = fn_c[i + k];
        let is_spike = outl_n[k] || outl_t[k];
        if !is_spike {
            check_force(i + k, f_n)?;
        }
        mu.push(ft_c[i + k] / f_n);
        good.push(!is_spike);
    }
    let rm = running_median(&mu, h_spike);
    let clean: Vec<f64> = mu
        .iter()
        .zip(&good)
        .zip(&rm)
        .map(|((m, g), r)| if *g { *m } else { *r })
        .collect();
    let smooth = moving_average(&clean, w_smooth);
    Ok(StepSignals {
        i,
        mu,
        good,
        smooth,
        w_smooth,
    })
}

/// Level and tolerance band of a smoothed signal over `part`: the median, and the larger of
/// five robust standard deviations and `floor`.
pub fn level_band(part: &[f64], floor: f64) -> (f64, f64) {
    let level = median(part);
    let sigma = mad_sigma(part, level).max(1e-4 * level.abs().max(1e-9));
    (level, (5.0 * sigma).max(floor))
}

/// The steady part `[a, b)` (window-relative) of a segment whose ends may hold ramps,
/// run-in or settling: the level and band come from the middle half of each signal; the
/// steady part starts after the last sample of the first half outside the band and ends
/// before the first sample of the second half outside it, for every signal. `None` when
/// nothing is left.
pub fn steady_span(signals: &[(&[f64], f64)], w_smooth: usize) -> Option<(usize, usize)> {
    let n = signals.first()?.0.len();
    if n < 8 {
        return None;
    }
    let (mut a, mut b) = (0usize, n);
    let min_run = w_smooth.max(3);
    for (x, floor) in signals {
        let (level, band) = level_band(&x[n / 4..(3 * n) / 4], *floor);
        let out = sustained_excursions(x, level, band, min_run);
        if let Some(k) = out[..n / 2].iter().rposition(|o| *o) {
            a = a.max(k + 1 + w_smooth / 2);
        }
        if let Some(k) = out[n / 2..].iter().position(|o| *o) {
            b = b.min((n / 2 + k).saturating_sub(w_smooth / 2));
        }
    }
    (b > a).then_some((a, b))
}

/// Samples outside `level ± band` that belong to a run of at least `min_run` such samples:
/// a ramp, a run-in or a settling is sustained, a glitch of a jittering or quantised channel
/// (a 1 Hz speed channel's odd sample) is not, and must not cut a 30-minute test short.
fn sustained_excursions(x: &[f64], level: f64, band: f64, min_run: usize) -> Vec<bool> {
    let mut out: Vec<bool> = x.iter().map(|v| (v - level).abs() > band).collect();
    let mut k = 0;
    while k < out.len() {
        if !out[k] {
            k += 1;
            continue;
        }
        let end = (k..out.len()).find(|&e| !out[e]).unwrap_or(out.len());
        if end - k < min_run {
            out[k..end].iter_mut().for_each(|o| *o = false);
        }
        k = end;
    }
    out
}

/// The final stationary stretch of a step's μ and the run-in before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinalStretch {
    /// Window-relative start of the steady part (after the run-in and the running level's
    /// half window).
    pub a: usize,
    /// Window-relative end (exclusive) of the steady part (before a transition at the end).
    pub b: usize,
    /// Window-relative sample where μ's running level enters, and stays in, the final
    /// stretch's band; 0 without a run-in.
    pub run_in_end: usize,
}

/// The final stationary stretch of the smoothed μ `x` sampled at (window-relative) times `t`,
/// s, following ASTM G99-17 §3.2/§9 and G133-05 §9 practice: the steady-state value comes
/// after the run-in, from the end of the test.
///
/// μ's running level is a centred moving average over w = max(`w_smooth`, n/50) samples. The
/// band is five standard deviations of that level's own noise over the last quarter
/// ([`level_noise`]: from its changes over one window, so that a slow excursion — a run-in's
/// tail, a swing of μ between two steps — is measured against the noise, not counted in it;
/// at least `floor`). The steady part is the longest final stretch (searched on
/// a grid of [`SUFFIX_GRID`] starts, at least n/4 samples long) whose level stays within the
/// band of a line fitted to that stretch (excursions shorter than the running window, stick-slip
/// bursts, aside), a line changing by at most [`MAX_DRIFT_FRACTION`]
/// of the level (or two bands) over it: a slow drift tilts the line, not the window, and a
/// test whose μ still moves in its second half (a wear transition) gets its last stationary
/// stretch rather than none. The run-in is what comes before it. `None` for fewer than 16
/// samples, or when even the last n/4 samples do not lie on a line within the band.
pub fn final_stationary(x: &[f64], t: &[f64], w_smooth: usize, floor: f64) -> Option<FinalStretch> {
    let n = x.len();
    if n < 16 || t.len() != n {
        return None;
    }
    let w = w_smooth.max(n / 50).max(3);
    let level = moving_average(x, w);
    let band = (5.0 * level_noise(&level[(3 * n) / 4..], w)).max(floor);
    let min_len = (n / 4).max(8);
    let on_a_line = |a: usize| {
        let (c0, c1, _) = linear_fit(&t[a..], &level[a..]);
        let mean = level[a..].iter().sum::<f64>() / (n - a) as f64;
        let change = (c1 * (t[n - 1] - t[a])).abs();
        let resid: Vec<f64> = (a..n).map(|k| level[k] - c0 - c1 * t[k]).collect();
        // forgiven: short excursions inside the stretch, never at its start (the run-in's tail)
        let head = resid.len().min(w);
        change <= (2.0 * band).max(MAX_DRIFT_FRACTION * mean.abs())
            && resid[..head].iter().all(|r| r.abs() <= band)
            && !sustained_excursions(&resid, 0.0, band, w).contains(&true)
    };
    let start = (0..=SUFFIX_GRID)
        .map(|g| g * (n - min_len) / SUFFIX_GRID)
        .find(|&a| on_a_line(a))?;
    let a = if start > 0 {
        (start + w / 2).min(n - min_len)
    } else {
        0
    };
    Some(FinalStretch {
        a,
        b: n,
        run_in_end: start,
    })
}

/// How a steady stretch was found ([`steady_stretch`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Settling {
    /// μ settled: its final stationary stretch ([`final_stationary`]).
    Settled,
    /// μ never settles: no final stretch lies on a line within its band. The stretch is the
    /// record after its warm-up (MSER-5), its mean reported with its trend.
    NeverSettles,
    /// Fewer than 16 values: too few to tell a run-in from the steady state; all are taken.
    TooShort,
}

impl Settling {
    /// Why the stretch is not a settled steady state (`None` when it is), for the reports.
    pub fn reason(self, n: usize, what: &str) -> Option<String> {
        match self {
            Settling::Settled => None,
            Settling::NeverSettles => Some(format!(
                "μ never settles (no final stretch of its {n} {what} lies on a line within its band): the mean after the warm-up (MSER-5), with its trend, and an interval that counts the wander"
            )),
            Settling::TooShort => Some(format!(
                "only {n} {what}, too few to tell a run-in from the steady state (16 needed): all of them averaged"
            )),
        }
    }
}

/// The steady stretch of a series `x` at times `t` — the one steady-state rule of greybox's
/// friction identification, for a continuous test's samples and a reciprocating test's
/// cycles alike: the final stationary stretch where μ settles ([`final_stationary`]);
/// where it never settles, the record after the warm-up that MSER-5 truncates
/// ([`greybox_core::stats::mser_truncation`], White 1997 — the rule greybox-sim applies to a
/// simulated cut), never a refusal; below 16 values, all of them, said so.
pub fn steady_stretch(
    x: &[f64],
    t: &[f64],
    w_smooth: usize,
    floor: f64,
) -> (FinalStretch, Settling) {
    let n = x.len();
    if n < 16 {
        let all = FinalStretch {
            a: 0,
            b: n,
            run_in_end: 0,
        };
        return (all, Settling::TooShort);
    }
    match final_stationary(x, t, w_smooth, floor) {
        Some(f) => (f, Settling::Settled),
        None => {
            let d = greybox_core::stats::mser_truncation(x, 5);
            let f = FinalStretch {
                a: d,
                b: n,
                run_in_end: d,
            };
            (f, Settling::NeverSettles)
        }
    }
}

/// The standard deviation of a running level `level` (a moving average over `w` samples):
/// the robust (MAD) spread of its changes over `w` samples — two windows that share no
/// sample — about their median (a steady drift's constant change), over √2. Where the
/// stretch is shorter than two windows, the robust spread of its residuals about a line.
pub fn level_noise(level: &[f64], w: usize) -> f64 {
    if level.len() < 2 * w + 8 {
        let t: Vec<f64> = (0..level.len()).map(|k| k as f64).collect();
        let (c0, c1, _) = linear_fit(&t, level);
        let resid: Vec<f64> = (0..level.len())
            .map(|k| level[k] - c0 - c1 * t[k])
            .collect();
        return mad_sigma(&resid, 0.0);
    }
    let d: Vec<f64> = (w..level.len()).map(|k| level[k] - level[k - w]).collect();
    mad_sigma(&d, median(&d)) / std::f64::consts::SQRT_2
}

/// The most μ may drift across a steady stretch, as a fraction of its level: a slow drift
/// (a few per cent over the test) is reported as a trend; a change of more than a tenth is a
/// transition (wear of a coating, a new mechanism), not a steady state.
pub const MAX_DRIFT_FRACTION: f64 = 0.1;

/// Starts tried for the final stationary stretch, evenly over the step (a 1 h test at 1 Hz:
/// every 25 s).
const SUFFIX_GRID: usize = 128;

/// Window-relative samples `[a, b)` of a step of `n` samples at times `t` (s, from the step's
/// start) under a user's rule: `last:P%` the last P % of the samples, `from:Ts` the samples
/// at or after T s. `Ok(None)` under [`SteadyRule::Auto`] (found from the signal).
///
/// A rule that cannot be honoured is never replaced by `auto`: `from:500s` on a 198 s segment,
/// or a window of fewer than `min_samples` (`last:0.01%` of 198 s is 0.02 s), is an error
/// naming the rule, the segment's length and what the window would hold. `what` names the
/// samples in it ("samples", "cycles").
pub fn rule_span(
    rule: SteadyRule,
    t: &[f64],
    min_samples: usize,
    what: &str,
) -> Result<Option<(usize, usize)>, String> {
    let n = t.len();
    let length = match (t.first(), t.last()) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    let a = match rule {
        SteadyRule::Auto => return Ok(None),
        SteadyRule::Last(p) => n - ((p * n as f64).round() as usize).min(n),
        SteadyRule::From(s) => match t.iter().position(|v| *v - t[0] >= s - 1e-9) {
            Some(a) => a,
            None => {
                return Err(format!(
                    "the steady rule {rule} starts after the end of the segment, which lasts {length:.1} s \
                     (give a start below {length:.1} s, a last:P% rule or auto)"
                ))
            }
        },
    };
    let held = n - a;
    if held < min_samples.max(1) {
        let span = if held > 0 { t[n - 1] - t[a] } else { 0.0 };
        return Err(format!(
            "the steady rule {rule} of a {length:.1} s segment is {span:.3} s ({held} {what}), \
             fewer than the {} {what} a steady window needs (min_plateau_samples)",
            min_samples.max(1)
        ));
    }
    Ok(Some((a, n)))
}

pub use crate::uncertainty::mean_standard_error;

/// Statistics of one plateau.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateauStats {
    pub mean: f64,
    pub std: f64,
    pub n_samples: usize,
    /// First and last sample used, s relative to `t_ref`.
    pub start_s: f64,
    pub end_s: f64,
    pub trend_per_s: f64,
    pub stationary: bool,
    /// `trend`, `stick-slip`, `spikes-removed` as found.
    pub flags: Vec<String>,
    /// Samples of the window masked as spikes.
    pub spikes: usize,
    /// μ's mean over the window with its uncertainty under serial correlation
    /// ([`crate::uncertainty::WindowMean`]).
    pub interval: WindowMean,
    /// Half-width of μ's 95 % interval, as reported: the window's own
    /// (`interval.half_width_95`), widened where the window's boundaries are uncertain.
    pub ci95: f64,
    /// Mean measured normal force over the samples used, N.
    pub normal_force_n: f64,
    /// What `ci95` is made of, where another window's interval may share a part (the two
    /// passes of a bidirectional test); `None` where it was not built from them.
    pub parts: Option<IntervalParts>,
}

/// The parts of a window's 95 % interval of μ (see the campaign's `measure`): the window's
/// own statistics, the baseline's errors, and the widening for uncertain boundaries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntervalParts {
    /// The window's mean with its standard error under serial correlation (with the run's
    /// disturbance as a floor).
    pub window: WindowMean,
    /// The normal channel's baseline error in μ, μ·se(F_N offset)/F_N.
    pub normal_offset: f64,
    /// The friction channel's baseline errors at the start and end windows, in μ
    /// (se/F_N each), and where this window lies between them (λ from 0 at the start window
    /// to 1 at the end window; `None`: one window, a constant offset).
    pub tangential_offset: (f64, f64, Option<f64>),
    /// μ's change when the window's ends move by their boundaries' uncertainty.
    pub shift: f64,
}

/// Where a plateau sits in the campaign: pin and step, the plan's load if any, the sliding
/// velocity (m/s), and the row's flags.
pub struct PlateauPlace {
    pub pin: u32,
    pub step: u32,
    pub planned_n: Option<f64>,
    pub velocity_m_s: f64,
    pub flags: Vec<String>,
    /// What placed the row on its step ([`greybox_core::dataset::label_evidence`]).
    pub label_evidence: Option<&'static str>,
}

impl PlateauStats {
    /// The dataset row: the measured load is the row's load and gives its Hertz pressure
    /// under `contact`'s convention; the plan's load beside it.
    pub fn record(
        &self,
        contact: &greybox_contact::PinContact,
        at: PlateauPlace,
    ) -> greybox_core::Result<greybox_core::dataset::FrictionRecord> {
        Ok(greybox_core::dataset::FrictionRecord {
            pin: at.pin,
            step: at.step,
            normal_force_n: self.normal_force_n,
            normal_force_planned_n: at.planned_n,
            sliding_velocity_m_s: at.velocity_m_s,
            hertz_pressure_pa: contact.pressure_pa(self.normal_force_n)?,
            pressure_convention: contact.convention,
            cof_apparent: self.mean,
            cof_apparent_std: self.std,
            cof_apparent_ci95: Some(self.ci95),
            n_samples: self.n_samples as u64,
            plateau_start_s: self.start_s,
            plateau_end_s: self.end_s,
            cof_trend_per_s: self.trend_per_s,
            stationary: self.stationary,
            flags: at.flags,
            label_evidence: at.label_evidence.map(String::from),
            cof_adhesive: None,
        })
    }
}

/// Statistics over the window-relative samples `[pi, pj)` of `sig`: mean and standard
/// deviation of F_t/F_N over the unmasked samples, the mean's 95 % interval under serial
/// correlation ([`WindowMean`]; a drift inflates it, as slow correlated content), linear
/// trend (flag `trend` when the change over the plateau exceeds the tolerance and four
/// standard errors), a saw-tooth of slow rises and sudden drops ([`stick_slip`], flag
/// `stick-slip`), and
/// whether the masked spikes matter (flag `spikes-removed` when μ with them differs by more
/// than the interval's half-width). `None` when fewer than `min_plateau_samples` unmasked
/// samples remain.
pub fn plateau_stats(
    time: &[f64],
    fn_c: &[f64],
    sig: &StepSignals,
    pi: usize,
    pj: usize,
    t_ref: f64,
    cfg: &IdentifyConfig,
) -> Option<PlateauStats> {
    let i = sig.i;
    // A plateau reaching past the step's window (margins longer than the step) is cut to it.
    let pj = pj.min(sig.good.len());
    let pi = pi.min(pj);
    let idx: Vec<usize> = (pi..pj).filter(|k| sig.good[*k]).collect();
    if idx.len() < cfg.min_plateau_samples.max(2) {
        return None;
    }
    let spikes = (pi..pj).filter(|k| !sig.good[*k]).count();
    let mut fl = Vec::new();
    let vals: Vec<f64> = idx.iter().map(|k| sig.mu[*k]).collect();
    let interval = WindowMean::of(&vals)?;
    if spikes > 0 && spikes_matter(&sig.mu[pi..pj], interval) {
        fl.push(flags::SPIKES_REMOVED.to_string());
    }
    let times: Vec<f64> = idx.iter().map(|k| time[i + k] - t_ref).collect();
    let (mean, std) = mean_std(&vals);
    let (_, slope, se) = linear_fit(&times, &vals);
    let duration = times[times.len() - 1] - times[0];
    let trend = (slope * duration).abs() > cfg.trend_tolerance && slope.abs() > 4.0 * se;
    let stick = stick_slip(&vals, cfg.stick_slip_threshold);
    if trend {
        fl.push(flags::TREND.to_string());
    }
    if stick {
        fl.push(flags::STICK_SLIP.to_string());
    }
    let f_meas = idx.iter().map(|k| fn_c[i + k]).sum::<f64>() / idx.len() as f64;
    Some(PlateauStats {
        mean,
        std,
        n_samples: idx.len(),
        start_s: times[0],
        end_s: times[times.len() - 1],
        trend_per_s: slope,
        stationary: !trend && !stick,
        flags: fl,
        spikes,
        interval,
        ci95: interval.half_width_95,
        normal_force_n: f_meas,
        parts: None,
    })
}

/// Whether masking changed μ by more than its interval: the mean of every finite sample of
/// the window `all` against the interval's mean (a spike that would move μ is worth a look;
/// a few masked blips that do not are noise the filter handled).
fn spikes_matter(all: &[f64], interval: WindowMean) -> bool {
    let finite: Vec<f64> = all.iter().copied().filter(|v| v.is_finite()).collect();
    let with = finite.iter().sum::<f64>() / finite.len().max(1) as f64;
    !((with - interval.mean).abs() <= interval.half_width_95)
}

/// Whether μ over a window (`x`, its unmasked samples in order) holds stick-slip: a
/// saw-tooth of slow rises (the contact sticks and the spring loads) and sudden drops (it
/// slips), told from noise and from a slow wander by the drops alone, relative to the local
/// noise. For each lag L ∈ {1, 2, 4, 8} samples (a slip spread over up to L samples), the
/// increments d_k = x_{k+L} − x_k have a robust spread σ_L (MAD about their median, at least
/// the quantisation step); a **slip** is a cluster of d_k < −6σ_L, a **sudden rise** a
/// cluster of d_k > +6σ_L. Stick-slip: at some lag, at least three slips, more than three
/// times as many slips as sudden rises (noise, heavy-tailed or not, jumps both ways; spikes
/// rise and fall), and a median drop of at least `min_drop` (a smaller saw-tooth moves the
/// mean by less than half of that). A wander, however large, is slow: its increments over a
/// few samples stay inside the noise.
pub fn stick_slip(x: &[f64], min_drop: f64) -> bool {
    const K: f64 = 6.0;
    let q = crate::signal::quantum(x);
    [1usize, 2, 4, 8].into_iter().any(|lag| {
        if x.len() < 8 * lag {
            return false;
        }
        let d: Vec<f64> = x.windows(lag + 1).map(|w| w[lag] - w[0]).collect();
        let sigma = mad_sigma(&d, median(&d)).max(q);
        let events = |sel: &dyn Fn(f64) -> bool| -> Vec<f64> {
            let mut out: Vec<(usize, f64)> = Vec::new();
            for (k, v) in d.iter().enumerate().filter(|(_, v)| sel(**v)) {
                match out.last_mut() {
                    Some(e) if k <= e.0 + lag => {
                        e.0 = k;
                        e.1 = if v.abs() > e.1.abs() { *v } else { e.1 };
                    }
                    _ => out.push((k, *v)),
                }
            }
            out.into_iter().map(|e| e.1.abs()).collect()
        };
        let slips = events(&|v| v < -K * sigma);
        let rises = events(&|v| v > K * sigma);
        slips.len() >= 3 && slips.len() > 3 * rises.len() && median(&slips) >= min_drop
    })
}
