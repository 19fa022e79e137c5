//! Seeded mutation test over model files: valid files of every family are damaged
//! structurally (indices, array lengths, numbers), re-sealed so that the content hash still
//! matches, then loaded and evaluated. Loading must either refuse with an error naming the
//! file and a field, or give a model whose predictions are finite; it must never panic and
//! never hang (a tree cycle used to make evaluation loop forever).

use greybox_learn::regressor::Regressor;
use greybox_model::column::Column;
use greybox_model::ensemble::{BoostParams, ForestParams};
use greybox_model::interval::{IntervalMethod, PredictionInterval};
use greybox_model::mlp::MlpParams;
use greybox_model::modelfile::{DomainPolicy, FeatureRange, ModelFile, SCHEMA, SCHEMA_VERSION};
use greybox_model::svr::SvrParams;
use greybox_model::Matrix;
use greybox_model::{FittedModel, Hyperparameters};
use rand::{Rng, SeedableRng};
use serde_json::Value;

fn data() -> (Matrix, Vec<f64>) {
    let mut rows = Vec::new();
    let mut y = Vec::new();
    for i in 0..40 {
        let (f, v) = (100.0 + 20.0 * (i % 8) as f64, 20.0 + 10.0 * (i / 8) as f64);
        rows.push(vec![f, v]);
        y.push(0.6 - 0.0002 * f - 0.001 * v + 0.01 * ((i * 7) % 5) as f64);
    }
    (Matrix::from_rows(&rows), y)
}

fn file(hp: Hyperparameters, model: FittedModel) -> ModelFile {
    let (x, _) = data();
    ModelFile {
        schema: SCHEMA.into(),
        schema_version: SCHEMA_VERSION,
        family: hp.family(),
        hyperparameters: hp,
        features: vec![
            Column::new("normal_force_N"),
            Column::new("sliding_velocity_m_per_min"),
        ],
        target: Column::new("cof_apparent"),
        training_domain: x
            .column_ranges()
            .into_iter()
            .map(|(min, max)| FeatureRange { min, max })
            .collect(),
        n_train: x.n_rows,
        prediction_interval: PredictionInterval {
            coverage: 0.9,
            half_width: 0.02,
            method: IntervalMethod::CvConformal,
        },
        held_out_r2: None,
        model,
        force_to_pressure: None,
        provenance: None,
        content_hash: String::new(),
    }
    .seal()
    .unwrap()
}

fn valid_files() -> Vec<ModelFile> {
    let (x, y) = data();
    let rf = ForestParams {
        n_estimators: 5,
        ..Default::default()
    };
    let gb = BoostParams {
        n_estimators: 5,
        ..Default::default()
    };
    let svr = SvrParams::default();
    let mlp = MlpParams {
        hidden_layers: vec![4, 3],
        max_epochs: 20,
        ..Default::default()
    };
    vec![
        file(
            Hyperparameters::RandomForest(rf.clone()),
            FittedModel::TreeEnsemble(rf.fit(&x, &y, 1).unwrap()),
        ),
        file(
            Hyperparameters::GradientBoosting(gb.clone()),
            FittedModel::TreeEnsemble(gb.fit(&x, &y, 1).unwrap()),
        ),
        file(
            Hyperparameters::Svr(svr.clone()),
            FittedModel::Svr(svr.fit(&x, &y, 1).unwrap()),
        ),
        file(
            Hyperparameters::Mlp(mlp.clone()),
            FittedModel::Mlp(mlp.fit(&x, &y, 1).unwrap()),
        ),
    ]
}

/// Every path to a number or an array inside `model`.
fn targets(v: &Value, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
    match v {
        Value::Number(_) => out.push(path.clone()),
        Value::Array(a) => {
            out.push(path.clone());
            for (i, x) in a.iter().enumerate() {
                path.push(i.to_string());
                targets(x, path, out);
                path.pop();
            }
        }
        Value::Object(o) => {
            for (k, x) in o {
                path.push(k.clone());
                targets(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

fn at<'a>(v: &'a mut Value, path: &[String]) -> &'a mut Value {
    path.iter().fold(v, |v, k| match v {
        Value::Array(a) => &mut a[k.parse::<usize>().unwrap()],
        Value::Object(o) => o.get_mut(k).unwrap(),
        _ => unreachable!(),
    })
}

fn mutate(v: &mut Value, rng: &mut rand_chacha::ChaCha8Rng) {
    let mut paths = Vec::new();
    targets(&v["model"], &mut vec!["model".to_string()], &mut paths);
    let p = &paths[rng.gen_range(0..paths.len())];
    let t = at(v, p);
    match t {
        Value::Array(a) => match rng.gen_range(0..3) {
            0 if !a.is_empty() => {
                let i = rng.gen_range(0..a.len());
                a.remove(i);
            }
            1 if !a.is_empty() => {
                let x = a[rng.gen_range(0..a.len())].clone();
                a.push(x);
            }
            _ => a.clear(),
        },
        _ => {
            *t = match rng.gen_range(0..7) {
                0 => Value::from(-1),
                1 => Value::from(0),
                2 => Value::from(rng.gen_range(0..64)),
                3 => Value::from(u32::MAX - 1),
                4 => Value::from(1e308),
                5 => Value::Null, // what a NaN becomes in JSON
                _ => Value::from(t.as_f64().unwrap_or(1.0) * -3.0),
            }
        }
    }
}

#[test]
fn damaged_model_files_never_panic_or_hang() {
    let files = valid_files();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026);
    let (mut refused, mut loaded) = (0, 0);
    for round in 0..3000 {
        let base = &files[round % files.len()];
        let mut v = serde_json::to_value(base).unwrap();
        for _ in 0..rng.gen_range(1..3) {
            mutate(&mut v, &mut rng);
        }
        // re-seal: the damage must get past the hash check to reach the structure check
        let Ok(mut m) = serde_json::from_value::<ModelFile>(v) else {
            refused += 1;
            continue;
        };
        m = m.seal().unwrap();
        let text = serde_json::to_string(&m).unwrap();
        let r = std::panic::catch_unwind(|| match ModelFile::parse(&text, "damaged.json") {
            Err(e) => {
                let e = e.to_string();
                assert!(e.contains("damaged.json") && e.contains("field"), "{e}");
                None
            }
            Ok(m) => {
                let mut out = Vec::new();
                for x in [[100.0, 20.0], [240.0, 60.0], [1e4, -5.0]] {
                    if let Ok(p) = m.predict(&x, DomainPolicy::Warn, 0.1) {
                        assert!(p.value.is_finite());
                        out.push(p.value);
                    }
                }
                Some(out)
            }
        });
        match r {
            Ok(None) => refused += 1,
            Ok(Some(_)) => loaded += 1,
            Err(_) => panic!("round {round}: a damaged {:?} model panicked", base.family),
        }
    }
    assert!(
        refused > 500 && loaded > 100,
        "refused {refused}, loaded {loaded}"
    );
}

/// The two defects seen by hand: a child index out of range and a cycle.
#[test]
fn tree_cycle_and_out_of_range_child_are_refused() {
    let files = valid_files();
    for (left, want) in [(0u32, "would loop"), (1_000_000, "do not exist")] {
        let mut m = files[0].clone();
        let FittedModel::TreeEnsemble(t) = &mut m.model else {
            unreachable!()
        };
        let k = t
            .nodes
            .iter()
            .position(|n| n.feature != greybox_model::tree::LEAF)
            .unwrap();
        t.nodes[k].left = left;
        let text = serde_json::to_string(&m.seal().unwrap()).unwrap();
        let e = ModelFile::parse(&text, "m.json").unwrap_err().to_string();
        assert!(
            e.contains(&format!("nodes[{k}].left")) && e.contains(want),
            "{e}"
        );
    }
    // an MLP whose layer sizes do not match its weights
    let mut m = files[3].clone();
    let FittedModel::Mlp(n) = &mut m.model else {
        unreachable!()
    };
    n.sizes[1] += 1;
    let e = ModelFile::parse(
        &serde_json::to_string(&m.seal().unwrap()).unwrap(),
        "m.json",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("model.weights[0]") || e.contains("model.biases[0]"),
        "{e}"
    );
}

/// Implausible records that used to load: a pressure per newton of 0 or below (μ 0.257 or
/// 0.527 instead of 0.403 through a law), a coverage of 5 ("500 % low/high"), an unsupported
/// schema version printed as `Some(99)`. Each is refused naming the field and the number.
#[test]
fn implausible_records_are_refused_with_the_number() {
    let base = valid_files().remove(0);
    type Damage = Box<dyn Fn(&mut ModelFile)>;
    let cases: Vec<(Damage, &str, &str)> = vec![
        (
            Box::new(|m: &mut ModelFile| {
                m.force_to_pressure = Some(greybox_model::modelfile::ForcePressure {
                    pressure_convention: greybox_core::dataset::PressureConvention::TextbookMax,
                    pressure_pa_at_1_n: 0.0,
                })
            }),
            "force_to_pressure.pressure_pa_at_1_n",
            "0 Pa at 1 N",
        ),
        (
            Box::new(|m: &mut ModelFile| {
                m.force_to_pressure = Some(greybox_model::modelfile::ForcePressure {
                    pressure_convention: greybox_core::dataset::PressureConvention::TextbookMax,
                    pressure_pa_at_1_n: -2.0e8,
                })
            }),
            "force_to_pressure.pressure_pa_at_1_n",
            "-200000000 Pa at 1 N",
        ),
        (
            Box::new(|m: &mut ModelFile| m.prediction_interval.coverage = 5.0),
            "prediction_interval.coverage",
            "5 is not a coverage",
        ),
        (
            Box::new(|m: &mut ModelFile| m.schema_version = 99),
            "schema_version",
            "schema version 99 is not supported",
        ),
    ];
    for (damage, field, text) in cases {
        let mut m = base.clone();
        damage(&mut m);
        let m = m.seal().unwrap();
        let json = serde_json::to_string(&m).unwrap();
        let e = ModelFile::parse(&json, "m.json")
            .expect_err("refused")
            .to_string();
        assert!(e.contains(field) && e.contains(text), "{e}");
        assert!(!e.contains("Some("), "{e}");
    }
}
