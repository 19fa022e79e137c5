//! `greybox simulate pin` (outputs, checkpoint/resume bit-for-bit, set-up mismatch),
//! `greybox adhesive --method simulation` on a small pin, and `--method simulation-3d` on
//! CalculiX with a coarse mesh.
mod common;
use common::{err, greybox, last_particle_vtk, ok};

const PIN: [&str; 12] = [
    "simulate",
    "pin",
    "--pin-radius-mm",
    "1",
    "--depth-um",
    "20",
    "--slide-mm",
    "0.2",
    "--height-mm",
    "0.12",
    "--mu",
    "0.2",
];

#[test]
fn pin_run_writes_outputs_and_resumes_bit_for_bit() {
    let d = tempfile::tempdir().unwrap();
    let run = |extra: &[&str]| {
        let mut args: Vec<&str> = PIN.to_vec();
        args.extend_from_slice(extra);
        greybox(&args, d.path())
    };
    let s = ok(&run(&[
        "--out",
        "a",
        "--checkpoint-every",
        "1500",
        "--json",
    ]));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert!(v["force_ratio"].as_f64().unwrap() > 0.2);
    for f in [
        "a/forces.csv",
        "a/windows_tool0.csv",
        "a/summary.json",
        "a/checkpoint.json",
    ] {
        assert!(d.path().join(f).exists(), "{f}");
    }
    // Re-running into the finished run's directory is refused (old VTK frames and checkpoint
    // would mix with the new run's); nothing was left beside it.
    let e = err(&run(&["--out", "a"]));
    assert!(e.contains("--force"), "{e}");
    assert!(!d.path().join("a.partial").exists());
    // Resume from the checkpoint: the final particle state is identical.
    ok(&run(&["--out", "b", "--resume", "a/checkpoint.json"]));
    let last = |dir: &str| last_particle_vtk(&d.path().join(dir));
    assert_eq!(last("a"), last("b"));
    // A checkpoint of another set-up is refused.
    let mut args: Vec<&str> = PIN.to_vec();
    args[11] = "0.3";
    args.extend_from_slice(&["--out", "c", "--resume", "a/checkpoint.json"]);
    assert!(err(&greybox(&args, d.path())).contains("different set-up"));
    // Bad input names the problem.
    let e = err(&greybox(
        &["simulate", "pin", "--depth-um", "2", "--spacing-um", "10"],
        d.path(),
    ));
    assert!(e.contains("below one particle spacing"), "{e}");
    let e = err(&greybox(
        &["simulate", "cutting", "--config", "missing.toml"],
        d.path(),
    ));
    assert!(e.contains("missing.toml"), "{e}");
}

/// A dataset with load levels 1000 N (μ_app 0.32) and 1500 N (0.30, 0.31).
fn small_dataset(dir: &std::path::Path) {
    greybox_testkit::dataset::write_dataset(
        &dir.join("ds.csv"),
        &[(1000.0, 0.32), (1500.0, 0.30), (1500.0, 0.31)],
    );
}

#[test]
fn adhesive_by_simulation_reduces_the_cof() {
    let d = tempfile::tempdir().unwrap();
    small_dataset(d.path());
    // r = 1 mm with 0.4/0.5 mm wide tracks: depths of 20–32 µm.
    let out = ok(&greybox(
        &[
            "adhesive",
            "--data",
            "ds.csv",
            "--method",
            "simulation",
            "--pin-radius-mm",
            "1",
            "--track-width",
            "1000:400",
            "--track-width",
            "1500:500",
            "--sim-loads",
            "1",
            "--sim-spacing-um",
            "10",
            "--sim-slide-mm",
            "0.2",
            "--sim-height-mm",
            "0.12",
            "--sim-max-runs",
            "3",
            "--sim-tolerance",
            "0.01",
            "--out",
            "adh.csv",
        ],
        d.path(),
    ));
    assert!(out.contains("analytic Bowden-Tabor"), "{out}");
    let c: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(d.path().join("adh.correction.json")).unwrap(),
    )
    .unwrap();
    let red = c["mean_reduction_percent"].as_f64().unwrap();
    assert!(red > 0.0 && red < 100.0, "{red}");
    assert!(c["method"].as_str().unwrap().starts_with("simulation"));
}

/// The 3D route end to end on the article's pin and Table 3 widths, one load (1500 N), a
/// coarse mesh (about 1 min a run). Skipped without `ccx` unless GREYBOX_REQUIRE_CCX is set.
#[test]
fn adhesive_by_3d_simulation_writes_the_searches_and_force_histories() {
    if !greybox_testkit::calculix::have_ccx("the 3D adhesive correction") {
        return;
    }
    let d = tempfile::tempdir().unwrap();
    small_dataset(d.path());
    let out = ok(&greybox(
        &[
            "adhesive",
            "--data",
            "ds.csv",
            "--method",
            "simulation-3d",
            "--sim3d-loads",
            "1",
            "--sim3d-elements-per-radius",
            "5",
            "--sim3d-increments",
            "8",
            "--sim3d-slide-per-radius",
            "1.2",
            "--sim-tolerance",
            "0.005",
            "--sim-max-runs",
            "2",
            "--out",
            "adh.csv",
        ],
        d.path(),
    ));
    assert!(out.contains("analytic Bowden-Tabor"), "{out}");
    let c: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(d.path().join("adh.correction.json")).unwrap(),
    )
    .unwrap();
    assert!(
        c["method"].as_str().unwrap().starts_with("simulation-3d"),
        "{c}"
    );
    let inv: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(d.path().join("adh.pin3d/inverse.json")).unwrap(),
    )
    .unwrap();
    let load = &inv[0];
    assert_eq!(load["normal_force_N"].as_f64().unwrap(), 1500.0);
    let share = load["search"]["deformation_share"].as_f64().unwrap();
    // the 3D share at the 1500 N track is of the order of the analytic 0.024
    assert!(share > 0.012 && share < 0.05, "{share}");
    let history = std::fs::read_to_string(d.path().join("adh.pin3d/load_1500N.csv")).unwrap();
    assert!(
        history.starts_with("slide_mm,depth_um,tangential_force_N,normal_force_N,contact_area_mm2"),
        "{history}"
    );
    assert!(history.lines().count() > 10);
    assert!(d
        .path()
        .join("adh.pin3d/load_1500N/run_1/pin.inp")
        .is_file());
}
