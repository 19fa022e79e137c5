//! A second virtual pin-on-disk rig: a lathe rig that does NOT run greybox's NC program.
//!
//! [`LatheRig::write_campaign`] writes one CSV per pin, `dir/rig2_pinNN.csv` (NN = 1-based pin
//! number, two digits: `rig2_pin01.csv`, `rig2_pin02.csv`, …).
//!
//! ## File layout
//!
//! * ASCII, LF line ends, comma-separated, no preamble, exactly one header line:
//!   `Time [s],Fz [kN],Fx [N],Fy [N],Spindle [rpm]`
//! * `Time [s]`: recorder timestamp, 6 decimals. The recorder clock runs 0.05 % fast:
//!   timestamp = true time × 1.0005 (nominal 2000 Hz → recorded step 0.00050025 s). The first
//!   row is at 0.
//! * `Fz [kN]`: normal force in **kN**, positive (e.g. `0.901300`).
//! * `Fx [N]`: tangential force in N, recorded with a **negative sign** (Fx ≈ −μ·F_N).
//! * `Fy [N]`: radial force in N, ≈ 5 % of F_N plus noise.
//! * `Spindle [rpm]`: measured spindle speed, rpm (true speed × (1 + 0.3 % noise); 0 at rest).
//! * Forces and speed are written with 6 significant digits. One file is ~1.2 MB for 6 steps.
//!
//! ## Timeline (true time, defaults of [`LatheRig`])
//!
//! 1. t = 0 … 0.2 s (`pre_roll_s`): pin loaded, spindle at rest (F_t ≈ 0, only noise). There is
//!    no unloaded window anywhere in the file (the load was applied before recording started).
//! 2. For every velocity of the pin, in the order given: a 0.3 s cosine S-ramp (`ramp_s`) of the
//!    spindle speed from the previous speed (0 for the first) straight to the new one (no stop
//!    between steps), then a 2.0 s dwell (`dwell_s`) at constant speed.
//!    Step k (0-based) therefore dwells over true time
//!    [pre_roll + k·(ramp+dwell) + ramp, pre_roll + (k+1)·(ramp+dwell)).
//! 3. At the end of the last dwell the spindle stops abruptly (speed 0 from the next sample on)
//!    and the recording ends 0.3 s later (`tail_s`), still loaded.
//!
//! Track radius R = 100 mm; speed n [rpm] = v [m/min] / (2π R [m]).
//!
//! ## Physics and sensor effects
//!
//! * F_t(t) = μ(t) · F_N(t), μ(t) = [`mu_law`](super::mu_law)(load, v(t)) · runin(t), v(t) the
//!   instantaneous sliding speed (so μ moves smoothly through the ramps and F_t → 0 at rest).
//! * Run-in: runin(t) = 1 + 0.25·exp(−(t − t_slide)/0.25 s) with t_slide the start of the first
//!   ramp (μ starts 25 % high on the first step of each pin and decays toward the steady value).
//! * F_N(t) = load · (1 + 0.015·sin(2π·f_p·t + φ_p) + 0.01·sin(θ(t) + φ_r)): hydraulic pulsation at
//!   f_p ≈ 6.7 Hz (±0.05 Hz per pin) and spindle-synchronous run-out at the rotation frequency
//!   (θ = spindle angle). F_t follows F_N(t).
//! * Offsets: each force channel has a constant offset |o| ≤ 0.04 N plus a drift of at most
//!   ±0.005 N over the file.
//! * White noise: F_N σ = 2 N, F_t σ = 0.8 N, Fy σ = 0.5 N; speed 0.3 % (relative).
//! * Spikes: Poisson arrivals, 0.3 per second, each ±20–40 N on ONE sample of Fz or Fx.
//! * One gap of 40 ms (80 consecutive rows simply absent) in every file, inside one randomly
//!   chosen dwell, starting 0.6–1.3 s after the dwell starts.
//!
//! Ground truth: one [`TruthStep`] per (pin, velocity) in the order run, `mu_true` =
//! `mu_law(load, v)` (steady value, without run-in).

use super::{mu_law, sig6, stream_rng, Schedule, TruthStep};
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};
use std::f64::consts::PI;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// The second virtual rig. All durations are true (not recorder) time.
#[derive(Debug, Clone, PartialEq)]
pub struct LatheRig {
    pub seed: u64,
    /// Nominal sample rate of the recorder, Hz (default 2000).
    pub sample_rate_hz: f64,
    /// Wear-track radius, m (default 0.1).
    pub track_radius_m: f64,
    /// Loaded, spindle at rest, before the first ramp, s (default 0.2).
    pub pre_roll_s: f64,
    /// Duration of every S-shaped speed ramp, s (default 0.3).
    pub ramp_s: f64,
    /// Dwell at each speed after its ramp, s (default 2.0).
    pub dwell_s: f64,
    /// Loaded, spindle stopped, after the abrupt stop, s (default 0.3).
    pub tail_s: f64,
    /// Recorder clock / true clock (default 1.0005).
    pub clock_factor: f64,
    /// Length of the gap of missing rows, s (default 0.04).
    pub gap_s: f64,
}

impl Default for LatheRig {
    fn default() -> Self {
        LatheRig {
            seed: 0,
            sample_rate_hz: 2000.0,
            track_radius_m: 0.1,
            pre_roll_s: 0.2,
            ramp_s: 0.3,
            dwell_s: 2.0,
            tail_s: 0.3,
            clock_factor: 1.0005,
            gap_s: 0.04,
        }
    }
}

/// 3 pins: 300 N, 900 N, 1800 N; velocities 40…240 m/min in steps of 40, ascending for pins 1
/// and 3, descending for pin 2.
pub fn default_pins() -> Vec<(f64, Vec<f64>)> {
    let up: Vec<f64> = vec![40.0, 80.0, 120.0, 160.0, 200.0, 240.0];
    let down: Vec<f64> = up.iter().rev().copied().collect();
    vec![(300.0, up.clone()), (900.0, down), (1800.0, up)]
}

impl LatheRig {
    /// Default rig with the given seed.
    pub fn new(seed: u64) -> Self {
        LatheRig {
            seed,
            ..LatheRig::default()
        }
    }

    /// The file name of pin `pin` (1-based).
    pub fn file_name(pin: u32) -> String {
        format!("rig2_pin{pin:02}.csv")
    }

    /// Writes `dir/rig2_pinNN.csv` for every pin (creating `dir`) and returns the ground truth.
    pub fn write_campaign(&self, dir: &Path, pins: &[(f64, Vec<f64>)]) -> Vec<TruthStep> {
        std::fs::create_dir_all(dir).expect("create output directory");
        let mut truth = Vec::new();
        for (i, (load, velocities)) in pins.iter().enumerate() {
            let pin = i as u32 + 1;
            let path = dir.join(Self::file_name(pin));
            self.write_pin(&path, pin, *load, velocities);
            for (k, &v) in velocities.iter().enumerate() {
                truth.push(TruthStep {
                    pin,
                    step: k as u32 + 1,
                    normal_force_n: *load,
                    velocity_m_per_min: v,
                    mu_true: mu_law(*load, v),
                    file: path.clone(),
                });
            }
        }
        truth
    }

    /// Spindle speed in rpm for a sliding velocity in m/min.
    pub fn rpm_for(&self, velocity_m_per_min: f64) -> f64 {
        velocity_m_per_min / (2.0 * PI * self.track_radius_m)
    }

    fn write_pin(&self, path: &Path, pin: u32, load_n: f64, velocities: &[f64]) {
        let fs = self.sample_rate_hz;
        let dt = 1.0 / fs;
        let mut rng = stream_rng(self.seed, 0x5249_4732_0000_0000 ^ u64::from(pin));

        // Spindle speed schedule (true time), rpm.
        let mut speed = Schedule::new(0.0);
        speed.hold(self.pre_roll_s);
        for &v in velocities {
            speed
                .ramp_to(self.ramp_s, self.rpm_for(v))
                .hold(self.dwell_s);
        }
        let t_stop = speed.duration();
        let t_slide = self.pre_roll_s;
        let n_samples = ((t_stop + self.tail_s) * fs).round() as usize;

        // Per-pin random constants.
        let pulsation_hz = 6.7 + rng.gen_range(-0.05..0.05);
        let pulsation_phase = rng.gen_range(0.0..2.0 * PI);
        let runout_phase = rng.gen_range(0.0..2.0 * PI);
        let radial_ratio = 0.05 * (1.0 + rng.gen_range(-0.1..0.1));
        let offsets: [f64; 3] = [
            rng.gen_range(-0.04..0.04),
            rng.gen_range(-0.04..0.04),
            rng.gen_range(-0.04..0.04),
        ];
        let total_t = n_samples as f64 * dt;
        let drifts: [f64; 3] = [
            rng.gen_range(-0.005..0.005) / total_t,
            rng.gen_range(-0.005..0.005) / total_t,
            rng.gen_range(-0.005..0.005) / total_t,
        ];
        let (gap_start, gap_len) = if velocities.is_empty() {
            (usize::MAX, 0)
        } else {
            let k = rng.gen_range(0..velocities.len());
            let dwell_start =
                self.pre_roll_s + k as f64 * (self.ramp_s + self.dwell_s) + self.ramp_s;
            let offset = rng.gen_range(0.3 * self.dwell_s..0.65 * self.dwell_s);
            (
                ((dwell_start + offset) * fs).round() as usize,
                (self.gap_s * fs).round() as usize,
            )
        };

        let file = File::create(path).expect("create rig2 file");
        let mut out = BufWriter::new(file);
        writeln!(out, "Time [s],Fz [kN],Fx [N],Fy [N],Spindle [rpm]").unwrap();

        let mut angle = 0.0_f64;
        let spike_p = 0.3 / fs;
        for i in 0..n_samples {
            let t = i as f64 * dt;
            let n_rpm = if t >= t_stop { 0.0 } else { speed.value(t) };
            angle += 2.0 * PI * n_rpm / 60.0 * dt;
            let v = 2.0 * PI * self.track_radius_m * n_rpm; // m/min
            let f_n = load_n
                * (1.0
                    + 0.015 * (2.0 * PI * pulsation_hz * t + pulsation_phase).sin()
                    + 0.01 * (angle + runout_phase).sin());
            let runin = if t >= t_slide {
                1.0 + 0.25 * (-(t - t_slide) / 0.25).exp()
            } else {
                1.25
            };
            let mu = mu_law(load_n, v) * runin;
            let f_t = mu * f_n;

            let e_n: f64 = StandardNormal.sample(&mut rng);
            let e_t: f64 = StandardNormal.sample(&mut rng);
            let e_r: f64 = StandardNormal.sample(&mut rng);
            let e_s: f64 = StandardNormal.sample(&mut rng);
            let mut fz = f_n + offsets[0] + drifts[0] * t + 2.0 * e_n;
            let mut fx = -f_t + offsets[1] + drifts[1] * t + 0.8 * e_t;
            let fy = radial_ratio * f_n + offsets[2] + drifts[2] * t + 0.5 * e_r;
            if rng.gen::<f64>() < spike_p {
                let amp = rng.gen_range(20.0..40.0) * if rng.gen::<bool>() { 1.0 } else { -1.0 };
                if rng.gen::<bool>() {
                    fz += amp;
                } else {
                    fx += amp;
                }
            }
            let rpm_meas = n_rpm * (1.0 + 0.003 * e_s);

            if i >= gap_start && i < gap_start + gap_len {
                continue;
            }
            writeln!(
                out,
                "{:.6},{},{},{},{}",
                t * self.clock_factor,
                sig6(fz / 1000.0),
                sig6(fx),
                sig6(fy),
                sig6(rpm_meas)
            )
            .unwrap();
        }
        out.flush().expect("write rig2 file");
    }
}
