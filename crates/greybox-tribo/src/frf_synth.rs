//! A virtual impact-hammer test: a chain of masses, springs and dampers (ground – k₀ – m₀ –
//! k₁ – m₁ …) hit on mass 0 by half-sine hammer pulses, integrated with classical RK4 at ten
//! substeps per sample. Used by the tests (analytic FRFs) and by `greybox demo`.

use crate::frf::ImpactRecording;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::f64::consts::PI;

/// The chain; response = displacement of mass 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// Masses, kg.
    pub m: Vec<f64>,
    /// Springs, N/m (k[0] to ground).
    pub k: Vec<f64>,
    /// Dampers, N·s/m (in parallel with the springs).
    pub c: Vec<f64>,
}

impl Chain {
    /// A single-degree-of-freedom system of mass `m_kg`, natural frequency `f_hz` and damping ratio `zeta`.
    pub fn sdof(m_kg: f64, f_hz: f64, zeta: f64) -> Self {
        let w = 2.0 * PI * f_hz;
        Chain {
            m: vec![m_kg],
            k: vec![m_kg * w * w],
            c: vec![2.0 * zeta * m_kg * w],
        }
    }

    /// Accelerations of the masses for positions x, velocities v and force f0 on mass 0.
    fn accel(&self, x: &[f64], v: &[f64], f0: f64) -> Vec<f64> {
        let n = self.m.len();
        (0..n)
            .map(|i| {
                let left = if i == 0 {
                    -self.k[0] * x[0] - self.c[0] * v[0]
                } else {
                    -self.k[i] * (x[i] - x[i - 1]) - self.c[i] * (v[i] - v[i - 1])
                };
                let right = if i + 1 < n {
                    self.k[i + 1] * (x[i + 1] - x[i]) + self.c[i + 1] * (v[i + 1] - v[i])
                } else {
                    0.0
                };
                (left + right + if i == 0 { f0 } else { 0.0 }) / self.m[i]
            })
            .collect()
    }

    /// Receptance H(ω) = X₀/F₀ (m/N) as (re, im), by solving (K − ω²M + jωC) x = e₀.
    pub fn receptance(&self, f_hz: f64) -> (f64, f64) {
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
                let pivot_row = a[k].clone();
                for (aij, akj) in a[i].iter_mut().zip(pivot_row).skip(k) {
                    let t = mul(f, akj);
                    *aij = (aij.0 - t.0, aij.1 - t.1);
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

    /// Hammer and response recordings at `fs`: impacts of `amps` (N) every `period_s`, each a
    /// half-sine of `pulse_s` starting 20 ms into its period (a harder hammer tip gives a
    /// shorter pulse and a wider usable band, ≈ 1.3 / pulse_s); white noise of standard
    /// deviation `noise_y` (m) on the response; seeded.
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        fs: f64,
        period_s: f64,
        amps: &[f64],
        pulse_s: f64,
        noise_y: f64,
        seed: u64,
    ) -> ImpactRecording {
        let sub = 10;
        let n_samples = (period_s * amps.len() as f64 * fs) as usize + (0.05 * fs) as usize;
        let dt = 1.0 / fs / sub as f64;
        let pulse = pulse_s;
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
                let add = |a: &[f64], b: &[f64], h: f64| {
                    a.iter()
                        .zip(b)
                        .map(|(p, q)| p + h * q)
                        .collect::<Vec<f64>>()
                };
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
        ImpactRecording {
            source: "simulated".into(),
            sample_rate_hz: fs,
            hammer,
            response: resp,
        }
    }
}
