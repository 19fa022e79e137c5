//! `greybox simulate pin` (outputs, checkpoint/resume bit-for-bit, set-up mismatch) and
//! `greybox adhesive --method simulation` on a small pin.
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

#[test]
fn adhesive_by_simulation_reduces_the_cof() {
    let d = tempfile::tempdir().unwrap();
    let mut csv = String::from("pin,step,normal_force_N,normal_force_measured_N,sliding_velocity_m_per_min,hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n");
    for (k, (f, mu)) in [(1000.0, 0.32), (1500.0, 0.30), (1500.0, 0.31)]
        .iter()
        .enumerate()
    {
        csv += &format!("1,{k},{f},{f},100,1500,textbook-max,{mu},0.01,1000,1,2,0,true,\n");
    }
    std::fs::write(d.path().join("ds.csv"), csv).unwrap();
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
