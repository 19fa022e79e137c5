//! Small models shared by the table and export tests.
#![allow(dead_code)]

use greybox_contact::PinContact;
use greybox_core::dataset::PressureConvention;
use greybox_core::ContactState;
use greybox_learn::protocol::{run_protocol, FitConfig};
use greybox_learn::table::read_dataset_from;
use greybox_model::modelfile::{ForcePressure, ModelFile};
use greybox_model::Family;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The article's contact convention (c = pressure at 1 N).
pub fn eq7() -> PinContact {
    PinContact {
        convention: PressureConvention::ArticleEq7,
        ..PinContact::default()
    }
}

/// A model of a smooth μ fitted on 160 random (scattered, noisy) rows of `features`, so that
/// tree thresholds are many and fall between arbitrary values.
pub fn model(family: Family, features: &[&str]) -> ModelFile {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut csv = features.join(",") + ",mu\n";
    for _ in 0..160 {
        let mut row = Vec::new();
        let mut mu = 0.5;
        for f in features {
            let (lo, hi) = match *f {
                "normal_force_N" => (150.0, 2000.0),
                "hertz_pressure_MPa" => (900.0, 2200.0),
                "sliding_velocity_m_per_min" => (20.0, 250.0),
                _ => (20.0, 600.0), // temperature_degC
            };
            let x: f64 = rng.gen_range(lo..hi);
            mu -= 0.08 * ((x - lo) / (hi - lo)).sqrt();
            row.push(x.to_string());
        }
        mu += rng.gen_range(-0.005..0.005);
        csv += &format!("{},{mu}\n", row.join(","));
    }
    let feats: Vec<String> = features.iter().map(|s| s.to_string()).collect();
    let data = read_dataset_from(csv.as_bytes(), "mem.csv", &feats, "mu", None).unwrap();
    let mut cfg = FitConfig {
        families: vec![family],
        skip_nested: true,
        bootstrap_resamples: greybox_learn::protocol::Resamples::of(2),
        importance_repeats: greybox_learn::protocol::Repeats::of(1),
        ..Default::default()
    };
    cfg.grid.random_forest.n_estimators = vec![20];
    cfg.grid.gradient_boosting.n_estimators = vec![60];
    cfg.grid.gradient_boosting.max_depth = vec![3];
    cfg.grid.gradient_boosting.learning_rate = vec![0.1];
    cfg.grid.svr.kernel = vec![greybox_model::svr::Kernel::Rbf];
    cfg.grid.svr.c = vec![10.0];
    cfg.grid.svr.epsilon = vec![0.01];
    cfg.grid.mlp.hidden_layers = vec![vec![16, 8]];
    cfg.grid.mlp.activation = vec![greybox_model::mlp::Activation::Tanh];
    cfg.grid.mlp.learning_rate = vec![0.01];
    let mut m = run_protocol(&data, &cfg).unwrap().1.remove(0);
    if features.contains(&"normal_force_N") {
        m.force_to_pressure = Some(ForcePressure {
            pressure_convention: PressureConvention::ArticleEq7,
            pressure_pa_at_1_n: eq7().pressure_pa(1.0).unwrap(),
        });
    }
    m
}

pub fn state(x: [f64; 3]) -> ContactState {
    ContactState {
        pressure_pa: x[0],
        sliding_velocity_m_s: x[1],
        temperature_k: x[2],
    }
}
