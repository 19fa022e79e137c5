//! A Stribeck sweep without a speed channel (issue 58, rule 4): one loaded test whose sliding
//! speed steps through 8–24 levels, log-spaced over two to three decades, falling or rising,
//! μ changing level at every step — from the boundary regime (0.06–0.15) down through the mixed
//! regime by 8–25 % a step to 0.004–0.02, optionally rising again in the elastohydrodynamic
//! regime over the last steps ([`Shape::Steps`]), or the same levels joined by slow excursions
//! that take most of the time ([`Shape::MostlyRamps`]). Nothing here uses `greybox_tribo`.
//!
//! Drawn from the seed: sample rate (50, 100 or 200 Hz), clock drift and lost samples, step
//! count, each step's dwell (2–10 s) and ramp (0.1–0.6 s, linear or cosine), the load (5–60
//! N), the force channels' offsets and drift, the friction channel's sign, the noise law
//! (Gaussian, Student's t₃, Laplace, AR(1)) and its level (σ of μ 0.0002–0.001 per sample —
//! a traction force resolved to 0.01–0.05 N under 50 N — an absolute force noise, so the low-friction steps are the noisiest relative to their level), and what
//! comes before the first step (nothing, a run-in at the first speed, an unplanned step).

use super::stream_rng;
use super::sure::{ramp, Before, Clock, Noise, NoiseStream, Step, Trace};
use rand::Rng;

/// How a sweep spends its sliding time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// Dwells of 2–10 s joined by ramps of 0.1–0.6 s.
    Steps,
    /// Dwells of 1.5–2.5 s joined by excursions of 30–60 s in which μ rises steadily by 50–150 %
    /// of its level and falls back (a speed excursion through the boundary regime): the steps are a
    /// sliver of the sliding time.
    MostlyRamps,
}

/// A generated sweep: the trace (no speed channel) and the truth per step, pin 1.
pub fn sweep(seed: u64, shape: Shape) -> (Trace, Vec<Step>) {
    let mut rng = stream_rng(seed, 63);
    let clock = Clock::draw(&mut rng, &[50.0, 100.0, 200.0]);
    let law = Noise::draw(&mut rng);
    let cosine = rng.gen_bool(0.5);
    let before = [Before::Nothing, Before::RunIn, Before::ExtraStep][rng.gen_range(0..3)];
    let k: usize = rng.gen_range(8..=24);
    let v_lo: f64 = rng.gen_range(0.3..3.0); // m/min
    let decades = rng.gen_range(2.0..3.0);
    let mut vs: Vec<f64> = (0..k)
        .map(|i| v_lo * 10f64.powf(decades * i as f64 / (k - 1) as f64))
        .collect();
    // μ per speed, slowest first: falling by 8–25 % a step from the boundary level, the last
    // 0–3 steps rising by 10–30 % a step (EHL)
    let mut mus: Vec<f64> = vec![rng.gen_range(0.06..0.15)];
    let rising = rng.gen_range(0..=3usize).min(k - 5);
    for i in 1..k {
        let prev = mus[i - 1];
        mus.push(if i >= k - rising {
            prev * rng.gen_range(1.1..1.3)
        } else {
            (prev * rng.gen_range(0.75..0.92)).max(0.004 + 0.002 * i as f64 / k as f64)
        });
    }
    // a floor reached early would make neighbours equal: keep every change at least 8 %
    for i in 1..k {
        if (mus[i] / mus[i - 1] - 1.0).abs() < 0.08 {
            mus[i] = mus[i - 1] * if i >= k - rising { 1.1 } else { 0.92 };
        }
    }
    let falling = rng.gen_bool(0.5);
    if falling {
        vs.reverse();
        mus.reverse();
    }
    let (dwell, ramp_s) = match shape {
        Shape::Steps => (2.0..10.0, 0.1..0.6),
        Shape::MostlyRamps => (1.5..2.5, 30.0..60.0),
    };
    let dwells: Vec<f64> = (0..k).map(|_| rng.gen_range(dwell.clone())).collect();
    let ramps: Vec<f64> = (0..k).map(|_| rng.gen_range(ramp_s.clone())).collect();
    let load = rng.gen_range(5.0..60.0);
    let t_unl0 = rng.gen_range(2.0..4.0);
    let t_load = t_unl0 + 0.5;
    let bumps: Vec<f64> = (0..k)
        .map(|i| match shape {
            Shape::Steps => 0.0,
            Shape::MostlyRamps => mus[i] * rng.gen_range(0.5..1.5),
        })
        .collect();
    let mut pieces: Vec<(f64, f64, f64, f64, f64)> = Vec::new(); // start, ramp, from, to, bump
    let mut t = t_load + rng.gen_range(0.2..0.6);
    let mut prev = 0.0;
    let run_in_start = t;
    if before != Before::Nothing {
        let m = match before {
            Before::ExtraStep => mus[0] * rng.gen_range(1.3..1.8),
            _ => mus[0],
        };
        pieces.push((t, 0.3, 0.0, m, 0.0));
        t += rng.gen_range(3.0..5.0);
        prev = m;
    }
    for i in 0..k {
        pieces.push((t, ramps[i], prev, mus[i], bumps[i]));
        t += ramps[i] + dwells[i];
        prev = mus[i];
    }
    pieces.push((t, 0.3, prev, 0.0, 0.0));
    let t_lift = t + 0.5;
    let t_end = t_lift + 0.5 + rng.gen_range(2.0..4.0);
    let run_in: (f64, f64) = (rng.gen_range(0.3..0.6), rng.gen_range(0.4..0.8));
    let (o_n, o_t, drift_t) = (
        rng.gen_range(-1.0..1.0),
        rng.gen_range(-0.05..0.05),
        rng.gen_range(-0.02..0.02),
    );
    let sigma_mu = rng.gen_range(0.0002..0.001);
    let sign = if rng.gen_bool(0.3) { -1.0 } else { 1.0 };
    let mut noise = NoiseStream::new(law);
    let mut tr = Trace {
        name: format!("stribeck_{seed}.csv"),
        ..Default::default()
    };
    for tc in clock.times(t_end) {
        let t = tc / (1.0 + clock.drift);
        let f = load * ramp((t - t_unl0) / 0.5, cosine) * (1.0 - ramp((t - t_lift) / 0.5, cosine));
        let mut mu = match pieces.iter().rev().find(|p| p.0 <= t) {
            Some(&(s, r, a, b, bump)) => {
                let x = ((t - s) / r).clamp(0.0, 1.0);
                a + (b - a) * ramp(x, cosine) + bump * (1.0 - (2.0 * x - 1.0).abs())
            }
            None => 0.0,
        };
        if before == Before::RunIn && t >= run_in_start {
            mu *= 1.0 + run_in.0 * (-(t - run_in_start) / run_in.1).exp();
        }
        tr.time_s.push(tc);
        tr.normal_n
            .push(f + o_n + 0.002 * load * noise.next(&mut rng));
        tr.tangential_n.push(
            sign * (mu * f + sigma_mu * load * noise.next(&mut rng)) + o_t + drift_t * t / t_end,
        );
    }
    let truth = (0..k)
        .map(|i| Step {
            pin: 1,
            step: i as u32 + 1,
            normal_force_n: load,
            velocity_m_per_min: vs[i],
            duration_s: ramps[i] + dwells[i],
            mu: mus[i],
        })
        .collect();
    (tr, truth)
}
