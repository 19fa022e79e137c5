//! The calibration's certainty against an independent reference: the same rule written from
//! the module documentation in numpy and scipy (`scripts/fit_certainty_reference.py`), on
//! generated calibrations that vary what a real one varies (fields 1–3, conditions 2–9,
//! evaluations 6–40 placed at random or repeated, optima inside and at the edge of what was
//! tried, an evaluation whose cut reported nothing). Runs where `GREYBOX_PYTHON` names a
//! Python with numpy and scipy (`.ci/run` sets it); skips otherwise.

use greybox_sweep::fit_certainty::{certainty, Evaluation};
use greybox_sweep::search::FitField;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use std::process::Command;

/// A generated calibration: fields, evaluations as `calibration.json` keeps them.
fn generated(seed: u64) -> (Vec<FitField>, Vec<Evaluation>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let nf = rng.gen_range(1..=3);
    let conditions = rng.gen_range(2..=9);
    let count = rng.gen_range(6..=40);
    let fields: Vec<FitField> = (0..nf)
        .map(|j| FitField::new(&format!("f{j}"), [0.0, 1.0], false))
        .collect();
    // per field: a true optimum (sometimes at the edge) and a sensitivity (sometimes none)
    let optimum: Vec<f64> = (0..nf)
        .map(|_| match rng.gen_range(0..4) {
            0 => 0.0,
            _ => rng.gen_range(0.2..0.8),
        })
        .collect();
    let weight: Vec<f64> = (0..nf)
        .map(|_| {
            if rng.gen_bool(0.3) {
                0.0
            } else {
                rng.gen_range(0.05..1.0)
            }
        })
        .collect();
    let offset: Vec<f64> = (0..conditions).map(|_| rng.gen_range(0.0..0.2)).collect();
    let noise = rng.gen_range(0.001..0.05);
    let mut evals: Vec<Evaluation> = Vec::new();
    for k in 0..count {
        if k > 3 && rng.gen_bool(0.1) {
            // a value tried again: the same cuts
            let again = evals[rng.gen_range(0..evals.len())].clone();
            evals.push(again);
            continue;
        }
        let p: Vec<f64> = (0..nf).map(|_| rng.gen_range(0.0..1.0)).collect();
        let errors: Vec<f64> = (0..conditions)
            .map(|i| {
                let scale = 0.5 + i as f64 / conditions as f64;
                let miss: f64 = (0..nf)
                    .map(|j| weight[j] * scale * (p[j] - optimum[j]).abs())
                    .sum();
                offset[i] + miss + noise * rng.gen_range(-1.0..1.0)
            })
            .collect();
        evals.push(Evaluation::new(p, errors));
    }
    if rng.gen_bool(0.3) {
        let mut blind = evals[0].clone();
        blind.parameters[0] = 0.999;
        blind.condition_errors[0] = f64::INFINITY;
        evals.push(Evaluation::new(blind.parameters, blind.condition_errors));
    }
    (fields, evals)
}

#[test]
fn the_certainty_matches_an_independent_numpy_scipy_reference() {
    let Some(py) = std::env::var("GREYBOX_PYTHON")
        .ok()
        .filter(|p| !p.is_empty())
    else {
        eprintln!("GREYBOX_PYTHON not set: skipping the numpy/scipy reference");
        return;
    };
    let script =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/fit_certainty_reference.py");
    let cases: Vec<_> = (0..60).map(generated).collect();
    let docs: Vec<serde_json::Value> = cases
        .iter()
        .map(|(fields, evals)| {
            serde_json::json!({
                "searched": fields.iter().map(|f| f.field.clone()).collect::<Vec<_>>(),
                "evaluations": evals,
            })
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("calibrations.json");
    std::fs::write(&path, serde_json::to_string(&docs).unwrap()).unwrap();
    let out = Command::new(&py).arg(&script).arg(&path).output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let references: Vec<serde_json::Value> = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(references.len(), cases.len());
    let (mut some, mut bounded, mut open) = (0, 0, 0);
    for (seed, ((fields, evals), reference)) in cases.iter().zip(&references).enumerate() {
        let Some(c) = certainty(fields, evals) else {
            assert!(reference.is_null(), "seed {seed}: {reference}");
            continue;
        };
        some += 1;
        let r = reference;
        assert_eq!(r["conditions"], c.conditions, "seed {seed}");
        assert_eq!(r["evaluations"], c.evaluations, "seed {seed}");
        assert_eq!(r["as_good_as_best"], c.as_good_as_best, "seed {seed}: {r}");
        for (f, rf) in c.fields.iter().zip(r["fields"].as_array().unwrap()) {
            let g = |k: &str| rf[k].as_f64().unwrap();
            assert_eq!(
                (f.value, f.low, f.high, f.tried),
                (
                    g("value"),
                    g("low"),
                    g("high"),
                    [
                        rf["tried"][0].as_f64().unwrap(),
                        rf["tried"][1].as_f64().unwrap()
                    ]
                ),
                "seed {seed}: {f:?} against {rf}"
            );
            assert_eq!(rf["bounded_below"], f.bounded_below, "seed {seed}");
            assert_eq!(rf["bounded_above"], f.bounded_above, "seed {seed}");
            if f.bounded_below && f.bounded_above {
                bounded += 1;
            } else {
                open += 1;
            }
        }
    }
    // the generated calibrations reach every case: no interval, bounded fields, open ones
    assert!(
        some > 40 && bounded > 5 && open > 5,
        "{some} {bounded} {open}"
    );
}
