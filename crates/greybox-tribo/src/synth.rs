//! The virtual tribometer: raw recordings as a pin-on-disk rig on a lathe produces them.
//!
//! For each pin of a [`Plan`] it generates 1 kHz samples of the normal, tangential and
//! radial force and the recording-trigger voltage. Physics and sensor effects, in order:
//!
//! * NC timing: every S command takes effect after a spindle latency; the real spindle
//!   acceleration differs from the nominal one by a random factor, so real plateaus start
//!   earlier or later than the run sheet says (identification must find them);
//! * hydraulic normal load ramp-up and release (half-cosine, `load_rise_fraction` of the load time);
//! * friction F_t = μ(p, v) F_N with μ from a ground-truth [`FrictionLaw`] at the
//!   instantaneous sliding velocity, plus a run-in overshoot at the start of each pin that
//!   decays exponentially in time;
//! * spindle-synchronous oscillation: track run-out modulates F_N (and so F_t) at the
//!   rotation frequency and its harmonics; a smaller independent tangential vibration;
//! * charge-amplifier offset and linear drift per channel, white noise, and spikes
//!   (Poisson arrivals, 1–3 samples wide, random sign);
//! * optional stick-slip (sawtooth on μ) below a velocity.
//!
//! All randomness comes from ChaCha8 streams seeded by `seed` and the pin number: same
//! seed, same bytes.

use crate::plan::Plan;
use greybox_contact::hertz::PinContact;
use greybox_core::dataset::PressureConvention;
use greybox_core::rules::Compact;
use greybox_core::{units, ContactState, Error, FrictionLaw, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, Poisson};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A smooth ground-truth law calibrated on the article's statements (digest §1, pressures in
/// the article's eq.-7 convention p_a = p0 / 4^(1/3)):
///
/// μ = μ_ref · [1 − c_p (p_a − p_ref)/p_ref] · (max(v, v_s)/v_ref)^(−β), floored at `mu_min`.
///
/// Defaults (μ_ref = 0.41, p_ref = 1500 MPa, v_ref = 60 m/min, c_p = 0.738, β = 0.19) give
/// μ(1500 MPa, 60 → 160 m/min) = 0.41 → 0.34 and μ(2000 MPa, 60 → 80 m/min) = 0.31 → 0.29,
/// falling with both velocity and pressure. The contact state's pressure is the textbook p0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ArticleLikeLaw {
    pub mu_ref: f64,
    /// Reference pressure in the article's convention, MPa.
    pub pressure_ref_article_mpa: f64,
    pub velocity_ref_m_per_min: f64,
    /// Relative fall of μ per p_ref of pressure.
    pub pressure_slope: f64,
    /// Exponent of the velocity power law.
    pub velocity_exponent: f64,
    /// Velocities below this are evaluated at it (static/start-up friction), m/min.
    pub velocity_static_m_per_min: f64,
    pub mu_min: f64,
}

impl Default for ArticleLikeLaw {
    fn default() -> Self {
        ArticleLikeLaw {
            mu_ref: 0.41,
            pressure_ref_article_mpa: 1500.0,
            velocity_ref_m_per_min: 60.0,
            pressure_slope: 0.738,
            velocity_exponent: 0.19,
            velocity_static_m_per_min: 5.0,
            mu_min: 0.05,
        }
    }
}

impl FrictionLaw for ArticleLikeLaw {
    fn name(&self) -> String {
        "article-like ground truth".into()
    }
    fn mu(&self, s: &ContactState) -> f64 {
        let p_article_mpa = s.pressure_pa / 4f64.cbrt() / units::PA_PER_MPA;
        let v = units::m_per_s_to_m_per_min(s.sliding_velocity_m_s.abs())
            .max(self.velocity_static_m_per_min);
        let fp = 1.0
            - self.pressure_slope * (p_article_mpa - self.pressure_ref_article_mpa)
                / self.pressure_ref_article_mpa;
        let fv = (v / self.velocity_ref_m_per_min).powf(-self.velocity_exponent);
        (self.mu_ref * fp * fv).max(self.mu_min)
    }
}

/// Stick-slip injection.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StickSlip {
    /// Steps below this sliding velocity stick-slip, m/min.
    pub below_m_per_min: f64,
    /// Sawtooth amplitude relative to μ.
    pub amplitude_rel: f64,
    /// Sawtooth frequency, Hz.
    pub frequency_hz: f64,
}

/// Virtual tribometer settings (study TOML `[synth]`); defaults are documented per field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SynthConfig {
    /// Random seed (default 42).
    pub seed: u64,
    /// Sample rate, Hz (1000, as in the article).
    pub sample_rate_hz: f64,
    /// Acquisition time before the trigger edge, s (0.3).
    pub pre_trigger_s: f64,
    /// Acquisition time after the trigger falls, s (0.3).
    pub post_trigger_s: f64,
    /// Delay from an NC command to the drive's response, s (0.05) …
    pub latency_s: f64,
    /// … plus a uniform random part per pin of ± this, s (0.02).
    pub latency_jitter_s: f64,
    /// Real spindle acceleration = nominal × (1 + U(−e, e)) per pin (e = 0.10).
    pub spindle_accel_error: f64,
    /// Fraction of the load time the hydraulic load takes to rise or fall (0.5).
    pub load_rise_fraction: f64,
    /// White noise standard deviation of the normal channel, N (2.0).
    pub noise_normal_n: f64,
    /// … tangential channel, N (1.0).
    pub noise_tangential_n: f64,
    /// … radial channel, N (1.0).
    pub noise_radial_n: f64,
    /// Amplifier offset standard deviation per channel, N (2.0).
    pub offset_std_n: f64,
    /// Amplifier drift rate standard deviation per channel, N/s (0.05).
    pub drift_std_n_per_s: f64,
    /// Run-out modulation of F_N at 1×, 2×, 3× the rotation frequency, relative ([0.02, 0.008, 0.004]).
    pub runout_rel: Vec<f64>,
    /// Independent tangential vibration at the rotation harmonics, relative to F_t (0.002).
    pub tangential_vibration_rel: f64,
    /// Radial force as a fraction of F_N (0.05).
    pub radial_fraction: f64,
    /// Spike arrivals per second per channel (0.5).
    pub spike_rate_per_s: f64,
    /// Spike amplitude, N (40); each spike is ±U(0.5, 1) × this.
    pub spike_amplitude_n: f64,
    /// Run-in overshoot of μ at sliding start, relative (0.25) …
    pub run_in_rel: f64,
    /// … decaying with this time constant, s (0.1).
    pub run_in_time_s: f64,
    /// Optional stick-slip (off by default).
    pub stick_slip: Option<StickSlip>,
    /// Trigger high level, V (5).
    pub trigger_high_v: f64,
    /// Trigger channel noise, V (0.02).
    pub trigger_noise_v: f64,
    /// Multiplies noise, drift and spikes (amplitude and rate) together (1).
    pub disturbance_scale: f64,
    /// The ground-truth friction law.
    pub ground_truth: ArticleLikeLaw,
}

impl Default for SynthConfig {
    fn default() -> Self {
        SynthConfig {
            seed: 42,
            sample_rate_hz: 1000.0,
            pre_trigger_s: 0.3,
            post_trigger_s: 0.3,
            latency_s: 0.05,
            latency_jitter_s: 0.02,
            spindle_accel_error: 0.10,
            load_rise_fraction: 0.5,
            noise_normal_n: 2.0,
            noise_tangential_n: 1.0,
            noise_radial_n: 1.0,
            offset_std_n: 2.0,
            drift_std_n_per_s: 0.05,
            runout_rel: vec![0.02, 0.008, 0.004],
            tangential_vibration_rel: 0.002,
            radial_fraction: 0.05,
            spike_rate_per_s: 0.5,
            spike_amplitude_n: 40.0,
            run_in_rel: 0.25,
            run_in_time_s: 0.1,
            stick_slip: None,
            trigger_high_v: 5.0,
            trigger_noise_v: 0.02,
            disturbance_scale: 1.0,
            ground_truth: ArticleLikeLaw::default(),
        }
    }
}

/// The true μ of one plateau.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruthRow {
    pub pin: u32,
    pub step: u32,
    pub normal_force_n: f64,
    /// Planned velocity, m/s.
    pub sliding_velocity_m_s: f64,
    /// Velocity the commanded rpm really gives, m/s.
    pub actual_velocity_m_s: f64,
    /// Pressure under the contact's convention, Pa.
    pub hertz_pressure_pa: f64,
    pub pressure_convention: PressureConvention,
    pub cof_true: f64,
}

/// The ground truth's μ of a plateau, refused when it is not a finite number.
fn finite_cof(mu: f64, pin: u32, step: u32) -> Result<f64> {
    if mu.is_finite() {
        return Ok(mu);
    }
    Err(Error::invalid(
        "synth",
        format!(
            "[synth.ground_truth] gives μ = {mu} at pin {pin} step {step}: check its parameters"
        ),
    ))
}

/// Most samples of one synthetic pin recording (five channels of f64: 800 MB): a real rig
/// at 100 kHz for over three minutes, far above the article's 1 kHz.
const MAX_SAMPLES_PER_PIN: f64 = 2e7;

impl SynthConfig {
    fn validate(&self) -> Result<()> {
        greybox_core::rules::Rules::new("synth")
            .positive("sample_rate_hz", self.sample_rate_hz)
            .non_negative("pre_trigger_s", self.pre_trigger_s)
            .non_negative("post_trigger_s", self.post_trigger_s)
            .non_negative("latency_s", self.latency_s)
            .non_negative("latency_jitter_s", self.latency_jitter_s)
            .relation(
                (0.0..0.9).contains(&self.spindle_accel_error),
                format!(
                    "spindle_accel_error must be in [0, 0.9), got {}",
                    Compact(self.spindle_accel_error)
                ),
            )
            .above_up_to("load_rise_fraction", self.load_rise_fraction, 0.0, 1.0)
            .non_negative("noise_normal_n", self.noise_normal_n)
            .non_negative("noise_tangential_n", self.noise_tangential_n)
            .non_negative("noise_radial_n", self.noise_radial_n)
            .non_negative("offset_std_n", self.offset_std_n)
            .non_negative("drift_std_n_per_s", self.drift_std_n_per_s)
            .non_negative("tangential_vibration_rel", self.tangential_vibration_rel)
            .non_negative("radial_fraction", self.radial_fraction)
            .non_negative("spike_rate_per_s", self.spike_rate_per_s)
            .non_negative("spike_amplitude_n", self.spike_amplitude_n)
            .non_negative("run_in_rel", self.run_in_rel)
            .positive("run_in_time_s", self.run_in_time_s)
            .positive("trigger_high_v", self.trigger_high_v)
            .non_negative("trigger_noise_v", self.trigger_noise_v)
            .non_negative("disturbance_scale", self.disturbance_scale)
            .relation(
                self.runout_rel.iter().all(|v| v.is_finite() && *v >= 0.0),
                format!("runout_rel must be numbers ≥ 0, got {:?}", self.runout_rel),
            )
            .section("stick_slip", |r| {
                if let Some(s) = &self.stick_slip {
                    r.non_negative("below_m_per_min", s.below_m_per_min)
                        .non_negative("amplitude_rel", s.amplitude_rel)
                        .positive("frequency_hz", s.frequency_hz);
                }
            })
            .finish()
    }

    /// Ground truth for every plateau of the plan.
    pub fn ground_truth(&self, plan: &Plan, contact: &PinContact) -> Result<Vec<TruthRow>> {
        let radius = plan.track_radius_m();
        plan.steps
            .iter()
            .map(|s| {
                let p0 =
                    contact.pressure_pa_as(s.normal_force_n, PressureConvention::TextbookMax)?;
                let v = units::velocity_for_rpm(s.spindle_rpm, radius);
                Ok(TruthRow {
                    pin: s.pin,
                    step: s.step,
                    normal_force_n: s.normal_force_n,
                    sliding_velocity_m_s: s.sliding_velocity_m_s,
                    actual_velocity_m_s: v,
                    hertz_pressure_pa: contact.pressure_pa(s.normal_force_n)?,
                    pressure_convention: contact.convention,
                    cof_true: finite_cof(
                        self.ground_truth.mu(&ContactState::new(p0, v)),
                        s.pin,
                        s.step,
                    )?,
                })
            })
            .collect()
    }

    /// Simulate the raw recording of one pin (1-based).
    pub fn simulate_pin(
        &self,
        plan: &Plan,
        contact: &PinContact,
        pin: u32,
    ) -> Result<greybox_recording::Recording> {
        self.validate()?;
        let sched = plan
            .pins
            .get(pin as usize - 1)
            .ok_or_else(|| Error::invalid("synth", format!("no pin {pin} in the plan")))?;
        let steps = plan.pin_steps(pin);
        let spec = &plan.spec;
        let radius = plan.track_radius_m();
        let p0 = contact.pressure_pa_as(sched.normal_force_n, PressureConvention::TextbookMax)?;
        let mut rng =
            ChaCha8Rng::seed_from_u64(self.seed ^ (pin as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        let k = self.disturbance_scale;
        let dt = 1.0 / self.sample_rate_hz;
        let t_start = -self.pre_trigger_s;
        let t_end = sched.end_s + self.post_trigger_s;
        let n = self.sample_count(pin, t_end - t_start)?;

        let std_normal = Normal::new(0.0, 1.0).expect("unit normal");
        let d = self.draw_pin(spec.spindle_accel_rpm_per_s, &mut rng, &std_normal);
        let (latency, accel) = (d.latency_s, d.accel_rpm_per_s);

        let commands = spindle_commands(steps, sched.spindle_stop_s, latency);
        let rise = self.load_rise_fraction * spec.load_time_s;
        let load_on = sched.load_start_s + latency;
        let load_off = sched.unload_start_s + latency;
        let load_shape = |t: f64| -> f64 {
            let up = ((t - load_on) / rise).clamp(0.0, 1.0);
            let down = ((t - load_off) / rise).clamp(0.0, 1.0);
            0.5 * (1.0 - (PI * up).cos()) * 0.5 * (1.0 + (PI * down).cos())
        };

        let mut rec = empty_recording(pin, n);
        let mut rpm = 0.0f64;
        let mut theta = 0.0f64;
        let mut next_cmd = 0usize;
        let mut target = 0.0f64;
        let mut slide_start: Option<f64> = None;
        for i in 0..n {
            let t = t_start + i as f64 * dt;
            while next_cmd < commands.len() && t >= commands[next_cmd].0 {
                target = commands[next_cmd].1;
                next_cmd += 1;
            }
            let step_rpm = accel * dt;
            rpm += (target - rpm).clamp(-step_rpm, step_rpm);
            theta += 2.0 * PI * rpm / 60.0 * dt;
            let v = units::velocity_for_rpm(rpm, radius);
            let load = load_shape(t);
            let runout = d.runout(theta);
            let f_n = sched.normal_force_n * load * (1.0 + runout);
            let f_t = if rpm > 1e-9 && load > 0.0 {
                let since = t - *slide_start.get_or_insert(t);
                let mu = self.mu_at(p0, v, t, since);
                mu * f_n
                    + self.tangential_vibration_rel
                        * mu
                        * sched.normal_force_n
                        * load
                        * d.vibration(theta)
            } else {
                0.0
            };
            let f_r = self.radial_fraction * f_n;
            let clock = t - t_start;
            let noisy = |rng: &mut ChaCha8Rng, c: usize, x: f64, sd: f64| {
                x + d.offsets[c] + d.drifts[c] * clock + k * sd * std_normal.sample(rng)
            };
            rec.time_s.push(clock);
            rec.normal_n
                .push(noisy(&mut rng, 0, f_n, self.noise_normal_n));
            rec.tangential_n
                .push(noisy(&mut rng, 1, f_t, self.noise_tangential_n));
            let r = noisy(&mut rng, 2, f_r, self.noise_radial_n);
            rec.radial_n.as_mut().expect("radial").push(r);
            let trig = if (0.0..sched.end_s).contains(&t) {
                self.trigger_high_v
            } else {
                0.0
            };
            rec.trigger_v
                .as_mut()
                .expect("trigger")
                .push(trig + self.trigger_noise_v * std_normal.sample(&mut rng));
        }
        self.add_spikes(&mut rec, &mut rng, t_end - t_start)?;
        // Settings that pass their own checks can still combine into ∞ (a velocity exponent
        // of 10¹¹): a recording is written only when every sample is a number.
        check_finite(&rec, pin)?;
        Ok(rec)
    }

    /// Samples of a pin's recording of `duration_s` at the sample rate (both ends included),
    /// refused above [`MAX_SAMPLES_PER_PIN`].
    fn sample_count(&self, pin: u32, duration_s: f64) -> Result<usize> {
        let dt = 1.0 / self.sample_rate_hz;
        let samples = (duration_s / dt).floor() + 1.0;
        if samples > MAX_SAMPLES_PER_PIN {
            return Err(Error::invalid(
                "synth",
                format!(
                    "pin {pin}'s recording of {} s at sample_rate_hz = {} would be {samples:.3e} samples, more than {MAX_SAMPLES_PER_PIN:.0e}: lower sample_rate_hz",
                    Compact(duration_s),
                    Compact(self.sample_rate_hz)
                ),
            ));
        }
        Ok(samples as usize)
    }
}

/// The NC's spindle commands shifted by the `latency`, s: (time, target rpm) for each step's
/// start and the stop at `stop_s`.
fn spindle_commands(steps: &[crate::plan::PlanStep], stop_s: f64, latency: f64) -> Vec<(f64, f64)> {
    steps
        .iter()
        .map(|s| (s.step_start_s + latency, s.spindle_rpm))
        .chain(std::iter::once((stop_s + latency, 0.0)))
        .collect()
}

/// A pin's recording with room for `n` samples of each channel (force, radial, trigger).
fn empty_recording(pin: u32, n: usize) -> greybox_recording::Recording {
    greybox_recording::Recording {
        source: format!("synth pin {pin}"),
        time_s: Vec::with_capacity(n),
        normal_n: Vec::with_capacity(n),
        tangential_n: Vec::with_capacity(n),
        radial_n: Some(Vec::with_capacity(n)),
        trigger_v: Some(Vec::with_capacity(n)),
        ..greybox_recording::Recording::new("", Vec::new(), Vec::new(), Vec::new())
    }
}

/// Refuse a simulated recording whose forces are not all numbers, naming the first sample.
fn check_finite(rec: &greybox_recording::Recording, pin: u32) -> Result<()> {
    let channels = [
        ("normal force", &rec.normal_n),
        ("tangential force", &rec.tangential_n),
    ];
    for (name, values) in channels {
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "synth",
                format!(
                    "pin {pin}'s {name} is {} at t = {:.3} s: check [synth.ground_truth] and the disturbances",
                    values[k], rec.time_s[k]
                ),
            ));
        }
    }
    Ok(())
}

/// The random state of one pin's run, drawn from the pin's seed in a fixed order.
struct PinDraws {
    /// Delay of the NC events on the recording, s.
    latency_s: f64,
    /// Actual spindle acceleration, rpm/s.
    accel_rpm_per_s: f64,
    /// Run-out harmonics: (relative amplitude, phase).
    harmonics: Vec<(f64, f64)>,
    /// Phases of the three tangential vibration harmonics.
    vib_phase: Vec<f64>,
    /// Offsets (N) and drifts (N/s) of the normal, tangential and radial channels.
    offsets: Vec<f64>,
    drifts: Vec<f64>,
}

impl PinDraws {
    /// Relative run-out of the normal force at the disk angle `theta`, rad.
    fn runout(&self, theta: f64) -> f64 {
        self.harmonics
            .iter()
            .enumerate()
            .map(|(h, (a, ph))| a * ((h + 1) as f64 * theta + ph).sin())
            .sum()
    }
    /// Shape of the tangential vibration at the disk angle `theta` (harmonics at 1/h).
    fn vibration(&self, theta: f64) -> f64 {
        self.vib_phase
            .iter()
            .enumerate()
            .map(|(h, ph)| ((h + 1) as f64 * theta + ph).sin() / (h + 1) as f64)
            .sum()
    }
}

impl SynthConfig {
    /// Draw a pin's latency, spindle acceleration, run-out, vibration phases and channel
    /// offsets and drifts.
    fn draw_pin(
        &self,
        nominal_accel_rpm_per_s: f64,
        rng: &mut ChaCha8Rng,
        std_normal: &Normal<f64>,
    ) -> PinDraws {
        let latency_s = self.latency_s + self.latency_jitter_s * rng.gen_range(-1.0..=1.0);
        let accel_rpm_per_s =
            nominal_accel_rpm_per_s * (1.0 + self.spindle_accel_error * rng.gen_range(-1.0..=1.0));
        let harmonics: Vec<(f64, f64)> = self
            .runout_rel
            .iter()
            .map(|a| (*a, rng.gen_range(0.0..2.0 * PI)))
            .collect();
        let vib_phase: Vec<f64> = (0..3).map(|_| rng.gen_range(0.0..2.0 * PI)).collect();
        let offsets: Vec<f64> = (0..3)
            .map(|_| self.offset_std_n * std_normal.sample(rng))
            .collect();
        let drifts: Vec<f64> = (0..3)
            .map(|_| self.disturbance_scale * self.drift_std_n_per_s * std_normal.sample(rng))
            .collect();
        PinDraws {
            latency_s,
            accel_rpm_per_s,
            harmonics,
            vib_phase,
            offsets,
            drifts,
        }
    }

    /// μ while sliding at pressure `p0` and speed `v` (m/s), time `t`, `since` s after the
    /// slide began: the ground truth, raised during run-in, with stick-slip at low speed.
    fn mu_at(&self, p0: f64, v: f64, t: f64, since: f64) -> f64 {
        let mut mu = self.ground_truth.mu(&ContactState::new(p0, v));
        mu *= 1.0 + self.run_in_rel * (-since / self.run_in_time_s).exp();
        if let Some(s) = self.stick_slip {
            if units::m_per_s_to_m_per_min(v) < s.below_m_per_min {
                let phase = (t * s.frequency_hz).fract();
                mu *= 1.0 + s.amplitude_rel * 2.0 * (phase - 0.5);
            }
        }
        mu
    }

    /// Spikes on the force channels: Poisson arrivals over `duration_s`, 1–3 samples wide,
    /// of random sign and 50–100 % of the spike amplitude.
    fn add_spikes(
        &self,
        rec: &mut greybox_recording::Recording,
        rng: &mut ChaCha8Rng,
        duration_s: f64,
    ) -> Result<()> {
        let k = self.disturbance_scale;
        let n = rec.len();
        let rate = k * self.spike_rate_per_s * duration_s;
        if !(rate > 0.0 && self.spike_amplitude_n > 0.0) {
            return Ok(());
        }
        let poisson =
            Poisson::new(rate).map_err(|e| Error::invalid("synth", format!("spike rate: {e}")))?;
        for c in 0..3 {
            let count = poisson.sample(rng) as usize;
            let ch = match c {
                0 => &mut rec.normal_n,
                1 => &mut rec.tangential_n,
                _ => rec.radial_n.as_mut().expect("radial"),
            };
            for _ in 0..count {
                let at = rng.gen_range(0..n);
                let width = rng.gen_range(1..=3usize);
                let amp = k
                    * self.spike_amplitude_n
                    * rng.gen_range(0.5..1.0)
                    * if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
                for v in &mut ch[at..(at + width).min(n)] {
                    *v += amp;
                }
            }
        }
        Ok(())
    }
}

/// Write the ground truth CSV atomically.
pub fn write_ground_truth(path: &std::path::Path, rows: &[TruthRow]) -> Result<()> {
    greybox_core::atomic::write_atomic(path, |w| {
        writeln!(w, "pin,step,normal_force_N,sliding_velocity_m_per_min,actual_velocity_m_per_min,hertz_pressure_MPa,pressure_convention,cof_true")?;
        for r in rows {
            writeln!(
                w,
                "{},{},{},{},{},{},{},{}",
                r.pin,
                r.step,
                r.normal_force_n,
                units::m_per_s_to_m_per_min(r.sliding_velocity_m_s),
                units::m_per_s_to_m_per_min(r.actual_velocity_m_s),
                r.hertz_pressure_pa / units::PA_PER_MPA,
                r.pressure_convention.name(),
                r.cof_true
            )?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ground truth is plausible against the article's reported values (digest §1).
    #[test]
    fn ground_truth_matches_the_article() {
        let law = ArticleLikeLaw::default();
        let at = |p_article_mpa: f64, v_m_min: f64| {
            law.mu(&ContactState::new(
                p_article_mpa * 4f64.cbrt() * 1e6,
                v_m_min / 60.0,
            ))
        };
        for v in [60.0, 70.0, 80.0] {
            let mu = at(2000.0, v);
            assert!((0.288..=0.312).contains(&mu), "μ(2000 MPa, {v}) = {mu}");
        }
        assert!((at(1500.0, 60.0) - 0.41).abs() < 0.005);
        assert!((at(1500.0, 160.0) - 0.34).abs() < 0.005);
        // falls with velocity and with pressure everywhere on the plan
        for p in [914.7, 1200.0, 1600.0, 2170.0] {
            for v in [20.0, 100.0, 200.0] {
                assert!(at(p, v + 10.0) < at(p, v));
                assert!(at(p + 100.0, v) < at(p, v));
            }
        }
    }

    #[test]
    fn same_seed_same_bytes() {
        let plan = crate::plan::PlanSpec {
            track_radius_mm: Some(100.0),
            normal_force_count: crate::plan::PinCount::of(2),
            normal_force_max_n: 300.0,
            velocity_count: crate::plan::VelocityCount::of(3),
            velocity_max_m_per_min: 43.0,
            ..Default::default()
        }
        .build()
        .unwrap();
        let cfg = SynthConfig::default();
        let c = PinContact::default();
        let a = cfg.simulate_pin(&plan, &c, 2).unwrap();
        let b = cfg.simulate_pin(&plan, &c, 2).unwrap();
        assert_eq!(a, b);
        let other = SynthConfig {
            seed: 7,
            ..SynthConfig::default()
        }
        .simulate_pin(&plan, &c, 2)
        .unwrap();
        assert_ne!(a.tangential_n, other.tangential_n);
    }
}
