//! `greybox fit` and `greybox predict` end to end on the demo dataset.

use std::path::Path;
mod common;
use common::{err, greybox, ok};

/// A small dataset from plan → synth → identify (3 loads × 6 velocities).
fn dataset(p: &Path) {
    ok(&greybox(
        &[
            "plan",
            "--track-radius-mm",
            "100",
            "--normal-force-count",
            "4",
            "--velocity-count",
            "8",
            "--out",
            "plan",
        ],
        p,
    ));
    ok(&greybox(
        &["synth", "--study", "plan/study.toml", "--out", "rec"],
        p,
    ));
    ok(&greybox(
        &[
            "identify",
            "--study",
            "plan/study.toml",
            "--recordings",
            "rec",
            "--out",
            "data.csv",
        ],
        p,
    ));
}

const SMALL_GRID: [&str; 16] = [
    "--rf-n-estimators",
    "10,30",
    "--svr-kernel",
    "rbf,linear",
    "--svr-c",
    "1,10",
    "--svr-epsilon",
    "0.01",
    "--gb-n-estimators",
    "50",
    "--gb-max-depth",
    "3",
    "--mlp-hidden",
    "16x8",
    "--mlp-learning-rate",
    "0.01",
];

#[test]
fn fit_then_predict() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    dataset(p);
    let mut args = vec![
        "fit",
        "--data",
        "data.csv",
        "--out",
        "fit",
        "--bootstrap",
        "100",
        "--importance-repeats",
        "5",
        "--json",
    ];
    args.extend(SMALL_GRID);
    let s = ok(&greybox(&args, p));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    let fams = v["families"].as_array().unwrap();
    assert_eq!(fams.len(), 4);
    for f in fams {
        let held = f["held_out"]["metrics"]["r2"]["value"].as_f64().unwrap();
        assert!(held > 0.8, "{}: held-out R² {held}", f["family"]);
        assert_eq!(f["importance"].as_array().unwrap().len(), 2);
        let ci = &f["training"]["mae"];
        assert!(ci["ci_low"].as_f64().unwrap() <= ci["value"].as_f64().unwrap());
    }
    for f in [
        "report.json",
        "report.md",
        "models/svr.json",
        "models/mlp.json",
        "plots/gradient-boosting-surface.svg",
        "plots/random-forest-predicted-vs-measured.svg",
    ] {
        assert!(p.join("fit").join(f).exists(), "{f}");
    }
    let md = std::fs::read_to_string(p.join("fit/report.md")).unwrap();
    assert!(
        md.contains("Training metrics")
            && md.contains("Held-out metrics")
            && md.contains("Permutation importance")
    );

    // predict at points, with intervals
    let s = ok(&greybox(
        &[
            "predict",
            "--model",
            "fit/models/gradient-boosting.json",
            "--at",
            "1000,100",
            "--at",
            "500,200",
            "--json",
        ],
        p,
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert_eq!(v.as_array().unwrap().len(), 2);
    let (lo, val, hi) = (
        v[0]["low"].as_f64().unwrap(),
        v[0]["value"].as_f64().unwrap(),
        v[0]["high"].as_f64().unwrap(),
    );
    assert!(
        lo < val && val < hi && (0.1..0.8).contains(&val),
        "{lo} {val} {hi}"
    );
    // from a CSV: the dataset itself
    let s = ok(&greybox(
        &[
            "predict",
            "--model",
            "fit/models/svr.json",
            "--csv",
            "data.csv",
            "--json",
        ],
        p,
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert_eq!(v.as_array().unwrap().len(), 32);
    // far outside the domain
    let e = err(&greybox(
        &[
            "predict",
            "--model",
            "fit/models/mlp.json",
            "--at",
            "9000,100",
            "--outside",
            "refuse",
        ],
        p,
    ));
    assert!(e.contains("outside the training domain"), "{e}");
    let o = greybox(
        &[
            "predict",
            "--model",
            "fit/models/mlp.json",
            "--at",
            "9000,100",
        ],
        p,
    );
    let w = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && w.contains("warning: 1 of 1 points") && w.contains("normal_force_N"),
        "{w}"
    );
    let e = err(&greybox(
        &["predict", "--model", "fit/models/mlp.json", "--at", "1000"],
        p,
    ));
    assert!(e.contains("expected 2 values"), "{e}");
    tables_of_fitted_models(p);
}

/// Tree models tabulate exactly (surrogate and engine tables), smooth ones adaptively.
fn tables_of_fitted_models(p: &Path) {
    let s = ok(&greybox(
        &[
            "export",
            "--law",
            "fit/models/gradient-boosting.json",
            "--format",
            "table",
            "--out",
            "gb-table.json",
        ],
        p,
    ));
    assert!(
        s.contains("exact table") && s.contains("max deviation from the law 0.000e0"),
        "{s}"
    );
    let t: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(p.join("gb-table.json")).unwrap()).unwrap();
    assert_eq!(
        (t["kind"].as_str(), t["schema_version"].as_u64()),
        (Some("exact"), Some(2))
    );
    let s = ok(&greybox(
        &[
            "export",
            "--law",
            "fit/models/random-forest.json",
            "--format",
            "abaqus",
            "--out",
            "rf.inp",
        ],
        p,
    ));
    assert!(
        s.contains("split thresholds") && s.contains("max deviation from the law 0.000e0"),
        "{s}"
    );
    let inp = std::fs::read_to_string(p.join("rf.inp")).unwrap();
    assert!(inp.contains("** max deviation of this table (linear interpolation) from the law: 0e0"));
    // a table file is a law: the C ABI and every command load it
    for (law, kind) in [
        ("gb-table.json", "exact"),
        ("fit/models/svr.json", "adaptive"),
    ] {
        let s = ok(&greybox(
            &[
                "bench",
                "surrogate",
                "--law",
                law,
                "--calls",
                "100000",
                "--json",
            ],
            p,
        ));
        let v: serde_json::Value = serde_json::from_str(&s).unwrap();
        assert_eq!(v["table_kind"], kind, "{s}");
        let d = v["max_deviation"].as_f64().unwrap();
        assert!(if kind == "exact" { d == 0.0 } else { d <= 1e-4 }, "{s}");
    }
}

#[test]
fn fit_bad_inputs() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    dataset(p);
    let e = err(&greybox(
        &[
            "fit",
            "--data",
            "data.csv",
            "--features",
            "normal_force_N,temperature_K",
        ],
        p,
    ));
    assert!(e.contains("unknown feature 'temperature_K'"), "{e}");
    std::fs::write(
        p.join("const.csv"),
        "a_N,b_m_per_min,mu\n1,2,0.3\n2,3,0.3\n3,4,0.3\n",
    )
    .unwrap();
    let e = err(&greybox(
        &[
            "fit",
            "--data",
            "const.csv",
            "--target",
            "mu",
            "--features",
            "a_N,b_m_per_min",
        ],
        p,
    ));
    assert!(e.contains("the target is constant"), "{e}");
    let e = err(&greybox(
        &["fit", "--data", "data.csv", "--families", "svm"],
        p,
    ));
    assert!(
        e.contains("invalid value 'svm' for '--families")
            && e.contains("[possible values: random-forest, svr, gradient-boosting, mlp]"),
        "{e}"
    );
    let e = err(&greybox(&["fit", "--data", "data.csv", "--folds", "40"], p));
    assert!(e.contains("too few for 40-fold"), "{e}");
    std::fs::write(
        p.join("bad.json"),
        "{\"schema\": \"greybox-model\", \"schema_version\": 9}",
    )
    .unwrap();
    let e = err(&greybox(
        &["predict", "--model", "bad.json", "--at", "1,2"],
        p,
    ));
    assert!(e.contains("schema version 9 is not supported"), "{e}");
}

#[test]
fn adhesive_and_export() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    dataset(p);
    let s = ok(&greybox(
        &[
            "adhesive", "--data", "data.csv", "--out", "adh.csv", "--json",
        ],
        p,
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert_eq!(v["per_load"].as_array().unwrap().len(), 4);
    let adh = greybox_core::dataset::FrictionDataset::read_csv(&p.join("adh.csv")).unwrap();
    for r in &adh.records {
        let a = r.cof_adhesive.unwrap();
        assert!(
            a < r.cof_apparent && a > 0.8 * r.cof_apparent,
            "{a} vs {}",
            r.cof_apparent
        );
    }
    assert!(p.join("adh.correction.json").exists());
    let e = err(&greybox(
        &[
            "adhesive",
            "--data",
            "data.csv",
            "--method",
            "simulation",
            "--sim-loads",
            "0",
        ],
        p,
    ));
    assert!(
        e.contains("--sim-loads")
            && e.contains("0 is below the least allowed 1 (a count in 1..=1000)"),
        "{e}"
    );
    let e = err(&greybox(
        &["adhesive", "--data", "data.csv", "--track-width", "150:abc"],
        p,
    ));
    assert!(e.contains("'abc' is not a number"), "{e}");

    std::fs::write(
        p.join("zorev.json"),
        r#"{"law": "zorev", "mu": 0.4, "k_MPa": 500}"#,
    )
    .unwrap();
    ok(&greybox(
        &[
            "export",
            "--law",
            "zorev.json",
            "--format",
            "abaqus",
            "--out",
            "f.inp",
            "--pressure-MPa",
            "1000,1250,1500",
        ],
        p,
    ));
    let inp = std::fs::read_to_string(p.join("f.inp")).unwrap();
    let rows = greybox_friction::export::parse_abaqus_friction(&inp, "f.inp").unwrap();
    assert_eq!(rows.len(), 3 * 30);
    // Zorev: μ = 0.4 below 1250 MPa, k/p above
    assert_eq!(rows[0][0], 0.4);
    assert!((rows[60][0] - 500.0 / 1500.0).abs() < 1e-15);
    for fmt in ["csv", "lsdyna", "deform", "table"] {
        ok(&greybox(
            &[
                "export",
                "--law",
                "zorev.json",
                "--format",
                fmt,
                "--out",
                &format!("out.{fmt}"),
            ],
            p,
        ));
    }
    let e = err(&greybox(
        &[
            "export",
            "--law",
            "zorev.json",
            "--format",
            "abaqus",
            "--out",
            "x.inp",
            "--units",
            "psi-in-s",
        ],
        p,
    ));
    assert!(e.contains("'psi-in-s'") && e.contains("MPa-mm-s"), "{e}");
    let e = err(&greybox(
        &[
            "export",
            "--law",
            "zorev.json",
            "--format",
            "csv",
            "--out",
            "x.csv",
            "--pressure-MPa",
            "2000:1000:5",
        ],
        p,
    ));
    assert!(e.contains("MIN < MAX"), "{e}");
}
