//! Virtual tests for the steady-state rule (issue 58, rule 5), each with its ground truth and
//! every free choice drawn from the seed. Nothing here uses `greybox_tribo`.
//!
//! * [`run_in`]: one constant test whose μ starts 20–100 % above (or 20–50 % below) its
//!   final level and settles exponentially over 3–15 % of the test.
//! * [`drifting`]: a 40–60 min test whose μ never settles: a steady drift of 10–40 % of its
//!   level over the test plus a wander (Ornstein–Uhlenbeck, 30 s–3 min correlation time).
//! * [`stick_slip`]: a saw-tooth of slow rises and sudden slips (3–30 Hz, drops of 0.02–0.1
//!   in μ) on noise, or (`with = false`) the same test without it, whose μ wanders slowly
//!   by as much as the saw-tooth's height.
//!
//! Every test is loaded at 5–80 N with unloaded windows of 5 s at each end; noise laws as in
//! [`super::sure::Noise`].

use super::stream_rng;
use super::sure::{ramp, Clock, Noise, NoiseStream, Trace};
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// The trace of a constant test of `dur` s at `load` N from μ(t) (t from the start of
/// sliding), with force noise σ_μ·load of law `law` (`(σ_μ, law)`); unloaded 5 s at each end.
fn constant_test(
    name: String,
    clock: &Clock,
    load: f64,
    dur: f64,
    (sigma_mu, law): (f64, Noise),
    rng: &mut rand_chacha::ChaCha8Rng,
    mut mu: impl FnMut(f64, &mut rand_chacha::ChaCha8Rng) -> f64,
) -> Trace {
    let (t_on, t_off) = (5.0, 5.0 + dur);
    let mut noise = NoiseStream::new(law);
    let mut tr = Trace {
        name,
        ..Default::default()
    };
    for tc in clock.times(t_off + 5.0) {
        let t = tc / (1.0 + clock.drift);
        let f = load * ramp((t - t_on) / 0.3, true) * (1.0 - ramp((t - t_off) / 0.3, true));
        let sliding = (t_on + 0.5..t_off).contains(&t);
        let m = if sliding {
            mu(t - t_on - 0.5, rng)
        } else {
            0.0
        };
        tr.time_s.push(tc);
        tr.normal_n.push(f + 0.003 * load * noise.next(rng));
        tr.tangential_n
            .push(m * f * ramp((t - t_on - 0.5) / 0.2, true) + sigma_mu * load * noise.next(rng));
    }
    tr
}

/// See the module docs: 60–600 s at 10–200 Hz. Returns the trace, the final μ and the
/// run-in's time constant, s.
pub fn run_in(seed: u64) -> (Trace, f64, f64) {
    let mut rng = stream_rng(seed, 70);
    let clock = Clock::draw(&mut rng, &[10.0, 50.0, 100.0, 200.0]);
    let law = Noise::draw(&mut rng);
    let (load, mu_inf) = (rng.gen_range(5.0..80.0), rng.gen_range(0.1..0.7));
    let dur = rng.gen_range(60.0..600.0);
    let amp = if rng.gen_bool(0.75) {
        rng.gen_range(0.2..1.0)
    } else {
        -rng.gen_range(0.2..0.5)
    };
    let tau = dur * rng.gen_range(0.03..0.15);
    let sigma = rng.gen_range(0.003..0.015);
    let tr = constant_test(
        format!("run_in_{seed}.csv"),
        &clock,
        load,
        dur,
        (sigma, law),
        &mut rng,
        |t, _| mu_inf * (1.0 + amp * (-t / tau).exp()),
    );
    (tr, mu_inf, tau)
}

/// See the module docs: 1–5 Hz. Returns the trace and μ's expected value as a function of
/// the time since sliding began (the drift, without the wander), s.
pub fn drifting(seed: u64) -> (Trace, impl Fn(f64) -> f64) {
    let mut rng = stream_rng(seed, 71);
    let clock = Clock::draw(&mut rng, &[1.0, 2.0, 5.0]);
    let law = Noise::draw(&mut rng);
    let (load, mu0) = (rng.gen_range(5.0..80.0), rng.gen_range(0.15..0.6));
    let dur = rng.gen_range(2400.0..3600.0);
    let rise = mu0 * rng.gen_range(0.1..0.4) * if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
    let tau: f64 = rng.gen_range(30.0..180.0);
    let sd = mu0 * rng.gen_range(0.01..0.04);
    let sigma = rng.gen_range(0.002..0.01);
    let mut ou = 0.0f64;
    let mut last = 0.0f64;
    let expected = move |t: f64| mu0 + rise * (t / dur).clamp(0.0, 1.0);
    let tr = constant_test(
        format!("drifting_{seed}.csv"),
        &clock,
        load,
        dur,
        (sigma, law),
        &mut rng,
        |t, rng| {
            let phi = (-(t - last).max(0.0) / tau).exp();
            let e: f64 = StandardNormal.sample(rng);
            ou = phi * ou + sd * (1.0 - phi * phi).sqrt() * e;
            last = t;
            expected(t) + ou
        },
    );
    (tr, expected)
}

/// See the module docs: 60–180 s at 200–1000 Hz. Returns the trace and μ's mean.
pub fn stick_slip(seed: u64, with: bool) -> (Trace, f64) {
    let mut rng = stream_rng(seed, 72);
    let clock = Clock::draw(&mut rng, &[200.0, 500.0, 1000.0]);
    let law = Noise::draw(&mut rng);
    let (load, mu) = (rng.gen_range(5.0..80.0), rng.gen_range(0.2..0.6));
    let dur = rng.gen_range(60.0..180.0);
    let freq = rng.gen_range(3.0..30.0);
    let drop = rng.gen_range(0.02..0.1);
    let sigma = rng.gen_range(0.001..0.004);
    // the wander: a sum of slow sines of the saw-tooth's height, periods 10–60 s
    let waves: Vec<(f64, f64)> = (0..3)
        .map(|_| (rng.gen_range(10.0..60.0), rng.gen_range(0.0..1.0)))
        .collect();
    let tr = constant_test(
        format!("stick_slip_{seed}_{with}.csv"),
        &clock,
        load,
        dur,
        (sigma, law),
        &mut rng,
        |t, _| {
            if with {
                // rises linearly over the stick, drops at the slip
                mu + drop * ((t * freq).fract() - 0.5)
            } else {
                mu + drop / 3.0
                    * waves
                        .iter()
                        .map(|(p, ph)| (2.0 * std::f64::consts::PI * (t / p + ph)).sin())
                        .sum::<f64>()
            }
        },
    );
    (tr, mu)
}
