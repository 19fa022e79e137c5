//! FRF estimation on analytic linear systems excited by half-sine hammer pulses.

use greybox_tribo::frf::{estimate, find_impacts, ImpactConfig, ImpactRecording};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::PI;

/// A chain of masses: ground –k[0]– m[0] –k[1]– m[1] …; dampers c in parallel. Force on mass 0,
/// response = displacement of mass 0. Integrated with RK4 at `sub` substeps per sample.
struct Chain {
    m: Vec<f64>,
    k: Vec<f64>,
    c: Vec<f64>,
}

impl Chain {
    fn accel(&self, x: &[f64], v: &[f64], f0: f64) -> Vec<f64> {
        let n = self.m.len();
        (0..n)
            .map(|i| {
                let left = if i == 0 { -self.k[0] * x[0] - self.c[0] * v[0] } else { -self.k[i] * (x[i] - x[i - 1]) - self.c[i] * (v[i] - v[i - 1]) };
                let right = if i + 1 < n { self.k[i + 1] * (x[i + 1] - x[i]) + self.c[i + 1] * (v[i + 1] - v[i]) } else { 0.0 };
                (left + right + if i == 0 { f0 } else { 0.0 }) / self.m[i]
            })
            .collect()
    }

    /// Receptance H(ω) = X0/F0 by solving the complex dynamic stiffness system.
    fn receptance(&self, f_hz: f64) -> (f64, f64) {
        let w = 2.0 * PI * f_hz;
        let n = self.m.len();
        // tridiagonal complex system (K − ω²M + jωC) x = e0, solved by Gaussian elimination
        let mut a = vec![vec![(0.0f64, 0.0f64); n]; n];
        for i in 0..n {
            let kk = self.k[i] + if i + 1 < n { self.k[i + 1] } else { 0.0 };
            let cc = self.c[i] + if i + 1 < n { self.c[i + 1] } else { 0.0 };
            a[i][i] = (kk - w * w * self.m[i], w * cc);
            if i + 1 < n {
                a[i][i + 1] = (-self.k[i + 1], -w * self.c[i + 1]);
                a[i + 1][i] = (-self.k[i + 1], -w * self.c[i + 1]);
            }
        }
        let mul = |p: (f64, f64), q: (f64, f64)| (p.0 * q.0 - p.1 * q.1, p.0 * q.1 + p.1 * q.0);
        let div = |p: (f64, f64), q: (f64, f64)| {
            let d = q.0 * q.0 + q.1 * q.1;
            ((p.0 * q.0 + p.1 * q.1) / d, (p.1 * q.0 - p.0 * q.1) / d)
        };
        let mut b = vec![(0.0, 0.0); n];
        b[0] = (1.0, 0.0);
        for k in 0..n {
            for i in k + 1..n {
                let f = div(a[i][k], a[k][k]);
                for j in k..n {
                    let t = mul(f, a[k][j]);
                    a[i][j] = (a[i][j].0 - t.0, a[i][j].1 - t.1);
                }
                let t = mul(f, b[k]);
                b[i] = (b[i].0 - t.0, b[i].1 - t.1);
            }
        }
        let mut x = vec![(0.0, 0.0); n];
        for k in (0..n).rev() {
            let mut s = b[k];
            for j in k + 1..n {
                let t = mul(a[k][j], x[j]);
                s = (s.0 - t.0, s.1 - t.1);
            }
            x[k] = div(s, a[k][k]);
        }
        x[0]
    }

    /// Hammer and response recordings: impacts of `amps` (N) every `period_s`, half-sine
    /// pulse of 3 ms (30 samples at 10 kHz, so the sampled force represents the pulse).
    fn record(&self, fs: f64, period_s: f64, amps: &[f64], noise_y: f64, seed: u64) -> ImpactRecording {
        let sub = 10;
        let n_samples = (period_s * amps.len() as f64 * fs) as usize + (0.05 * fs) as usize;
        let dt = 1.0 / fs / sub as f64;
        let pulse = 3e-3;
        let force = |t: f64| {
            let k = (t / period_s).floor() as usize;
            let tl = t - k as f64 * period_s - 0.02;
            if k < amps.len() && (0.0..pulse).contains(&tl) {
                amps[k] * (PI * tl / pulse).sin()
            } else {
                0.0
            }
        };
        let n = self.m.len();
        let (mut x, mut v) = (vec![0.0; n], vec![0.0; n]);
        let mut hammer = Vec::with_capacity(n_samples);
        let mut resp = Vec::with_capacity(n_samples);
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let normal = Normal::new(0.0, 1.0).unwrap();
        for s in 0..n_samples {
            let t0 = s as f64 / fs;
            hammer.push(force(t0));
            resp.push(x[0] + noise_y * normal.sample(&mut rng));
            for j in 0..sub {
                let t = t0 + j as f64 * dt;
                let add = |a: &[f64], b: &[f64], h: f64| a.iter().zip(b).map(|(p, q)| p + h * q).collect::<Vec<f64>>();
                let a1 = self.accel(&x, &v, force(t));
                let (x2, v2) = (add(&x, &v, dt / 2.0), add(&v, &a1, dt / 2.0));
                let a2 = self.accel(&x2, &v2, force(t + dt / 2.0));
                let (x3, v3) = (add(&x, &v2, dt / 2.0), add(&v, &a2, dt / 2.0));
                let a3 = self.accel(&x3, &v3, force(t + dt / 2.0));
                let (x4, v4) = (add(&x, &v3, dt), add(&v, &a3, dt));
                let a4 = self.accel(&x4, &v4, force(t + dt));
                for i in 0..n {
                    x[i] += dt / 6.0 * (v[i] + 2.0 * v2[i] + 2.0 * v3[i] + v4[i]);
                    v[i] += dt / 6.0 * (a1[i] + 2.0 * a2[i] + 2.0 * a3[i] + a4[i]);
                }
            }
        }
        ImpactRecording { source: "simulated".into(), sample_rate_hz: fs, hammer, response: resp }
    }
}

fn sdof() -> Chain {
    let (m, fnat, zeta) = (1.0, 100.0, 0.01);
    let w = 2.0 * PI * fnat;
    Chain { m: vec![m], k: vec![m * w * w], c: vec![2.0 * zeta * m * w] }
}

#[test]
fn sdof_without_noise() {
    let cfg = ImpactConfig { block_s: 2.0, ..Default::default() };
    let rec = sdof().record(10000.0, 2.2, &[100.0, 80.0, 120.0], 0.0, 1);
    let frf = estimate(&[rec], &cfg).unwrap();
    assert_eq!(frf.impacts_used, 3);
    let df = frf.frequency_hz[1];
    for (k, f) in frf.frequency_hz.iter().enumerate() {
        if *f > 2.0 && *f < 300.0 {
            let (h1, h2) = (frf.h1[k].0, frf.h2[k].0);
            assert!((h1 - h2).norm() <= 1e-6 * h1.norm(), "H1 ≠ H2 at {f} Hz");
            assert!(frf.coherence[k] > 1.0 - 1e-9, "coherence {} at {f} Hz", frf.coherence[k]);
        }
    }
    let res = frf.resonances(&cfg, 3);
    let r = res[0];
    assert!((r.frequency_hz - 100.0).abs() <= df, "resonance at {} Hz", r.frequency_hz);
    assert!((r.damping - 0.01).abs() <= 0.05 * 0.01, "ζ = {} (measured {})", r.damping, r.damping_measured);
    assert!(r.damping_measured > 0.012, "the exponential window adds damping: {}", r.damping_measured);
    // magnitude at the resonance line against the analytic receptance (window-broadened peak
    // compared on the line nearest 100 Hz is not exact; compare away from resonance instead)
    let k = (50.0 / df) as usize;
    let exact = sdof().receptance(frf.frequency_hz[k]);
    let exact = (exact.0 * exact.0 + exact.1 * exact.1).sqrt();
    assert!((frf.h1[k].0.norm() / exact - 1.0).abs() < 0.02, "{} vs {exact}", frf.h1[k].0.norm());
}

#[test]
fn noise_on_the_response_two_dof() {
    // ground –k1– m1 –k2– m2: driving-point receptance at m1 has an anti-resonance at √(k2/m2) = 150 Hz
    let w2 = 2.0 * PI * 150.0;
    let w1 = 2.0 * PI * 120.0;
    let sys = Chain { m: vec![1.0, 1.0], k: vec![w1 * w1, w2 * w2], c: vec![2.0 * 0.01 * w1, 2.0 * 0.01 * w2] };
    let clean = sys.record(10000.0, 2.2, &[100.0; 12], 0.0, 3);
    let peak_y = clean.response.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let noisy = sys.record(10000.0, 2.2, &[100.0; 12], 0.01 * peak_y, 3);
    let cfg = ImpactConfig { block_s: 2.0, exponential_end: 0.05, ..Default::default() };
    let frf = estimate(&[noisy], &cfg).unwrap();
    assert_eq!(frf.impacts_used, 12);
    let df = frf.frequency_hz[1];
    let at = |f: f64| (f / df).round() as usize;
    // anti-resonance: coherence drops there, and H2 is biased up while H1 is not
    let ka = at(150.0);
    let (lo_k, lo) = (at(140.0)..=at(160.0)).map(|k| (k, frf.coherence[k])).fold((0, 2.0), |b, x| if x.1 < b.1 { x } else { b });
    assert!((lo_k as f64 - ka as f64).abs() * df <= 2.0, "coherence minimum at {} Hz", lo_k as f64 * df);
    assert!(lo < 0.9, "coherence at the anti-resonance {lo}");
    let res = frf.resonances(&cfg, 2);
    for r in &res {
        let k = at(r.frequency_hz);
        assert!(frf.coherence[k] > 0.99, "coherence at resonance {} Hz: {}", r.frequency_hz, frf.coherence[k]);
    }
    // H1 unbiased away from the anti-resonance: within 3 % of the analytic receptance of the
    // exponentially windowed system (extra decay 1/τ ⇒ evaluate at the damped frequency line)
    let k = at(60.0);
    let e = sys.receptance(frf.frequency_hz[k]);
    let exact = (e.0 * e.0 + e.1 * e.1).sqrt();
    assert!((frf.h1[k].0.norm() / exact - 1.0).abs() < 0.03, "{} vs {exact}", frf.h1[k].0.norm());
    assert!(frf.h2[ka].0.norm() > frf.h1[ka].0.norm(), "H2 biased upward at the anti-resonance");
}

#[test]
fn bad_impact_recordings() {
    let cfg = ImpactConfig::default();
    let mut rec = sdof().record(10000.0, 1.2, &[100.0, 100.0], 0.0, 1);
    // clipped: flatten the first pulse top
    let peak = rec.hammer.iter().cloned().fold(0.0, f64::max);
    for v in rec.hammer.iter_mut() {
        if *v > 0.6 * peak {
            *v = 0.6 * peak;
        }
    }
    let e = find_impacts(&rec, &cfg).unwrap_err().to_string();
    assert!(e.contains("no usable impact") && e.contains("clipped"), "{e}");
    // no impact
    let zero = ImpactRecording { source: "z.csv".into(), sample_rate_hz: 1000.0, hammer: vec![0.0; 5000], response: vec![0.0; 5000] };
    let e = find_impacts(&zero, &cfg).unwrap_err().to_string();
    assert!(e.contains("z.csv") && e.contains("no impact found"), "{e}");
    // double hit: a second tap 50 ms after the first
    let mut dbl = sdof().record(10000.0, 1.2, &[100.0], 0.0, 1);
    let i0 = dbl.hammer.iter().position(|v| *v > 10.0).unwrap();
    for k in 0..5 {
        dbl.hammer[i0 + 500 + k] = 50.0;
    }
    let e = find_impacts(&dbl, &cfg).unwrap_err().to_string();
    assert!(e.contains("double hit"), "{e}");
    // mismatched sampling rates
    let a = sdof().record(10000.0, 1.2, &[100.0], 0.0, 1);
    let mut b = a.clone();
    b.sample_rate_hz = 4000.0;
    b.source = "b.csv".into();
    let e = estimate(&[a, b], &cfg).unwrap_err().to_string();
    assert!(e.contains("b.csv") && e.contains("differs"), "{e}");
}
