//! The protocol end to end on a small dataset: determinism across thread counts, model files,
//! prediction intervals, bad input.

use greybox_learn::protocol::{run_protocol, FitConfig};
use greybox_learn::table::read_dataset_from;
use greybox_model::modelfile::{DomainPolicy, ModelFile};
use greybox_model::Family;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn csv(n: usize, seed: u64) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = rand_distr::Normal::new(0.0, 0.004).unwrap();
    let mut s = String::from("normal_force_N,sliding_velocity_m_per_min,cof\n");
    for _ in 0..n {
        let f: f64 = rng.gen_range(150.0..2000.0);
        let v: f64 = rng.gen_range(20.0..250.0);
        let e: f64 = rand_distr::Distribution::sample(&normal, &mut rng);
        s.push_str(&format!(
            "{f},{v},{}\n",
            0.45 - 0.08 * (f / 2000.0) - 0.1 * (v / 250.0).sqrt() + e
        ));
    }
    s
}

fn small_config() -> FitConfig {
    let mut c = FitConfig {
        bootstrap_resamples: greybox_learn::protocol::Resamples::of(200),
        importance_repeats: greybox_learn::protocol::Repeats::of(5),
        inner_folds: greybox_learn::protocol::Folds::of(3),
        ..Default::default()
    };
    c.grid.random_forest.n_estimators = vec![10, 30];
    c.grid.svr.c = vec![1.0, 10.0];
    c.grid.svr.kernel = vec![greybox_model::svr::Kernel::Rbf];
    c.grid.svr.epsilon = vec![0.01];
    c.grid.gradient_boosting.n_estimators = vec![50];
    c.grid.gradient_boosting.max_depth = vec![3];
    c.grid.gradient_boosting.learning_rate = vec![0.1];
    c.grid.mlp.hidden_layers = vec![vec![16, 8]];
    c.grid.mlp.activation = vec![greybox_model::mlp::Activation::Relu];
    c.grid.mlp.learning_rate = vec![0.01];
    c
}

fn data(n: usize, seed: u64) -> greybox_learn::table::Dataset {
    let feats = vec![
        "normal_force_N".to_string(),
        "sliding_velocity_m_per_min".to_string(),
    ];
    read_dataset_from(
        csv(n, seed).as_bytes(),
        "synthetic.csv",
        &feats,
        "cof",
        None,
    )
    .unwrap()
}

#[test]
fn deterministic_whatever_the_thread_count() {
    let d = data(80, 1);
    let cfg = small_config();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| run_protocol(&d, &cfg).unwrap());
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| run_protocol(&d, &cfg).unwrap());
    assert_eq!(one.1, two.1, "model files");
    for (a, b) in one.0.families.iter().zip(&two.0.families) {
        assert_eq!(a.training, b.training);
        assert_eq!(a.held_out, b.held_out);
        assert_eq!(a.importance, b.importance);
    }
    // held-out metrics are reported per outer fold
    for f in &one.0.families {
        let h = f.held_out.as_ref().unwrap();
        assert_eq!(h.r2_per_fold.len(), 5);
        assert_eq!(h.predictions.len(), 80);
    }
}

#[test]
fn model_files_round_trip_and_verify() {
    let d = data(80, 2);
    let cfg = FitConfig {
        families: vec![Family::GradientBoosting, Family::Mlp],
        ..small_config()
    };
    let (_, files) = run_protocol(&d, &cfg).unwrap();
    let dir = tempfile::tempdir().unwrap();
    for f in &files {
        let p = dir.path().join(format!("{}.json", f.family.name()));
        f.save(&p).unwrap();
        let back = ModelFile::load(&p).unwrap();
        assert_eq!(&back, f);
        let x = [1000.0, 100.0];
        assert_eq!(
            back.predict(&x, DomainPolicy::Refuse, 0.0).unwrap(),
            f.predict(&x, DomainPolicy::Refuse, 0.0).unwrap()
        );
        // tampering is detected
        let text =
            std::fs::read_to_string(&p)
                .unwrap()
                .replacen("\"n_train\": 80", "\"n_train\": 81", 1);
        let e = ModelFile::parse(&text, "t.json").unwrap_err().to_string();
        assert!(e.contains("content hash mismatch"), "{e}");
        // another schema version is refused
        let text = std::fs::read_to_string(&p).unwrap().replacen(
            "\"schema_version\": 2",
            "\"schema_version\": 3",
            1,
        );
        let e = ModelFile::parse(&text, "t.json").unwrap_err().to_string();
        assert!(e.contains("schema version 3 is not supported"), "{e}");
        // a version-1 file (before force_to_pressure and provenance) still loads
        let mut v1 = f.clone();
        v1.schema_version = 1;
        let v1 = v1.seal().unwrap();
        let text = serde_json::to_string(&v1).unwrap();
        assert!(!text.contains("force_to_pressure") && !text.contains("provenance"));
        assert_eq!(ModelFile::parse(&text, "v1.json").unwrap(), v1);
        // far outside the training domain: refused or flagged
        let far = [5000.0, 100.0];
        let e = f
            .predict(&far, DomainPolicy::Refuse, 0.05)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("outside the training domain") && e.contains("normal_force_N = 5000"),
            "{e}"
        );
        assert!(!f.predict(&far, DomainPolicy::Warn, 0.05).unwrap().in_domain);
    }
}

/// The CV-conformal 95 % interval covers ≈ 95 % of fresh observations from the same process.
#[test]
fn prediction_interval_covers_fresh_data() {
    let d = data(200, 3);
    let cfg = FitConfig {
        families: vec![Family::GradientBoosting],
        skip_nested: true,
        ..small_config()
    };
    let (_, files) = run_protocol(&d, &cfg).unwrap();
    let fresh = data(2000, 4);
    let m = &files[0];
    let covered = (0..fresh.y.len())
        .filter(|&i| {
            let p = m.predict(fresh.x.row(i), DomainPolicy::Warn, 0.0).unwrap();
            fresh.y[i] >= p.low && fresh.y[i] <= p.high
        })
        .count() as f64
        / fresh.y.len() as f64;
    assert!((0.92..=0.985).contains(&covered), "coverage {covered}");
}

#[test]
fn too_few_rows_for_the_folds() {
    let d = data(8, 5);
    let e = run_protocol(&d, &small_config()).unwrap_err().to_string();
    assert!(e.contains("8 rows are too few for 5-fold"), "{e}");
}

/// `bootstrap` 0 and `importance_repeats` 0 skip what they count (a quick look): the metrics
/// stand without intervals (`null`, never a NaN), the importance is empty, and the report
/// says both instead of printing numbers that rest on nothing.
#[test]
fn zero_resamples_and_repeats_skip_them_and_say_so() {
    let d = data(60, 4);
    let mut cfg = small_config();
    cfg.families = vec![Family::Svr];
    cfg.skip_nested = true;
    cfg.bootstrap_resamples = greybox_learn::protocol::Resamples::of(0);
    cfg.importance_repeats = greybox_learn::protocol::Repeats::of(0);
    let (report, _) = run_protocol(&d, &cfg).unwrap();
    let f = &report.families[0];
    assert!(f.importance.is_empty());
    let mae = f.training.mae;
    assert!(mae.value.is_finite() && mae.ci_low.is_none() && mae.ci_high.is_none());
    let json = serde_json::to_string(&report).unwrap();
    assert!(
        json.contains(r#""ci_low":null"#) && !json.contains("NaN"),
        "{json}"
    );
    let md = greybox_learn::protocol::markdown(&report);
    assert!(md.contains("(no interval: bootstrap 0)"), "{md}");
    assert!(md.contains("skipped (`importance_repeats` 0)"), "{md}");
}
