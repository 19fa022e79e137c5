//! `greybox bench validate` on a subset of the bundled measured cuts (the full suite runs with
//! `greybox bench validate`, docs/validation.md): the calibration lands μ inside its bracket
//! and brings the calibration condition's feed force to the measurement, the held-out errors
//! are computed from the simulated and measured forces, and a bad suite is refused.
mod common;
use common::{err, greybox, ok, ti64_suite, without_wall_times};

/// The held-out summary's goal checks: the suite's three goals, each interval's measured
/// part recomputed here from the bundled data's dispersions (2σ over 3 repeats, the columns
/// `dispersion_sigmas` and `repeats`) and the simulated and measured values, and a verdict
/// that follows from the interval.
fn goals_count_the_measurements_scatter(held: &serde_json::Value, rows: &[serde_json::Value]) {
    let data = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../validation/orthogonal-cutting.csv"),
    )
    .unwrap();
    let mut lines = data.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let table: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let value = |id: &str, name: &str| -> f64 {
        let row = table.iter().find(|r| r[0] == id).unwrap();
        row[col(name)].parse().unwrap()
    };
    let checks = held["goals"].as_array().unwrap();
    let measures: Vec<&str> = checks
        .iter()
        .map(|c| c["measure"].as_str().unwrap())
        .collect();
    assert_eq!(measures, ["F'c", "F'f", "chip ratio"]);
    let columns = [
        (
            "cutting_force_dispersion_N_per_mm",
            "measured_cutting_force_n_per_mm",
            "simulated_cutting_force_n_per_mm",
        ),
        (
            "feed_force_dispersion_N_per_mm",
            "measured_feed_force_n_per_mm",
            "simulated_feed_force_n_per_mm",
        ),
        (
            "chip_ratio_dispersion",
            "measured_chip_ratio",
            "simulated_chip_ratio",
        ),
    ];
    for (c, (dispersion, measured, simulated)) in checks.iter().zip(columns) {
        let sum_sq: f64 = rows
            .iter()
            .map(|o| {
                let id = o["id"].as_str().unwrap();
                let se_mean = value(id, dispersion)
                    / (value(id, "dispersion_sigmas") * value(id, "repeats").sqrt());
                let (m, s) = (
                    o[measured].as_f64().unwrap(),
                    o[simulated].as_f64().unwrap(),
                );
                (s / m * se_mean / m).powi(2)
            })
            .sum();
        let expected = 1.96 * sum_sq.sqrt() / rows.len() as f64;
        let f = |k: &str| c[k].as_f64().unwrap();
        assert!((f("measured_ci95") - expected).abs() < 1e-9, "{c}");
        assert_eq!(c["measured_uncertainty_known"], rows.len());
        let h = f("ci95");
        assert!(h >= f("measured_ci95") && h >= f("cuts_ci95"), "{c}");
        let (mean, goal) = (f("mean_abs"), f("goal"));
        let verdict = if mean + h <= goal {
            "met"
        } else if mean - h > goal {
            "not met"
        } else {
            "cannot tell"
        };
        assert_eq!(c["verdict"], verdict, "{c}");
    }
    assert_eq!(
        (checks[0]["goal"].as_f64(), checks[2]["goal"].as_f64()),
        (Some(0.15), Some(0.08))
    );
}

#[test]
fn validation_subset_calibrates_on_one_condition_and_reports_the_held_out_ones() {
    let d = tempfile::tempdir().unwrap();
    // The bundled data and template; one calibration condition, two held out.
    ti64_suite(
        d.path(),
        "suite.toml",
        &["D08"],
        "[goals]\nchip_ratio_percent = 8.0\n",
    );
    let s = ok(&greybox(
        &[
            "bench",
            "validate",
            "--suite",
            "suite.toml",
            "--out",
            "out",
            "--only",
            "D09,D16",
            "--tool",
            "thermal",
            "--fraction",
            "0.6",
            "--json",
            "-q",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    let outcomes = v["outcomes"].as_array().unwrap();
    let ids: Vec<(&str, &str)> = outcomes
        .iter()
        .map(|o| (o["id"].as_str().unwrap(), o["role"].as_str().unwrap()))
        .collect();
    assert_eq!(
        ids,
        [
            ("D08", "calibration"),
            ("D09", "held-out"),
            ("D16", "held-out")
        ]
    );
    let mu = outcomes[0]["mu"].as_f64().unwrap();
    assert!(mu > 0.2 && mu < 0.8, "calibrated μ {mu}");
    // Re-simulated at μ*, the calibration condition's feed force is near the measured one
    // (the interpolation between the bracket ends is linear, the force nearly so).
    let cal = outcomes[0]["feed_force_error"].as_f64().unwrap();
    assert!(cal.abs() < 0.1, "calibration feed-force error {cal}");
    for o in outcomes {
        let f = |k: &str| o[k].as_f64().unwrap();
        let e = f("simulated_cutting_force_n_per_mm") / f("measured_cutting_force_n_per_mm") - 1.0;
        assert!((e - f("cutting_force_error")).abs() < 1e-12);
        assert!(f("simulated_cutting_force_n_per_mm") > 30.0);
    }
    let held = v["summaries"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["role"] == "held-out")
        .unwrap();
    let mean_abs = (outcomes[1]["cutting_force_error"].as_f64().unwrap().abs()
        + outcomes[2]["cutting_force_error"].as_f64().unwrap().abs())
        / 2.0;
    assert!((held["cutting_force_mean_abs"].as_f64().unwrap() - mean_abs).abs() < 1e-12);
    goals_count_the_measurements_scatter(held, &outcomes[1..]);
    for f in ["results.csv", "summary.json", "validation.md", "forces.svg"] {
        assert!(d.path().join("out").join(f).exists(), "{f}");
    }
    let csv = std::fs::read_to_string(d.path().join("out/results.csv")).unwrap();
    assert_eq!(csv.lines().count(), 4);

    // More than a third of the material's conditions for calibration is refused.
    let many: Vec<String> = (1..=7).map(|k| format!("D{k:02}")).collect();
    let many: Vec<&str> = many.iter().map(String::as_str).collect();
    ti64_suite(d.path(), "bad.toml", &many, "");
    let e = err(&greybox(
        &["bench", "validate", "--suite", "bad.toml", "--out", "o2"],
        d.path(),
    ));
    assert!(
        e.contains("7 calibration conditions of 18") && e.contains("at most a third"),
        "{e}"
    );
    assert!(
        !d.path().join("o2").exists(),
        "a refused run leaves no output directory"
    );

    // A mistyped condition id is named, not skipped.
    let e = err(&greybox(
        &[
            "bench",
            "validate",
            "--suite",
            "suite.toml",
            "--out",
            "o3",
            "--only",
            "D9",
        ],
        d.path(),
    ));
    assert!(e.contains("'D9'") && e.contains("D09"), "{e}");
    // The previous run's directory is kept unless --force.
    let e = err(&greybox(
        &["bench", "validate", "--suite", "suite.toml", "--out", "out"],
        d.path(),
    ));
    assert!(e.contains("--force"), "{e}");
    assert_eq!(
        std::fs::read_to_string(d.path().join("out/results.csv")).unwrap(),
        csv
    );
    assert!(d.path().join("out/provenance.json").exists());
}

#[test]
fn cuts_run_as_sweep_cases_give_the_results_of_cuts_run_in_this_process() {
    let d = tempfile::tempdir().unwrap();
    // a law file with a calibrated factor (its law inline in each case, its file by
    // absolute path) beside the calibrated constant
    std::fs::write(
        d.path().join("law.json"),
        r#"{"law": "power", "mu_ref": 0.5, "p_ref_MPa": 1000.0, "v_ref_m_per_min": 10.0, "b": -0.2, "shear_cap_k_MPa": 500.0}"#,
    )
    .unwrap();
    ti64_suite(
        d.path(),
        "suite.toml",
        &["D08"],
        "friction = [{ kind = \"coulomb-calibrated\" }, { kind = \"law\", file = \"law.json\", scale = [0.5, 1.5] }]\n",
    );
    let run = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "bench",
            "validate",
            "--suite",
            "suite.toml",
            "--out",
            out,
            "--only",
            "D09",
            "--tool",
            "thermal",
            "--fraction",
            "0.4",
            "--json",
            "-q",
        ];
        args.extend_from_slice(extra);
        let v: serde_json::Value = serde_json::from_str(&ok(&greybox(&args, d.path()))).unwrap();
        without_wall_times(v)
    };
    let here = run("here", &[]);
    let cases = run("cases", &["--executor", "local", "--jobs", "2"]);
    assert_eq!(here, cases);
    assert_eq!(here["outcomes"].as_array().unwrap().len(), 4);
    // two steps (the bracket ends, the final cuts), each one plan of cases; only their
    // summaries are kept
    let cuts = d.path().join("cases/cuts");
    for (batch, n) in [("batch-01", 4), ("batch-02", 4)] {
        let plan: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(cuts.join(batch).join("plan.json")).unwrap(),
        )
        .unwrap();
        let listed = plan["cases"].as_array().unwrap();
        assert_eq!(listed.len(), n, "{batch}");
        let case = cuts
            .join(batch)
            .join("cases")
            .join(listed[0]["id"].as_str().unwrap());
        assert!(case.join("done.json").is_file() && !case.join("result").exists());
        let config = std::fs::read_to_string(case.join("config.toml")).unwrap();
        assert!(config.contains("[friction.law]"), "{config}");
    }
    assert!(!d.path().join("here/cuts").exists());
    // validation.md groups the held-out errors by speed and by thickness, one column per
    // friction model: here the one held-out condition's own errors
    let md = std::fs::read_to_string(d.path().join("here/validation.md")).unwrap();
    assert!(
        md.contains("held out by v_c m/min") && md.contains("held out by h mm"),
        "{md}"
    );
    for o in here["outcomes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|o| o["role"] == "held-out")
    {
        let e = |k: &str| 100.0 * o[k].as_f64().unwrap();
        let cell = format!(
            "{:+.1} % / {:+.1} % (1)",
            e("cutting_force_error"),
            e("feed_force_error")
        );
        assert_eq!(md.matches(&cell).count(), 2, "{cell} in\n{md}");
    }
}
