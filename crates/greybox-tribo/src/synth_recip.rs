//! A virtual linear reciprocating rig (ASTM G133 ball-on-flat): recordings with known μ per
//! direction, for tests and demonstrations of [`crate::reciprocating`].
//!
//! The stroke is sinusoidal, x(t) = L/2·(1 − cos 2πft); the friction force is
//! μ_dir(t)·F_N·sign(v) with a static-friction overshoot after every reversal (decaying over
//! `transient_s`), a run-in excess of μ decaying exponentially over the first cycles, and
//! Gaussian noise on both forces. The test is loaded after `rest_s` of unloaded recording and
//! unloaded again for `rest_s` at the end (so the baseline can be taken).

use greybox_recording::Recording;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// What the virtual reciprocating rig runs.
#[derive(Debug, Clone, PartialEq)]
pub struct RecipSpec {
    pub sample_rate_hz: f64,
    /// Cycle frequency, Hz.
    pub frequency_hz: f64,
    /// Stroke length, m.
    pub stroke_m: f64,
    pub cycles: usize,
    pub normal_n: f64,
    /// Steady μ moving forward (increasing x) and backward.
    pub mu_forward: f64,
    pub mu_backward: f64,
    /// Run-in: μ starts this much higher and decays with time constant `run_in_cycles`.
    pub run_in_excess: f64,
    pub run_in_cycles: f64,
    /// Static-friction overshoot after a reversal, as a share of the sliding force.
    pub overshoot: f64,
    pub transient_s: f64,
    /// Noise σ of both forces, N.
    pub noise_n: f64,
    /// Unloaded time before and after the test, s.
    pub rest_s: f64,
    pub seed: u64,
}

impl Default for RecipSpec {
    /// 5 Hz, 1 mm stroke, 10 N, μ 0.30 forward / 0.26 backward, 100 cycles.
    fn default() -> Self {
        RecipSpec {
            sample_rate_hz: 1000.0,
            frequency_hz: 5.0,
            stroke_m: 1e-3,
            cycles: 100,
            normal_n: 10.0,
            mu_forward: 0.30,
            mu_backward: 0.26,
            run_in_excess: 0.08,
            run_in_cycles: 6.0,
            overshoot: 0.4,
            transient_s: 0.004,
            noise_n: 0.05,
            rest_s: 0.5,
            seed: 7,
        }
    }
}

/// The recording (with its position channel) and, per sample, the block number of its
/// half-stroke (1, 2, … from the first loaded half-stroke; 0 while unloaded).
pub fn reciprocating_recording(spec: &RecipSpec) -> (Recording, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
    let noise = Normal::new(0.0, spec.noise_n.max(1e-15)).expect("σ > 0");
    let dt = 1.0 / spec.sample_rate_hz;
    let test_s = spec.cycles as f64 / spec.frequency_hz;
    let n = ((test_s + 2.0 * spec.rest_s) * spec.sample_rate_hz).round() as usize;
    let half = 0.5 / spec.frequency_hz;
    let w = 2.0 * std::f64::consts::PI * spec.frequency_hz;
    let mut rec = Recording::new("recip.csv", Vec::new(), Vec::new(), Vec::new());
    let (mut x, mut block) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for k in 0..n {
        let t = k as f64 * dt;
        let ts = t - spec.rest_s;
        let sliding = ts >= 0.0 && ts < test_s;
        let pos = if sliding {
            0.5 * spec.stroke_m * (1.0 - (w * ts).cos())
        } else {
            0.0
        };
        let (f_n, f_t) = if sliding {
            let since = ts % half;
            let forward = ((ts / half) as usize).is_multiple_of(2);
            let cyc = ts * spec.frequency_hz;
            let mu = if forward {
                spec.mu_forward
            } else {
                spec.mu_backward
            } + spec.run_in_excess * (-cyc / spec.run_in_cycles).exp();
            let shape = 1.0 + spec.overshoot * (-since / spec.transient_s).exp();
            let ramp = (since / (0.2 * spec.transient_s)).min(1.0);
            let s = if forward { 1.0 } else { -1.0 };
            (spec.normal_n, s * mu * spec.normal_n * shape * ramp)
        } else {
            (0.0, 0.0)
        };
        rec.time_s.push(t);
        rec.normal_n.push(f_n + noise.sample(&mut rng));
        rec.tangential_n.push(f_t + noise.sample(&mut rng));
        x.push(pos);
        block.push(if sliding {
            (ts / half).floor() + 1.0
        } else {
            0.0
        });
    }
    rec.position_m = Some(x);
    (rec, block)
}

/// The loaded part of a recording as a CETR/Bruker UMT Data Viewer export: a preamble, then
/// one block per half-stroke (`Step No. k`, its settings, the header
/// `Fx,Fz,Z,Y,X,V1,V2,V3,T,Ff,COF` and the units row `g,g,mm,…,sec,g,`), forces in grams-force
/// with Fz negative, Fx signed by direction, Ff = |Fx|, X the constant radius setting in mm,
/// T restarting at 0 in every block.
pub fn umt_export_text(rec: &Recording, block: &[f64]) -> String {
    use std::fmt::Write as _;
    const G: f64 = 9.806_65e-3; // N per gram-force
    let mut runs: Vec<(usize, usize)> = Vec::new();
    let mut s = 0;
    for k in 1..=block.len() {
        if k == block.len() || block[k] != block[s] {
            if block[s] > 0.0 {
                runs.push((s, k));
            }
            s = k;
        }
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "Created by CETR Data Viewer ver.2.19.106 05/12/22 14:43:46"
    );
    let _ = writeln!(
        out,
        "Created by CETR UMT ver.1.136.257 12 May 2022 12:21:50"
    );
    let _ = writeln!(
        out,
        "Total number of runs - 1\nTotal number of steps = {}",
        runs.len()
    );
    let _ = writeln!(out, "Indenter tip ID = 0\nC:\\data\\recip.tst\n\nRun # 1");
    let _ = writeln!(
        out,
        "Script file C:\\scripts\\recip.cts\nRun date 12 May 2022 12:21:50"
    );
    for (b, &(i, j)) in runs.iter().enumerate() {
        let _ = writeln!(out, "Step No. {}\n\nStep Type Code: 0", b + 1);
        let _ = writeln!(
            out,
            "Radius       = 3.9493\nVelocity     = 240\nSet Force    = -1000"
        );
        let _ = writeln!(
            out,
            "Duration     = {:.2}\nData Count   = {}",
            rec.time_s[j - 1] - rec.time_s[i],
            j - i
        );
        let _ = writeln!(out, "Started at: 12:21:58.029 12 May 2022\n");
        let _ = writeln!(
            out,
            "Fx,Fz,Z,Y,X,V1,V2,V3,T,Ff,COF\ng,g,mm,mm,mm,mm/sec,mm/sec,mm/sec,sec,g,\n"
        );
        for k in i..j {
            let (fx, fz) = (rec.tangential_n[k] / G, -rec.normal_n[k] / G);
            let _ = writeln!(
                out,
                "{fx:.6},{fz:.6},-0.6850,0.000000,3.949250,0.050000,0.000000,0.000000,{:.4},{:.6},{:.6}",
                rec.time_s[k] - rec.time_s[i],
                fx.abs(),
                (fx / fz).abs()
            );
        }
        out.push_str("\n\n");
    }
    out
}
