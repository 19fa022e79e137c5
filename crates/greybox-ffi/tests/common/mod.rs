//! A small learned model shared by the FFI tests.

use greybox_learn::protocol::{run_protocol, FitConfig};
use greybox_model::mlp::Activation;
use greybox_model::modelfile::ModelFile;
use greybox_model::Family;

/// A model of a smooth μ(hertz_pressure_MPa, sliding_velocity_m_per_min) on a 10 × 10 grid,
/// fitted with one small configuration of `family` (`activation` for the MLP).
pub fn small_model(family: Family, activation: Activation) -> ModelFile {
    let mut csv = String::from("hertz_pressure_MPa,sliding_velocity_m_per_min,mu\n");
    for i in 0..10 {
        for j in 0..10 {
            let (p, v) = (900.0 + 140.0 * i as f64, 20.0 + 25.0 * j as f64);
            csv.push_str(&format!(
                "{p},{v},{}\n",
                0.5 - 0.1 * (p - 900.0) / 1300.0 - 0.1 * (v / 250.0).sqrt()
            ));
        }
    }
    let feats = vec![
        "hertz_pressure_MPa".to_string(),
        "sliding_velocity_m_per_min".to_string(),
    ];
    let data =
        greybox_learn::table::read_dataset_from(csv.as_bytes(), "mem.csv", &feats, "mu", None)
            .unwrap();
    let mut cfg = FitConfig {
        families: vec![family],
        skip_nested: true,
        bootstrap_resamples: greybox_learn::protocol::Resamples::of(5),
        importance_repeats: greybox_learn::protocol::Repeats::of(1),
        ..Default::default()
    };
    cfg.grid.mlp.hidden_layers = vec![vec![16, 8]];
    cfg.grid.mlp.activation = vec![activation];
    cfg.grid.mlp.learning_rate = vec![0.01];
    cfg.grid.gradient_boosting.n_estimators = vec![50];
    cfg.grid.gradient_boosting.max_depth = vec![3];
    cfg.grid.gradient_boosting.learning_rate = vec![0.1];
    cfg.grid.svr.kernel = vec![greybox_model::svr::Kernel::Rbf];
    cfg.grid.svr.c = vec![10.0];
    cfg.grid.svr.epsilon = vec![0.01];
    run_protocol(&data, &cfg).unwrap().1.remove(0)
}
