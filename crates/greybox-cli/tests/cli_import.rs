//! `greybox import`: a booster file becomes a model file that `greybox predict` evaluates as
//! XGBoost does (float32 split and sum, checked by hand), with the domain stated or taken
//! from training data, calibration rows giving the interval, and clear errors.

mod common;
use common::{err, greybox, ok};

/// One stump on feature 0 at 0.1f32, base 0.33f32 (XGBoost's JSON schema).
const BOOSTER: &str = r#"{"version": [3, 2, 0], "learner": {
  "objective": {"name": "reg:squarederror"},
  "feature_names": ["normal_force_N", "sliding_velocity_m_per_min"],
  "learner_model_param": {"base_score": "[3.3E-1]", "num_feature": "2", "num_class": "0", "num_target": "1"},
  "gradient_booster": {"name": "gbtree", "model": {"trees": [{
    "left_children": [1, -1, -1], "right_children": [2, -1, -1], "split_indices": [0, 0, 0],
    "split_conditions": [1000.5, 0.0123, -0.0456], "split_type": [0, 0, 0], "default_left": [0, 0, 0],
    "tree_param": {"num_nodes": "3", "size_leaf_vector": "1"}}]}}}}"#;

fn by_hand(force: f64) -> f64 {
    let leaf = if (force as f32) < 1000.5f32 {
        0.0123f32
    } else {
        -0.0456f32
    };
    (0.33f32 + leaf) as f64
}

#[test]
fn import_then_predict_agrees_with_float32_arithmetic() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("booster.json"), BOOSTER).unwrap();
    std::fs::write(
        d.join("train.csv"),
        "normal_force_N,sliding_velocity_m_per_min\n150,20\n2000,250\n",
    )
    .unwrap();
    std::fs::write(
        d.join("cal.csv"),
        "normal_force_N,sliding_velocity_m_per_min,cof_adhesive\n500,50,0.35\n1500,100,0.27\n",
    )
    .unwrap();
    let out = ok(&greybox(
        &[
            "import",
            "booster.json",
            "--training-data",
            "train.csv",
            "--calibration",
            "cal.csv",
            "--out",
            "model.json",
        ],
        d,
    ));
    assert!(out.contains("xgboost 3.2.0"), "{out}");
    assert!(d.join("model.json.provenance.json").exists());
    // 1000.5 itself, the f64 just above (still 1000.5 in float32) and the float32 above it
    let above32 = f32::from_bits(1000.5f32.to_bits() + 1) as f64;
    let tie = (1000.5 + above32) / 2.0;
    let mut args = vec!["predict", "--model", "model.json", "--json"];
    let pts: Vec<String> = [
        999.0,
        1000.5,
        1000.5f64.next_up(),
        tie,
        tie.next_up(),
        above32,
    ]
    .iter()
    .map(|f| format!("{f:e},100"))
    .collect();
    for p in &pts {
        args.extend(["--at", p.as_str()]);
    }
    let rows: serde_json::Value = serde_json::from_str(&ok(&greybox(&args, d))).unwrap();
    for r in rows.as_array().unwrap() {
        let f = r["features"][0].as_f64().unwrap();
        assert_eq!(r["value"].as_f64().unwrap(), by_hand(f), "at {f:e}");
        // split-conformal half-width from the two calibration rows: the larger residual
        let q = (0.35 - by_hand(500.0))
            .abs()
            .max((0.27 - by_hand(1500.0)).abs());
        assert!((r["high"].as_f64().unwrap() - by_hand(f) - q).abs() < 1e-12);
    }
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("model.json")).unwrap()).unwrap();
    assert_eq!(m["training_domain"][0]["max"], 2000.0);
    assert_eq!(m["prediction_interval"]["method"], "split-conformal");
}

#[test]
fn import_errors_name_what_is_missing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("booster.json"), BOOSTER).unwrap();
    let e = err(&greybox(&["import", "booster.json", "--out", "m.json"], d));
    assert!(e.contains("state the training domain"), "{e}");
    let e = err(&greybox(
        &[
            "import",
            "booster.json",
            "--features",
            "pressure_MPa,sliding_velocity_m_per_s",
            "--domain",
            "0:1,0:1",
            "--out",
            "m.json",
        ],
        d,
    ));
    assert!(e.contains("trained on features"), "{e}");
    std::fs::write(d.join("bad.json"), "{\"hello\": 1}").unwrap();
    let e = err(&greybox(
        &[
            "import", "bad.json", "--domain", "0:1,0:1", "--out", "m.json",
        ],
        d,
    ));
    assert!(
        e.contains("bad.json") && e.contains("neither an XGBoost booster"),
        "{e}"
    );
    let e = err(&greybox(
        &[
            "import",
            "booster.json",
            "--domain",
            "0:1",
            "--out",
            "m.json",
        ],
        d,
    ));
    assert!(e.contains("1 ranges for 2 features"), "{e}");
    assert!(!d.join("m.json").exists());
}

/// The article's pin contact as a study's [contact] table.
const STUDY: &str = "[contact]\npin_tip_radius_mm = 17.0\ndisk_youngs_modulus_gpa = 210.0\ndisk_poisson_ratio = 0.3\npin_youngs_modulus_gpa = 650.0\npin_poisson_ratio = 0.3\nconvention = \"article-eq7\"\n";

/// A force-trained booster imported with its contact is a friction law: `greybox export`
/// writes its table and `greybox predict` evaluates it; both ways of stating the contact
/// (a study's [contact] table, the flags) record the same map.
#[test]
fn import_with_contact_makes_a_force_model_a_law() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("booster.json"), BOOSTER).unwrap();
    std::fs::write(d.join("study.toml"), STUDY).unwrap();
    let common = ["import", "booster.json", "--domain", "150:2000,20:250"];
    let by_flags = [
        "--convention",
        "article-eq7",
        "--pin-tip-radius-mm",
        "17",
        "--pin-youngs-modulus-gpa",
        "650",
        "--disk-youngs-modulus-gpa",
        "210",
        "--out",
        "flags.json",
    ];
    let out = ok(&greybox(&[&common[..], &by_flags[..]].concat(), d));
    assert!(out.contains("article-eq7 convention"), "{out}");
    let by_study = ["--contact", "study.toml", "--out", "model.json"];
    ok(&greybox(&[&common[..], &by_study[..]].concat(), d));
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.join(f)).unwrap()).unwrap()
    };
    let (m, f) = (read("model.json"), read("flags.json"));
    assert_eq!(m["force_to_pressure"], f["force_to_pressure"]);
    assert_eq!(m["force_to_pressure"]["pressure_convention"], "article-eq7");
    // the law's domain in pressure is the article's 914.7–2170 MPa for 150–2000 N
    ok(&greybox(
        &[
            "export",
            "--law",
            "model.json",
            "--format",
            "csv",
            "--pressure-MPa",
            "950:2150:13",
            "--velocity-m-per-min",
            "20:250:5",
            "--out",
            "table.csv",
        ],
        d,
    ));
    let table = std::fs::read_to_string(d.join("table.csv")).unwrap();
    // the split at 1000.5 N restated in pressure: c·1000.5^(1/3), c = 172.05 MPa at 1 N
    assert!(table.contains("\n1720.74"), "{table}");
    for mu in [by_hand(500.0), by_hand(1500.0)] {
        assert!(table.contains(&format!(",{mu}\n")), "{table}");
    }
    let p = ok(&greybox(
        &[
            "predict",
            "--model",
            "model.json",
            "--at",
            "500,100",
            "--json",
        ],
        d,
    ));
    let rows: serde_json::Value = serde_json::from_str(&p).unwrap();
    assert_eq!(rows[0]["value"].as_f64().unwrap(), by_hand(500.0));
}

/// Without a contact the import works (the model predicts on forces) and says what is
/// missing; using it as a law names the fix, not the schema version.
#[test]
fn force_model_without_contact_says_how_to_state_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("booster.json"), BOOSTER).unwrap();
    let out = greybox(
        &[
            "import",
            "booster.json",
            "--domain",
            "150:2000,20:250",
            "--out",
            "model.json",
        ],
        d,
    );
    ok(&out);
    let note = String::from_utf8_lossy(&out.stderr);
    assert!(note.contains("no contact was stated"), "{note}");
    ok(&greybox(
        &["predict", "--model", "model.json", "--at", "500,100"],
        d,
    ));
    let e = err(&greybox(
        &[
            "export",
            "--law",
            "model.json",
            "--format",
            "csv",
            "--out",
            "table.csv",
        ],
        d,
    ));
    assert!(
        e.contains("imported without a contact") && e.contains("`contact` STUDY.toml"),
        "{e}"
    );
    assert!(!e.contains("schema version"), "{e}");
    // a contact without a convention is refused, naming it
    let e = err(&greybox(
        &[
            "import",
            "booster.json",
            "--domain",
            "150:2000,20:250",
            "--pin-tip-radius-mm",
            "17",
            "--out",
            "m2.json",
        ],
        d,
    ));
    assert!(e.contains("convention"), "{e}");
}

/// Feature names without a unit greybox maps are refused at import, naming the feature.
#[test]
fn unknown_feature_unit_is_refused_at_import() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("booster.json"),
        BOOSTER.replace("normal_force_N", "load_lbf"),
    )
    .unwrap();
    let e = err(&greybox(
        &[
            "import",
            "booster.json",
            "--domain",
            "150:2000,20:250",
            "--out",
            "m.json",
        ],
        d,
    ));
    assert!(e.contains("'load_lbf'") && e.contains("_N, _kN"), "{e}");
    assert!(!d.join("m.json").exists());
}

/// `greybox predict` warns once for points outside the domain: how many, on which feature.
#[test]
fn predict_warns_how_many_points_lie_outside() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("booster.json"), BOOSTER).unwrap();
    ok(&greybox(
        &[
            "import",
            "booster.json",
            "--domain",
            "150:2000,20:250",
            "--out",
            "model.json",
        ],
        d,
    ));
    let out = greybox(
        &[
            "predict",
            "--model",
            "model.json",
            "--at",
            "500,100",
            "--at",
            "5000,100",
            "--at",
            "500,1000",
        ],
        d,
    );
    ok(&out);
    let w = String::from_utf8_lossy(&out.stderr);
    assert!(
        w.contains("2 of 3 points")
            && w.contains("normal_force_N")
            && w.contains("sliding_velocity_m_per_min"),
        "{w}"
    );
}

/// A stated training domain no contact can have (5·10⁸ MPa: Pa numbers given as MPa) is
/// refused naming the feature, the end and the slip; an unusual one (a normal force of
/// 200 kN) is imported with a warning line; the physics table, as for every other input.
#[test]
fn an_impossible_training_domain_is_refused_with_its_slip() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("booster.json"), BOOSTER).unwrap();
    let import = |domain: &str| {
        greybox(
            &[
                "import",
                "booster.json",
                "--features",
                "normal_force_N,sliding_velocity_m_per_min",
                "--domain",
                domain,
                "--out",
                "m.json",
            ],
            d,
        )
    };
    let e = err(&import("150:5e14,20:250"));
    assert!(
        e.contains("normal_force_N") && e.contains("max") && e.contains("possible range"),
        "{e}"
    );
    let out = import("150:2e5,20:250");
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("warning:") && stderr.contains("normal_force_N"),
        "{stderr}"
    );
}
