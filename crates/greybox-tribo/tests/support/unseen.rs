//! Recordings of the classes that rigs greybox was never tuned for produce (issue 44), each
//! written as text by this module alone (no greybox code) with its ground truth:
//!
//! * [`cof_trace_with_dips`]: a 20-minute, 100 Hz COF trace (`Time [s],Load [N],COF`) with a
//!   once-per-revolution dip to 20 % of μ (40 ms of every 0.6 s revolution), a 60 s run-in
//!   and white noise; no speed channel. The truth is the revolution-averaged steady μ.
//! * [`stribeck_sweep`]: 7 speed steps (0.01–1 m/s, log spaced, 30 s each, 1 s linear ramps
//!   between them) with μ falling from 0.12 to 0.04 (`Time [s],Load [N],Friction [N],Speed
//!   [m/s]`, 200 Hz), preceded by a 40 s run-in at the 4th step's speed that a plan omits
//!   (μ decaying from 0.15 to 0.095), then the spindle stops and the load is lifted.
//! * [`timed_steps`]: one file per pin (`Time [s],Fn [N],Ft [N],Trigger [V]`, 1 kHz), no
//!   speed channel, a trigger that rises as the first ramp starts, 9 velocity steps of a
//!   0.3 s ramp and a 0.5 s dwell each, μ changing by as little as 0.002 between steps.

use super::stream_rng;
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One step's truth: load, velocity (m/min), μ and the file.
#[derive(Debug, Clone)]
pub struct Truth {
    pub pin: u32,
    pub step: u32,
    pub normal_force_n: f64,
    pub velocity_m_per_min: f64,
    /// Planned duration of the step (ramp and dwell), s.
    pub duration_s: f64,
    pub mu: f64,
    pub file: PathBuf,
}

fn gauss(rng: &mut impl Rng) -> f64 {
    StandardNormal.sample(rng)
}

fn write(path: &Path, text: &str) {
    std::fs::write(path, text).expect("write a generated recording");
}

/// Revolution period, dip share and depth of [`cof_trace_with_dips`].
pub const DIP_PERIOD_S: f64 = 0.6;
pub const DIP_LENGTH_S: f64 = 0.04;
pub const DIP_DEPTH: f64 = 0.2;

/// See the module docs. Steady μ 0.45 (before the dips); load 10 N; 5 s unloaded at each end.
pub fn cof_trace_with_dips(dir: &Path, seed: u64) -> Truth {
    let mut rng = stream_rng(seed, 1);
    let fs = 100.0;
    let (mu_ss, load) = (0.45, 10.0);
    let (t_on, t_off, t_end) = (5.0, 1205.0, 1210.0);
    let mut text = String::from("Time [s],Load [N],COF\n");
    for k in 0..(t_end * fs) as usize {
        let t = k as f64 / fs;
        let loaded = (t_on..t_off).contains(&t);
        let fn_ = if loaded { load } else { 0.0 } + 0.02 * gauss(&mut rng);
        let mu = if loaded {
            let run_in = 1.0 + 0.3 * (-(t - t_on) / 20.0).exp();
            let dip = if (t - t_on) % DIP_PERIOD_S < DIP_LENGTH_S {
                DIP_DEPTH
            } else {
                1.0
            };
            mu_ss * run_in * dip + 0.01 * gauss(&mut rng)
        } else {
            0.002 * gauss(&mut rng)
        };
        let _ = writeln!(text, "{t:.2},{fn_:.4},{mu:.5}");
    }
    let path = dir.join("cof-trace.csv");
    write(&path, &text);
    Truth {
        pin: 1,
        step: 1,
        normal_force_n: load,
        velocity_m_per_min: 30.0,
        duration_s: t_off - t_on,
        // the mean over whole revolutions: the dips are part of the friction the pin felt
        mu: mu_ss * (1.0 - (1.0 - DIP_DEPTH) * DIP_LENGTH_S / DIP_PERIOD_S),
        file: path,
    }
}

/// The Stribeck sweep's speeds, m/s, and its μ per step.
pub fn stribeck_steps() -> Vec<(f64, f64)> {
    (0..7)
        .map(|k| {
            let v = 0.01 * 10f64.powf(2.0 * k as f64 / 6.0);
            (v, 0.12 - 0.08 * k as f64 / 6.0)
        })
        .collect()
}

/// See the module docs; `skip` leaves one step out of the recording (never run).
pub fn stribeck_sweep(dir: &Path, seed: u64, skip: Option<usize>) -> Vec<Truth> {
    let mut rng = stream_rng(seed, 2);
    let fs = 200.0;
    let load = 20.0;
    let steps: Vec<(f64, f64)> = stribeck_steps()
        .into_iter()
        .enumerate()
        .filter(|(k, _)| Some(*k) != skip)
        .map(|(_, s)| s)
        .collect();
    // (start, end, speed, μ) pieces: run-in, then ramps and dwells
    let run_in_v = stribeck_steps()[3].0;
    let mut pieces: Vec<(f64, f64, f64, f64, f64)> =
        vec![(2.0, 42.0, run_in_v, run_in_v, f64::NAN)];
    let mut t = 42.0;
    let mut prev = run_in_v;
    for (v, mu) in &steps {
        pieces.push((t, t + 1.0, prev, *v, *mu));
        pieces.push((t + 1.0, t + 30.0, *v, *v, *mu));
        prev = *v;
        t += 30.0;
    }
    let (t_stop, t_end) = (t, t + 3.0);
    let mut text = String::from("Time [s],Load [N],Friction [N],Speed [m/s]\n");
    for k in 0..(t_end * fs) as usize {
        let t = k as f64 / fs;
        let loaded = (1.0..t_stop + 1.0).contains(&t);
        let (v, mu) = match pieces.iter().find(|p| (p.0..p.1).contains(&t)) {
            Some(p) if p.4.is_nan() => (p.2, 0.095 + 0.055 * (-(t - 2.0) / 8.0).exp()),
            Some(p) => {
                let x = (t - p.0) / (p.1 - p.0);
                (p.2 + (p.3 - p.2) * x, p.4)
            }
            None => (0.0, 0.0),
        };
        let fn_ = if loaded { load } else { 0.0 } + 0.02 * gauss(&mut rng);
        let ft = if loaded && v > 0.0 {
            (mu + 0.004 * gauss(&mut rng)) * load
        } else {
            0.01 * gauss(&mut rng)
        };
        let vm = v * (1.0 + 0.002 * gauss(&mut rng));
        let _ = writeln!(text, "{t:.3},{fn_:.4},{ft:.5},{vm:.6}");
    }
    let path = dir.join("stribeck.csv");
    write(&path, &text);
    steps
        .iter()
        .enumerate()
        .map(|(k, (v, mu))| Truth {
            pin: 1,
            step: k as u32 + 1,
            normal_force_n: load,
            velocity_m_per_min: v * 60.0,
            duration_s: 31.0,
            mu: *mu,
            file: path.clone(),
        })
        .collect()
}

/// Ramp and dwell of [`timed_steps`], s.
pub const TIMED_RAMP_S: f64 = 0.3;
pub const TIMED_DWELL_S: f64 = 0.5;

/// See the module docs: `pins` files, loads 50, 100, 150 … N, velocities 10–90 m/min.
pub fn timed_steps(dir: &Path, seed: u64, pins: u32) -> Vec<Truth> {
    let fs = 1000.0;
    let mut truth = Vec::new();
    for pin in 1..=pins {
        let mut rng = stream_rng(seed, 10 + pin as u64);
        let load = 50.0 * pin as f64;
        // μ per step: a slow fall with speed and two steps only 0.002 apart
        let mus: Vec<f64> = (0..9)
            .map(|k| 0.30 - 0.01 * k as f64 + if k == 5 { 0.008 } else { 0.0 })
            .collect();
        let vs: Vec<f64> = (0..9).map(|k| 10.0 + 10.0 * k as f64).collect();
        let t0 = 1.0 + 0.05 * pin as f64; // the trigger edge
        let step_s = TIMED_RAMP_S + TIMED_DWELL_S;
        let t_stop = t0 + 9.0 * step_s;
        let t_end = t_stop + 1.0;
        let mut text = String::from("Time [s],Fn [N],Ft [N],Trigger [V]\n");
        for k in 0..(t_end * fs) as usize {
            let t = k as f64 / fs;
            let trig = if t >= t0 { 5.0 } else { 0.0 };
            let mu = if t < t0 || t >= t_stop {
                0.0
            } else {
                let s = ((t - t0) / step_s) as usize;
                let into = t - t0 - s as f64 * step_s;
                let prev = if s == 0 { 0.0 } else { mus[s - 1] };
                if into < TIMED_RAMP_S {
                    prev + (mus[s] - prev) * into / TIMED_RAMP_S
                } else {
                    mus[s]
                }
            };
            let fn_ = load * (1.0 + 0.003 * gauss(&mut rng)) + 0.05 * rng.gen_range(-1.0..1.0);
            let ft = mu * load + 0.003 * load * gauss(&mut rng);
            let _ = writeln!(text, "{t:.4},{fn_:.4},{ft:.5},{trig:.1}");
        }
        let path = dir.join(format!("timed_pin{pin}.csv"));
        write(&path, &text);
        for s in 0..9 {
            truth.push(Truth {
                pin,
                step: s as u32 + 1,
                normal_force_n: load,
                velocity_m_per_min: vs[s],
                duration_s: step_s,
                mu: mus[s],
                file: path.clone(),
            });
        }
    }
    truth
}
