//! End-to-end tests of the `greybox` binary.

mod common;
use common::{err, greybox, ok};

#[test]
fn every_subcommand_has_help() {
    let d = tempfile::tempdir().unwrap();
    for sub in [
        "plan",
        "synth",
        "identify",
        "hertz",
        "demo",
        "bench",
        "fit",
        "predict",
        "adhesive",
        "export",
        "characterize",
        "wear",
        "windows",
    ] {
        let s = ok(&greybox(&[sub, "--help"], d.path()));
        assert!(s.contains("Usage:"), "{sub}");
    }
}

#[test]
fn plan_synth_identify_through_files() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let s = ok(&greybox(
        &[
            "plan",
            "--track-radius-mm",
            "120",
            "--out",
            "plan",
            "--json",
        ],
        p,
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert_eq!(v["pins"], 10);
    assert_eq!(v["steps"], 210);
    // n = v / (2πR) = 250 / (2π · 0.12) = 331.57 rpm
    assert_eq!(v["spindle_rpm_max"], 331.57);
    assert!(p.join("plan/nc/pin10.nc").exists() && p.join("plan/run_sheet.csv").exists());
    let sheet = std::fs::read_to_string(p.join("plan/run_sheet.csv")).unwrap();
    assert_eq!(sheet.lines().count(), 211);
    assert!(sheet.starts_with("pin,step,normal_force_N,sliding_velocity_m_per_min,spindle_rpm,"));

    ok(&greybox(
        &[
            "synth",
            "--study",
            "plan/study.toml",
            "--out",
            "rec",
            "--format",
            "both",
            "--seed",
            "3",
        ],
        p,
    ));
    for fmt in ["csv", "tdms"] {
        let out = format!("dataset_{fmt}.csv");
        let s = ok(&greybox(
            &[
                "identify",
                "--study",
                "plan/study.toml",
                "--recordings",
                "rec",
                "--format",
                fmt,
                "--out",
                &out,
                "--truth",
                "rec/ground_truth.csv",
                "--json",
            ],
            p,
        ));
        let v: serde_json::Value = serde_json::from_str(&s).unwrap();
        assert_eq!(v["plateaus"], 210);
        let max = v["truth"]["max_abs_error"].as_f64().unwrap();
        assert!(max <= 0.003, "{fmt}: {max}");
    }
    // CSV and TDMS recordings give the same dataset up to the CSV's 4 decimals
    let a = std::fs::read_to_string(p.join("dataset_csv.csv")).unwrap();
    let b = std::fs::read_to_string(p.join("dataset_tdms.csv")).unwrap();
    assert_eq!(a.lines().count(), b.lines().count());
    let dataset =
        greybox_core::dataset::FrictionDataset::read_csv(&p.join("dataset_tdms.csv")).unwrap();
    assert_eq!(
        dataset.records[0].pressure_convention.name(),
        "textbook-max"
    );
    // same seed, same bytes
    ok(&greybox(
        &[
            "synth",
            "--study",
            "plan/study.toml",
            "--out",
            "rec2",
            "--format",
            "both",
            "--seed",
            "3",
        ],
        p,
    ));
    for f in ["pin01.csv", "pin07.tdms", "ground_truth.csv"] {
        assert_eq!(
            std::fs::read(p.join("rec").join(f)).unwrap(),
            std::fs::read(p.join("rec2").join(f)).unwrap(),
            "{f}"
        );
    }
}

#[test]
fn impossible_plans_are_rejected() {
    let d = tempfile::tempdir().unwrap();
    let e = err(&greybox(
        &["plan", "--track-radius-mm", "5", "--out", "x"],
        d.path(),
    ));
    assert!(e.contains("above the spindle limit of 3000 rpm"), "{e}");
    let e = err(&greybox(&["plan", "--out", "x"], d.path()));
    assert!(e.contains("track radius is required"), "{e}");
    let e = err(&greybox(
        &[
            "plan",
            "--track-radius-mm",
            "100",
            "--velocity-count",
            "0",
            "--out",
            "x",
        ],
        d.path(),
    ));
    assert!(
        e.contains("--velocity-count") && e.contains("0 is below the least allowed 1"),
        "{e}"
    );
    let e = err(&greybox(
        &[
            "plan",
            "--track-radius-mm",
            "100",
            "--dwell-s=-1",
            "--out",
            "x",
        ],
        d.path(),
    ));
    assert!(e.contains("dwell_s must be positive"), "{e}");
    assert!(
        !d.path().join("x").exists(),
        "nothing written for a rejected plan"
    );
}

#[test]
fn identify_names_the_bad_file_and_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&greybox(
        &[
            "plan",
            "--track-radius-mm",
            "100",
            "--normal-force-count",
            "1",
            "--normal-force-max-N",
            "150",
            "--out",
            "plan",
        ],
        p,
    ));
    ok(&greybox(
        &["synth", "--study", "plan/study.toml", "--out", "rec"],
        p,
    ));
    let text = std::fs::read_to_string(p.join("rec/pin01.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let fields: Vec<&str> = lines[100].split(',').collect();
    lines[100] = format!("{},NaN,{}", fields[0], fields[2..].join(","));
    std::fs::write(p.join("bad.csv"), lines.join("\n")).unwrap();
    let e = err(&greybox(
        &[
            "identify",
            "--study",
            "plan/study.toml",
            "--recordings",
            "bad.csv",
            "--out",
            "d.csv",
        ],
        p,
    ));
    assert!(
        e.contains("bad.csv, line 101, field 'normal_force_N'")
            && e.contains("expected a number, found 'NaN'"),
        "{e}"
    );
    assert!(!p.join("d.csv").exists(), "no dataset written on error");
    // wrong number of files
    std::fs::copy(p.join("rec/pin01.csv"), p.join("a.csv")).unwrap();
    std::fs::copy(p.join("rec/pin01.csv"), p.join("b.csv")).unwrap();
    let e = err(&greybox(
        &[
            "identify",
            "--study",
            "plan/study.toml",
            "--recordings",
            "a.csv",
            "b.csv",
        ],
        p,
    ));
    assert!(
        e.contains("the plan has 1 pins but 2 recordings were given"),
        "{e}"
    );
    // truncated TDMS
    ok(&greybox(
        &[
            "synth",
            "--study",
            "plan/study.toml",
            "--out",
            "rect",
            "--format",
            "tdms",
        ],
        p,
    ));
    let bytes = std::fs::read(p.join("rect/pin01.tdms")).unwrap();
    std::fs::write(p.join("cut.tdms"), &bytes[..bytes.len() - 100]).unwrap();
    let e = err(&greybox(
        &[
            "identify",
            "--study",
            "plan/study.toml",
            "--recordings",
            "cut.tdms",
        ],
        p,
    ));
    assert!(
        e.contains("cut.tdms, byte") && e.contains("truncated"),
        "{e}"
    );
    // unknown channel mapping unit
    let e = err(&greybox(
        &[
            "identify",
            "--study",
            "plan/study.toml",
            "--recordings",
            "rec",
            "--map",
            "normal=normal_force_N:tonf",
        ],
        p,
    ));
    assert!(e.contains("unknown force unit 'tonf'"), "{e}");
}

#[test]
fn hertz_reference_vectors() {
    let d = tempfile::tempdir().unwrap();
    let s = ok(&greybox(
        &[
            "hertz",
            "--force-N",
            "10",
            "--radius-mm",
            "6.35",
            "--e1-GPa",
            "210",
            "--e2-GPa",
            "210",
            "--json",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert!((v[0]["mean_pressure_mpa"].as_f64().unwrap() - 574.0).abs() < 0.5);
    assert!((v[0]["max_pressure_mpa"].as_f64().unwrap() - 861.0).abs() < 0.5);
    let s = ok(&greybox(
        &[
            "hertz",
            "--force-N",
            "150",
            "2000",
            "--convention",
            "article-eq7",
            "--json",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    let p150 = v[0]["convention_pressure_mpa"].as_f64().unwrap();
    let p2000 = v[1]["convention_pressure_mpa"].as_f64().unwrap();
    assert!(
        (p150 / 914.7 - 1.0).abs() < 0.005 && (p2000 / 2170.0 - 1.0).abs() < 0.005,
        "{p150} {p2000}"
    );
    let s = ok(&greybox(
        &[
            "hertz",
            "--force-N",
            "188.4956",
            "--radius-mm",
            "8",
            "--e1-GPa",
            "1",
            "--e2-GPa",
            "inf",
            "--json",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert!((v[0]["contact_half_width_mm"].as_f64().unwrap() - 1.010).abs() < 0.0006);
    let e = err(&greybox(&["hertz", "--force-N=-5"], d.path()));
    assert!(
        e.contains("--force-N") && e.contains("normal force -5 N") && e.contains("possible range"),
        "{e}"
    );
}

#[test]
fn demo_runs_and_recovers_the_truth() {
    let d = tempfile::tempdir().unwrap();
    let s = ok(&greybox(&["demo", "--out", "demo", "--json"], d.path()));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert_eq!(v["identify"]["plateaus"], 210);
    assert!(v["identify"]["truth"]["max_abs_error"].as_f64().unwrap() <= 0.003);
    assert_eq!(v["identify"]["pressure_convention"], "article-eq7");
}
