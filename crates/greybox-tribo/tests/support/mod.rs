//! Test-support generators: recordings of tribometers *other* than greybox's own virtual rig.
//!
//! Use from an integration test with `mod support;`. Every generator is seeded (ChaCha8):
//! the same seed gives the same bytes. Nothing here uses `greybox_tribo` itself.
//!
//! * [`rig2`] — a second pin-on-disk rig on a lathe that does NOT run greybox's NC program:
//!   one CSV per pin, `dir/rig2_pinNN.csv`, header `Time [s],Fz [kN],Fx [N],Fy [N],Spindle [rpm]`.
//!   See the module docs of `rig2.rs` for the exact timeline and sensor effects.
//! * [`exports`] — four export layouts of other tribometers:
//!   `rotary.csv` (ball-on-disk vendor CSV, metadata + footer, per-step time, trailing commas),
//!   `campaign.csv` (UTF-8 BOM, CRLF, `;`, decimal commas, lifted pin between pins),
//!   `step_01.txt …` (tab-separated, one file per step, no time column, 1000 Hz) and
//!   `tribo.xlsx` (sheet `Data`, title row, empty row, header row, numeric cells).
//!   See the module docs of `exports.rs` for each exact layout.
//!
//! Every generator returns the ground truth as a `Vec<TruthStep>`, one entry per (pin, step) in
//! the order run. `mu_true` is the steady-state coefficient the rig imposes at the nominal
//! load and velocity of that step (what a perfect identification returns); it is
//! [`mu_law`]`(normal_force_n, velocity_m_per_min)`.
//!
//! ## Ground-truth law
//!
//! μ(F, v) = 0.40 · (F / 300 N)^(−0.05) · (v_eff / 60 m/min)^(−0.12) · tanh(v / 0.5 m/min),
//! v_eff = √(v² + (5 m/min)²).
//!
//! It falls with load and with velocity; over the loads (10–1800 N) and nominal velocities
//! (9–240 m/min) used here it lies in 0.30–0.59. The tanh factor makes the tangential force
//! vanish smoothly when the spindle is at rest (it equals 1 to 1e-8 at every nominal speed),
//! and v_eff keeps μ finite at the low speeds crossed during ramps.
#![allow(dead_code)]

pub mod exports;
pub mod rig2;
pub mod settle;
pub mod stribeck;
pub mod sure;
pub mod unseen;

/// A planned step of any generator's truth, as a plan states it: (pin, step, normal load N,
/// sliding velocity m/min, planned duration s where the generator plans one). One view of
/// the generators' truth types, so that the tests turn each into greybox's plan one way.
pub trait PlannedStep {
    fn planned(&self) -> (u32, u32, f64, f64, Option<f64>);
}

impl PlannedStep for TruthStep {
    fn planned(&self) -> (u32, u32, f64, f64, Option<f64>) {
        (
            self.pin,
            self.step,
            self.normal_force_n,
            self.velocity_m_per_min,
            None,
        )
    }
}

/// The generators whose truth plans a duration per step.
macro_rules! planned_with_duration {
    ($($t:ty),+) => {$(
        impl PlannedStep for $t {
            fn planned(&self) -> (u32, u32, f64, f64, Option<f64>) {
                let d = Some(self.duration_s);
                (self.pin, self.step, self.normal_force_n, self.velocity_m_per_min, d)
            }
        }
    )+};
}
planned_with_duration!(sure::Step, unseen::Truth);

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;

/// Ground truth of one (pin, step).
#[derive(Debug, Clone, PartialEq)]
pub struct TruthStep {
    /// 1-based pin number.
    pub pin: u32,
    /// 1-based step number within the pin, in the order run.
    pub step: u32,
    /// Nominal normal load, N.
    pub normal_force_n: f64,
    /// Nominal sliding velocity, m/min.
    pub velocity_m_per_min: f64,
    /// Steady-state friction coefficient imposed by the rig for this step.
    pub mu_true: f64,
    /// The file holding this step's samples.
    pub file: PathBuf,
}

/// Reference coefficient of the ground-truth law.
pub const MU_REF: f64 = 0.40;
/// Reference load, N.
pub const LOAD_REF_N: f64 = 300.0;
/// Reference velocity, m/min.
pub const VELOCITY_REF_M_PER_MIN: f64 = 60.0;
/// Load exponent (μ falls with load).
pub const LOAD_EXPONENT: f64 = -0.05;
/// Velocity exponent (μ falls with velocity).
pub const VELOCITY_EXPONENT: f64 = -0.12;
/// Velocity regularisation of the power law, m/min.
pub const VELOCITY_REG_M_PER_MIN: f64 = 5.0;
/// Velocity scale of the stick-to-slip transition, m/min.
pub const VELOCITY_SLIP_M_PER_MIN: f64 = 0.5;

/// The ground-truth friction law μ(F, v) (see the module docs).
pub fn mu_law(load_n: f64, velocity_m_per_min: f64) -> f64 {
    let v = velocity_m_per_min.abs();
    let v_eff = (v * v + VELOCITY_REG_M_PER_MIN * VELOCITY_REG_M_PER_MIN).sqrt();
    let load = load_n.abs().max(1.0);
    MU_REF
        * (load / LOAD_REF_N).powf(LOAD_EXPONENT)
        * (v_eff / VELOCITY_REF_M_PER_MIN).powf(VELOCITY_EXPONENT)
        * (v / VELOCITY_SLIP_M_PER_MIN).tanh()
}

/// A ChaCha8 generator for one independent stream of a generator.
pub(crate) fn stream_rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// Cosine S-curve: 0 at x ≤ 0, 1 at x ≥ 1, zero slope at both ends.
pub(crate) fn s_curve(x: f64) -> f64 {
    if x <= 0.0 {
        0.0
    } else if x >= 1.0 {
        1.0
    } else {
        0.5 - 0.5 * (std::f64::consts::PI * x).cos()
    }
}

/// A piecewise signal of holds and S-shaped ramps, evaluated at a time in seconds.
#[derive(Debug, Clone)]
pub(crate) struct Schedule {
    start: f64,
    /// (t_begin, duration, from, to)
    segments: Vec<(f64, f64, f64, f64)>,
    end_time: f64,
    end_value: f64,
}

impl Schedule {
    pub(crate) fn new(start: f64) -> Self {
        Schedule {
            start,
            segments: Vec::new(),
            end_time: 0.0,
            end_value: start,
        }
    }

    pub(crate) fn hold(&mut self, duration_s: f64) -> &mut Self {
        let v = self.end_value;
        self.segments.push((self.end_time, duration_s, v, v));
        self.end_time += duration_s;
        self
    }

    pub(crate) fn ramp_to(&mut self, duration_s: f64, target: f64) -> &mut Self {
        self.segments
            .push((self.end_time, duration_s, self.end_value, target));
        self.end_time += duration_s;
        self.end_value = target;
        self
    }

    pub(crate) fn duration(&self) -> f64 {
        self.end_time
    }

    pub(crate) fn value(&self, t: f64) -> f64 {
        if t < 0.0 {
            return self.start;
        }
        for &(t0, dur, from, to) in &self.segments {
            if t < t0 + dur {
                if from == to || dur <= 0.0 {
                    return to;
                }
                return from + (to - from) * s_curve((t - t0) / dur);
            }
        }
        self.end_value
    }
}

/// `x` with six significant digits in plain decimal notation (no exponent).
pub(crate) fn sig6(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return "0".to_string();
    }
    let magnitude = x.abs().log10().floor() as i32;
    let decimals = (5 - magnitude).clamp(0, 9) as usize;
    let s = format!("{:.*}", decimals, x);
    if s.starts_with('-') && s[1..].bytes().all(|b| b == b'0' || b == b'.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// `x` with a fixed number of decimals, never printed as negative zero.
pub(crate) fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{:.*}", decimals, x);
    if s.starts_with('-') && s[1..].bytes().all(|b| b == b'0' || b == b'.') {
        s[1..].to_string()
    } else {
        s
    }
}
