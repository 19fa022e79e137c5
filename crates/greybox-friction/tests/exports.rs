//! Engine exports report their max deviation from the law, and are exact for tree ensembles.
//!
//! The independent check reads the written text back (numbers parse bit for bit) and
//! interpolates it the way the engine does — piecewise linear, written here from scratch per
//! format — at random points, at every written abscissa and at its neighbouring floats.

mod common;
use common::{model, state};
use greybox_core::units::{PressureUnit, TemperatureUnit, VelocityUnit};
use greybox_core::{ContactState, FrictionLaw};
use greybox_friction::export::{
    abaqus_checked, csv_checked, deform_checked, lsdyna_checked, parse_abaqus_friction,
    parse_frcfac, Grid, StepLines, TableOptions, Units,
};
use greybox_friction::learned::LearnedLaw;
use greybox_model::Family;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn units() -> Units {
    Units {
        pressure: PressureUnit::MPa,
        speed: VelocityUnit::MmPerS,
        temperature: TemperatureUnit::C,
    }
}

/// 21 pressures 900–2200 MPa, 24 velocities 20–250 m/min (SI).
fn grid(temperature: bool) -> Grid {
    Grid {
        pressure_pa: (0..21).map(|i| (900.0 + 65.0 * i as f64) * 1e6).collect(),
        velocity_m_s: (0..24).map(|i| (20.0 + 10.0 * i as f64) / 60.0).collect(),
        temperature_k: temperature.then(|| (0..5).map(|i| 293.15 + 100.0 * i as f64).collect()),
    }
}

/// Piecewise-linear interpolation on ascending abscissae, clamped: f(x).
fn pwl(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let n = xs.len();
    if n == 1 || x <= xs[0] {
        return ys[0];
    }
    if x >= xs[n - 1] {
        return ys[n - 1];
    }
    let j = xs.partition_point(|&a| a <= x) - 1; // xs[j] ≤ x < xs[j+1]
    if x == xs[j] {
        return ys[j];
    }
    let f = (x - xs[j]) / (xs[j + 1] - xs[j]);
    ys[j] + f * (ys[j + 1] - ys[j])
}

/// Points along an axis of written abscissae: random, each abscissa and its neighbours.
fn probes(xs: &[f64], rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    let (lo, hi) = (xs[0], xs[xs.len() - 1]);
    let mut p: Vec<f64> = (0..n).map(|_| rng.gen_range(lo..=hi)).collect();
    for &x in xs {
        p.extend(
            [x.next_down(), x, x.next_up()]
                .into_iter()
                .filter(|y| (lo..=hi).contains(y)),
        );
    }
    p
}

#[test]
fn tree_exports_are_exact_with_step_lines() {
    let law = LearnedLaw::new(
        model(
            Family::GradientBoosting,
            &["normal_force_N", "sliding_velocity_m_per_min"],
        ),
        None,
    )
    .unwrap();
    let o = TableOptions::default();
    let g = grid(false);
    // LS-DYNA: curves μ(p) per velocity, linear between curves
    let e = lsdyna_checked(&law, &g, units(), 1000, &o).unwrap();
    assert!(e.table.exact_steps);
    assert_eq!(e.deviation.unwrap().max, 0.0, "{:?}", e.deviation);
    assert!(e
        .text
        .contains("max deviation of this table (linear interpolation) from the law: 0e0"));
    let (speeds, curves) = read_lsdyna(&e.text);
    assert!(
        speeds.len() > 24 && curves[0].0.len() > 21,
        "step lines added"
    );
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut worst: f64 = 0.0;
    let vs = probes(&speeds, &mut rng, 300);
    let ps = probes(&curves[0].0, &mut rng, 300);
    for (k, &v) in vs.iter().enumerate() {
        for &p in ps.iter().skip(k % 7).step_by(7) {
            let at_curves: Vec<f64> = curves.iter().map(|(x, y)| pwl(x, y, p)).collect();
            let table = pwl(&speeds, &at_curves, v);
            let s = ContactState::new(PressureUnit::MPa.to_pa(p), VelocityUnit::MmPerS.to_m_s(v));
            worst = worst.max((table - law.mu(&s)).abs());
        }
    }
    assert_eq!(worst, 0.0);
    // Abaqus (slip rate fastest, then pressure): the same, read back
    let e = abaqus_checked(&law, &g, units(), None, &o).unwrap();
    assert_eq!(e.deviation.unwrap().max, 0.0);
    let rows = parse_abaqus_friction(&e.text, "f.inp").unwrap();
    let [nv, np, _] = e.table.shape();
    assert_eq!(rows.len(), nv * np);
    for r in rows.iter().step_by(13) {
        let s = ContactState::new(
            PressureUnit::MPa.to_pa(r[2]),
            VelocityUnit::MmPerS.to_m_s(r[1]),
        );
        assert_eq!(r[0], law.mu(&s));
    }
    // without step lines the same grid misses the steps
    let off = TableOptions {
        steps: StepLines::Off,
        ..o
    };
    let e = abaqus_checked(&law, &g, units(), None, &off).unwrap();
    assert!(!e.table.exact_steps && e.table.shape() == [24, 21, 1]);
    let d = e.deviation.unwrap().max;
    assert!(d > 1e-3, "{d}");
}

/// A curve: abscissae and ordinates.
type Curve = (Vec<f64>, Vec<f64>);

/// (velocities, one (pressures, μ) curve per velocity) of LS-DYNA cards.
fn read_lsdyna(text: &str) -> (Vec<f64>, Vec<Curve>) {
    let mut speeds = Vec::new();
    let mut curves: Vec<Curve> = Vec::new();
    let mut block = "";
    let mut skip = 0;
    for line in text.lines() {
        if line.starts_with('$') {
            continue;
        }
        if line.starts_with('*') {
            block = if line == "*DEFINE_TABLE" {
                "table"
            } else {
                "curve"
            };
            if block == "curve" {
                curves.push((Vec::new(), Vec::new()));
            }
            skip = 1; // the id line
            continue;
        }
        if skip > 0 {
            skip -= 1;
            continue;
        }
        let f: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        match block {
            "table" => speeds.push(f[0]),
            _ => {
                let c = curves.last_mut().unwrap();
                c.0.push(f[0]);
                c.1.push(f[1]);
            }
        }
    }
    (speeds, curves)
}

#[test]
fn every_format_reports_its_deviation() {
    let tree3 = LearnedLaw::new(
        model(
            Family::GradientBoosting,
            &[
                "hertz_pressure_MPa",
                "sliding_velocity_m_per_min",
                "temperature_degC",
            ],
        ),
        None,
    )
    .unwrap();
    let svr = LearnedLaw::new(
        model(
            Family::Svr,
            &["hertz_pressure_MPa", "sliding_velocity_m_per_min"],
        ),
        None,
    )
    .unwrap();
    let o = TableOptions {
        check_points: 20_000,
        ..TableOptions::default()
    };
    let (g2, g3) = (grid(false), grid(true));
    for (law, exact) in [(&tree3 as &dyn FrictionLaw, true), (&svr, false)] {
        let exports = [
            (
                "abaqus",
                abaqus_checked(law, &g3, units(), Some(450e6), &o).unwrap(),
            ),
            ("lsdyna", lsdyna_checked(law, &g2, units(), 7, &o).unwrap()),
            (
                "deform",
                deform_checked(law, &g3, 2.5, &[], (2, 1), &o).unwrap(),
            ),
            ("csv", csv_checked(law, &g3, &o).unwrap()),
        ];
        for (name, e) in exports {
            let d = e.deviation.unwrap();
            assert!(d.points >= 20_000, "{name}");
            assert_eq!(e.table.exact_steps, exact, "{name}");
            if exact {
                assert_eq!(d.max, 0.0, "{name}: {d:?}");
            } else {
                // a smooth law between grid points: small, not zero
                assert!(d.max > 0.0 && d.max < 1e-2, "{name}: {d:?}");
            }
        }
    }
    // DEFORM's FRCFAC table reads back with its step lines, μ at each written (p, T)
    let e = deform_checked(&tree3, &g3, 2.5, &[], (2, 1), &o).unwrap();
    let b = &parse_frcfac(&e.text, "d.key").unwrap()[0];
    assert!(b.pressures.len() > 21 && b.temperatures.len() > 5);
    for (k, &mu) in b.values.iter().enumerate() {
        let (ip, it) = (k % b.pressures.len(), k / b.pressures.len());
        let s = state([
            PressureUnit::MPa.to_pa(b.pressures[ip]),
            2.5,
            TemperatureUnit::C.to_k(b.temperatures[it]),
        ]);
        assert_eq!(mu, tree3.mu(&s));
    }
}
