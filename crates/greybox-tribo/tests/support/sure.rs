//! Virtual rigs for "how sure is it" (issue 58), each with its ground truth and with every
//! choice the rule under test does not fix drawn from the seed: sample rate, clock drift,
//! dropped samples, force offsets and their drift, the sign of the friction channel, the
//! noise law (Gaussian, Student's t with 3 degrees of freedom, Laplace, AR(1)), ramp shapes
//! and lengths, and what comes before the first step. Nothing here uses `greybox_tribo`.
//!
//! * [`staircase`]: a continuous velocity staircase per pin (one file per pin, no speed
//!   channel), steps 4–8 s long, a 0.3–1 s ramp between them, preceded by nothing, a run-in at
//!   the first speed, or an unplanned extra step.
//! * [`pull_off`]: one constant test with unloaded windows of 15 s and 20 s, the normal force
//!   pulling off (negative blips) at lift-off, drifting offsets.
//! * [`cof_trace`]: a rig's COF column (no friction force) with heavy-tailed noise whose level
//!   changes along the test.
//! * [`bidirectional`]: a forward pass and a reverse pass (the friction force changes sign
//!   once), no position channel, different μ each way.
//! * [`wandering`]: a long test whose μ wanders (an Ornstein–Uhlenbeck process with a 5–20 s
//!   correlation time about its level), 10 Hz.

use super::stream_rng;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal, StudentT};

/// A generated recording, SI: time, normal and friction force, and optionally the rig's μ.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    pub name: String,
    pub time_s: Vec<f64>,
    pub normal_n: Vec<f64>,
    pub tangential_n: Vec<f64>,
    /// The rig's own μ column (then `tangential_n` is empty: the file has no force column).
    pub cof: Option<Vec<f64>>,
}

/// One step's truth.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    pub pin: u32,
    pub step: u32,
    pub normal_force_n: f64,
    pub velocity_m_per_min: f64,
    /// Planned duration (ramp into the step and dwell), s.
    pub duration_s: f64,
    /// The steady μ of the step (the mean of the noise-free μ over its dwell).
    pub mu: f64,
}

/// A noise law of unit scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Noise {
    Gauss,
    /// Student's t, 3 degrees of freedom, scaled to unit variance.
    StudentT3,
    /// Laplace, unit variance.
    Laplace,
    /// AR(1), φ = 0.8, unit stationary variance.
    Ar1,
}

impl Noise {
    pub fn draw(rng: &mut ChaCha8Rng) -> Noise {
        [Noise::Gauss, Noise::StudentT3, Noise::Laplace, Noise::Ar1][rng.gen_range(0..4)]
    }
}

/// A stream of noise of one law.
pub struct NoiseStream {
    law: Noise,
    state: f64,
    t3: StudentT<f64>,
}

impl NoiseStream {
    pub fn new(law: Noise) -> Self {
        NoiseStream {
            law,
            state: 0.0,
            t3: StudentT::new(3.0).unwrap(),
        }
    }

    pub fn next(&mut self, rng: &mut ChaCha8Rng) -> f64 {
        match self.law {
            Noise::Gauss => StandardNormal.sample(rng),
            Noise::StudentT3 => self.t3.sample(rng) / 3f64.sqrt(),
            Noise::Laplace => {
                let u: f64 = rng.gen_range(-0.5..0.5);
                -u.signum() * (1.0 - 2.0 * u.abs()).ln() / std::f64::consts::SQRT_2
            }
            Noise::Ar1 => {
                let e: f64 = StandardNormal.sample(rng);
                self.state = 0.8 * self.state + 0.6 * e;
                self.state
            }
        }
    }
}

/// A sampling clock: rate, drift and dropped samples drawn from the seed.
pub struct Clock {
    pub fs: f64,
    pub drift: f64,
    drop_every: usize,
}

impl Clock {
    pub fn draw(rng: &mut ChaCha8Rng, rates: &[f64]) -> Clock {
        Clock {
            fs: rates[rng.gen_range(0..rates.len())],
            drift: rng.gen_range(-1e-3..1e-3),
            drop_every: rng.gen_range(2000..20000),
        }
    }

    /// Sample times up to `t_end`, s: k/fs stretched by the drift, an occasional sample lost.
    pub fn times(&self, t_end: f64) -> Vec<f64> {
        let n = (t_end * self.fs) as usize;
        (0..n)
            .filter(|k| k % self.drop_every != self.drop_every - 1)
            .map(|k| k as f64 / self.fs * (1.0 + self.drift))
            .collect()
    }
}

/// Ramp from 0 to 1 over x ∈ [0, 1]: linear or cosine.
pub fn ramp(x: f64, cosine: bool) -> f64 {
    let x = x.clamp(0.0, 1.0);
    if cosine {
        0.5 - 0.5 * (std::f64::consts::PI * x).cos()
    } else {
        x
    }
}

/// μ of the staircase's law at velocity v (m/min) and load (N): falls with both, as the
/// support module's law, with a pin-specific factor.
pub fn staircase_mu(load_n: f64, v: f64, factor: f64) -> f64 {
    factor * super::mu_law(load_n, v)
}

/// What comes before a pin's first planned step in [`staircase`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Before {
    Nothing,
    /// An unplanned run-in at the first speed, 3–5 s before the first planned step: μ
    /// 30–60 % above the first step's, decaying with a time constant of 0.4–0.8 s.
    RunIn,
    /// An unplanned step at another speed, 3–5 s, before the first planned one.
    ExtraStep,
}

/// See the module docs: `pins` pins (one trace each) of 3–6 steps; returns the traces and the
/// truth per step. μ changes by at least 0.006 between neighbouring steps.
pub fn staircase(seed: u64, pins: u32) -> (Vec<Trace>, Vec<Step>) {
    let mut rng = stream_rng(seed, 58);
    let clock = Clock::draw(&mut rng, &[100.0, 200.0, 250.0]);
    let law = Noise::draw(&mut rng);
    let cosine = rng.gen_bool(0.5);
    let before = [Before::Nothing, Before::RunIn, Before::ExtraStep][rng.gen_range(0..3)];
    let mut traces = Vec::new();
    let mut truth = Vec::new();
    for pin in 1..=pins {
        let load = rng.gen_range(50.0..400.0);
        let factor = rng.gen_range(0.7..1.2);
        let k: usize = rng.gen_range(3..=6);
        // velocities: log-spaced with a random start and ratio, up or down
        let v0 = rng.gen_range(10.0..40.0);
        let ratio: f64 = rng.gen_range(1.35..1.8);
        let mut vs: Vec<f64> = (0..k).map(|i| v0 * ratio.powi(i as i32)).collect();
        if rng.gen_bool(0.4) {
            vs.reverse();
        }
        let dwells: Vec<f64> = (0..k).map(|_| rng.gen_range(4.0..8.0)).collect();
        let ramps: Vec<f64> = (0..k).map(|_| rng.gen_range(0.3..1.0)).collect();
        // schedule: unloaded, load ramp, (extra step), then ramp + dwell per step, stop, lift
        let t_unl0 = rng.gen_range(2.0..4.0);
        let t_load = t_unl0 + 0.5;
        let mut pieces: Vec<(f64, f64, f64, f64)> = Vec::new(); // start, ramp, from, to
        let mut t = t_load + rng.gen_range(0.2..0.6);
        let mut prev_v = 0.0;
        let run_in_start = t;
        if before != Before::Nothing {
            let vx = match before {
                Before::ExtraStep => v0 * ratio.powf(rng.gen_range(-1.5..(k as f64 + 0.5))),
                _ => vs[0],
            };
            let d = rng.gen_range(3.0..5.0);
            pieces.push((t, 0.5, 0.0, vx));
            t += d;
            prev_v = vx;
        }
        let mut starts = Vec::new();
        for i in 0..k {
            pieces.push((t, ramps[i], prev_v, vs[i]));
            starts.push(t);
            t += ramps[i] + dwells[i];
            prev_v = vs[i];
        }
        let t_stop = t;
        pieces.push((t_stop, 0.4, prev_v, 0.0));
        let t_lift = t_stop + 0.6;
        let t_end = t_lift + 0.5 + rng.gen_range(2.0..3.0);
        let first_speed_start = pieces[0].0;
        let speed = |t: f64| -> f64 {
            if t < first_speed_start {
                return 0.0;
            }
            let &(s, r, a, b) = pieces.iter().rev().find(|p| p.0 <= t).unwrap();
            a + (b - a) * ramp((t - s) / r, cosine)
        };
        let run_in: (f64, f64) = (rng.gen_range(0.3..0.6), rng.gen_range(0.4..0.8));
        let (o_n, o_t, drift_t) = (
            rng.gen_range(-2.0..2.0),
            rng.gen_range(-0.5..0.5),
            rng.gen_range(-0.2..0.2),
        );
        let sigma_mu = rng.gen_range(0.002..0.006);
        let sign = if rng.gen_bool(0.3) { -1.0 } else { 1.0 };
        let mut noise = NoiseStream::new(law);
        let times = clock.times(t_end);
        let mut tr = Trace {
            name: format!("staircase_{seed}_pin{pin}.csv"),
            ..Default::default()
        };
        for &tc in &times {
            let t = tc / (1.0 + clock.drift); // the rig's true time
            let f =
                load * ramp((t - t_unl0) / 0.5, cosine) * (1.0 - ramp((t - t_lift) / 0.5, cosine));
            let v = speed(t);
            let mut mu = staircase_mu(load, v, factor);
            if before == Before::RunIn && t >= run_in_start {
                mu *= 1.0 + run_in.0 * (-(t - run_in_start) / run_in.1).exp();
            }
            let ft = sign * (mu * f + sigma_mu * f * noise.next(&mut rng));
            tr.time_s.push(tc);
            tr.normal_n
                .push(f + o_n + 0.002 * load * noise.next(&mut rng));
            tr.tangential_n.push(ft + o_t + drift_t * t / t_end);
        }
        traces.push(tr);
        for i in 0..k {
            truth.push(Step {
                pin,
                step: i as u32 + 1,
                normal_force_n: load,
                velocity_m_per_min: vs[i],
                duration_s: ramps[i] + dwells[i],
                mu: staircase_mu(load, vs[i], factor),
            });
        }
    }
    (traces, truth)
}

/// See the module docs: one test at 5–50 N, 100 Hz, unloaded 15 s before and 20 s after;
/// lift-off pulls the normal force below zero for 2–6 samples (down to −(0.3–1.5)× the
/// load); offsets drift linearly. Returns the trace and μ.
pub fn pull_off(seed: u64) -> (Trace, f64) {
    let mut rng = stream_rng(seed, 59);
    let clock = Clock::draw(&mut rng, &[50.0, 100.0]);
    let law = Noise::draw(&mut rng);
    let load = rng.gen_range(5.0..50.0);
    let mu = rng.gen_range(0.1..0.7);
    let (t_on, dur) = (15.0, rng.gen_range(40.0..80.0));
    let t_off = t_on + dur;
    let t_end = t_off + 20.0;
    let (o_n, d_n, o_t, d_t) = (
        rng.gen_range(-0.5..0.5),
        rng.gen_range(-0.3..0.3),
        rng.gen_range(-0.2..0.2),
        rng.gen_range(-0.1..0.1),
    );
    let blips: Vec<(f64, f64)> = (0..rng.gen_range(1..4))
        .map(|_| {
            (
                t_off + rng.gen_range(0.0..0.3),
                -load * rng.gen_range(0.3..1.5),
            )
        })
        .collect();
    let blip_len = rng.gen_range(2..7) as f64 / clock.fs;
    let sigma = rng.gen_range(0.003..0.01);
    let mut noise = NoiseStream::new(law);
    let mut tr = Trace {
        name: format!("pull_off_{seed}.csv"),
        ..Default::default()
    };
    for tc in clock.times(t_end) {
        let t = tc / (1.0 + clock.drift);
        let f = load * ramp((t - t_on) / 0.3, false) * (1.0 - ramp((t - t_off) / 0.2, false));
        let mut fn_ =
            f + o_n + d_n * t / t_end + 0.01 * load * noise.next(&mut rng).clamp(-5.0, 5.0);
        for (tb, depth) in &blips {
            if (*tb..tb + blip_len).contains(&t) {
                fn_ = *depth;
            }
        }
        let sliding = (t_on + 1.0..t_off - 0.2).contains(&t);
        let ft = if sliding { mu * f } else { 0.0 }
            + sigma * load * noise.next(&mut rng)
            + o_t
            + d_t * t / t_end;
        tr.time_s.push(tc);
        tr.normal_n.push(fn_);
        tr.tangential_n.push(ft);
    }
    (tr, mu)
}

/// See the module docs: a COF column (μ 0.2–0.6) at 50–200 Hz over 60–120 s at a constant
/// load, its noise heavy-tailed (Student's t with 2–4 degrees of freedom, scale 0.004–0.01)
/// with a scale that grows 1×–3× along the test, the rig's μ quantised to 3 or 4 decimals, a
/// 5 s unloaded window at each end. Returns the trace and μ.
pub fn cof_trace(seed: u64) -> (Trace, f64) {
    let mut rng = stream_rng(seed, 60);
    let clock = Clock::draw(&mut rng, &[50.0, 100.0, 200.0]);
    let dof = rng.gen_range(2.0..4.0);
    let heavy = StudentT::new(dof).unwrap();
    let load = rng.gen_range(2.0..20.0);
    let mu = rng.gen_range(0.2..0.6);
    let dur = rng.gen_range(60.0..120.0);
    let (t_on, t_off) = (5.0, 5.0 + dur);
    let t_end = t_off + 5.0;
    let scale0 = rng.gen_range(0.004..0.01);
    let change_at = rng.gen_range(0.2..0.8) * dur + t_on;
    let factor = rng.gen_range(1.0..3.0);
    let decimals = if rng.gen_bool(0.5) { 1e3 } else { 1e4 };
    let mut tr = Trace {
        name: format!("cof_{seed}.csv"),
        cof: Some(Vec::new()),
        ..Default::default()
    };
    for tc in clock.times(t_end) {
        let t = tc / (1.0 + clock.drift);
        let loaded = (t_on..t_off).contains(&t);
        let fn_ = if loaded { load } else { 0.0 } + 0.002 * load * rng.gen_range(-1.0..1.0);
        let scale = if t > change_at {
            scale0 * factor
        } else {
            scale0
        };
        let e: f64 = heavy.sample(&mut rng);
        let m = if loaded { mu + scale * e } else { 0.001 * e };
        tr.time_s.push(tc);
        tr.normal_n.push(fn_);
        tr.cof
            .as_mut()
            .unwrap()
            .push((m * decimals).round() / decimals);
    }
    (tr, mu)
}

/// See the module docs: 100–500 Hz; a forward pass of 8–12 s at μ_f, then a reverse pass of
/// 7–11 s at μ_b (the friction force of the other sign), either after a stop of 0.3–1 s or
/// reversing at once (the force passing through zero over the 0.2–0.5 s ramp); each pass
/// entered over that ramp; the friction channel's sign as recorded drawn (the first pass
/// positive or negative), its offset and drift drawn; unloaded windows of 3 s at each end.
/// Returns the trace and (μ_f, μ_b).
pub fn bidirectional(seed: u64) -> (Trace, (f64, f64)) {
    let mut rng = stream_rng(seed, 61);
    let clock = Clock::draw(&mut rng, &[100.0, 200.0, 500.0]);
    let law = Noise::draw(&mut rng);
    let load = rng.gen_range(5.0..100.0);
    let mu_f = rng.gen_range(0.1..0.6);
    let mu_b = mu_f * rng.gen_range(0.8..1.2);
    let stop = if rng.gen_bool(0.5) {
        rng.gen_range(0.3..1.0)
    } else {
        0.0
    };
    let (fwd, back) = (rng.gen_range(8.0..12.0), rng.gen_range(7.0..11.0));
    let r = rng.gen_range(0.2..0.5);
    let sign = if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
    let (o_t, d_t) = (
        rng.gen_range(-0.05..0.05) * load,
        rng.gen_range(-0.01..0.01) * load,
    );
    let t_on = 3.0;
    let t_f = t_on + 0.5;
    let t_b = t_f + fwd + stop;
    let t_off = t_b + back;
    let t_end = t_off + 0.5 + 3.0;
    let sigma = rng.gen_range(0.003..0.01);
    let mut noise = NoiseStream::new(law);
    let mut tr = Trace {
        name: format!("bidirectional_{seed}.csv"),
        ..Default::default()
    };
    for tc in clock.times(t_end) {
        let t = tc / (1.0 + clock.drift);
        let f = load * ramp((t - t_on) / 0.3, true) * (1.0 - ramp((t - t_off - 0.2) / 0.3, true));
        let m = if stop == 0.0 && (t_b - r..t_b + r).contains(&t) {
            // reversing at once: from +μ_f through zero to −μ_b
            let x = ramp((t - (t_b - r)) / (2.0 * r), true);
            mu_f * (1.0 - x) - mu_b * x
        } else if (t_f..t_f + fwd).contains(&t) {
            mu_f * ramp((t - t_f) / r, true)
        } else if (t_b..t_off).contains(&t) {
            -mu_b * ramp((t - t_b) / r, true)
        } else {
            0.0
        };
        tr.time_s.push(tc);
        tr.normal_n.push(f + 0.005 * load * noise.next(&mut rng));
        tr.tangential_n
            .push(sign * (m * f + sigma * load * noise.next(&mut rng)) + o_t + d_t * t / t_end);
    }
    (tr, (mu_f, mu_b))
}

/// See the module docs: 10 Hz over 10–20 min at 10–50 N; μ = μ₀ + an OU process of
/// correlation time 5–20 s and standard deviation 0.005–0.015, plus white noise; unloaded
/// windows of 5 s at each end. Returns the trace and μ₀ (the level μ wanders about).
pub fn wandering(seed: u64) -> (Trace, f64) {
    let mut rng = stream_rng(seed, 62);
    let fs = 10.0;
    let load = rng.gen_range(10.0..50.0);
    let mu0 = rng.gen_range(0.1..0.6);
    let dur = rng.gen_range(600.0..1200.0);
    let tau: f64 = rng.gen_range(5.0..20.0);
    let sd = rng.gen_range(0.005..0.015);
    let white = rng.gen_range(0.002..0.006);
    let (t_on, t_off) = (5.0, 5.0 + dur);
    let t_end = t_off + 5.0;
    let phi: f64 = (-1.0 / (fs * tau)).exp();
    let mut ou: f64 = sd * {
        let e: f64 = StandardNormal.sample(&mut rng);
        e
    };
    let mut tr = Trace {
        name: format!("wandering_{seed}.csv"),
        ..Default::default()
    };
    for k in 0..(t_end * fs) as usize {
        let t = k as f64 / fs;
        let loaded = (t_on..t_off).contains(&t);
        let e: f64 = StandardNormal.sample(&mut rng);
        ou = phi * ou + sd * (1.0 - phi * phi).sqrt() * e;
        let w: f64 = StandardNormal.sample(&mut rng);
        let wn: f64 = StandardNormal.sample(&mut rng);
        let f = if loaded { load } else { 0.0 };
        tr.time_s.push(t);
        tr.normal_n.push(f + 0.002 * load * wn);
        tr.tangential_n
            .push(if loaded { (mu0 + ou) * f } else { 0.0 } + white * load * w);
    }
    (tr, mu0)
}
