//! Helpers shared by the CLI integration tests.
#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Run the greybox binary in `cwd`.
pub fn greybox(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_greybox"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run greybox")
}

/// Assert success; return stdout.
pub fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "stderr: {}\nstdout: {}",
        String::from_utf8_lossy(&out.stderr),
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The values of column `name` of a CSV file written by the binary (a dataset), in order.
pub fn csv_column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse().unwrap())
        .collect()
}

/// Assert failure; return stderr.
pub fn err(out: &Output) -> String {
    assert!(
        !out.status.success(),
        "expected failure, stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Text of the last `particles_*.vtk` written under `dir/vtk` (the final state of a run).
pub fn last_particle_vtk(dir: &Path) -> String {
    let mut v: Vec<_> = std::fs::read_dir(dir.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("particles_")
        })
        .collect();
    v.sort();
    std::fs::read_to_string(v.last().unwrap()).unwrap()
}

/// The bundled article case made coarse and short (20 µm spacing, 0.25 mm of cut).
pub fn coarse_config(dir: &Path, law_file: Option<&str>) {
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/aisi1045-cut.toml"
    ))
    .unwrap();
    let mut s = String::new();
    for line in base.lines() {
        let l = if line.starts_with("spacing_m") {
            "spacing_m = 2.0e-5".to_string()
        } else if line.starts_with("cut_length_m") {
            "cut_length_m = 0.25e-3".to_string()
        } else if line.starts_with("workpiece_height_m") {
            "workpiece_height_m = 2.4e-4".to_string()
        } else if line.starts_with("window_length_m") {
            "window_length_m = 2.0e-5".to_string()
        } else if line.starts_with("update_every_steps") {
            "update_every_steps = 200".to_string()
        } else if line.starts_with("stop_when_sure") {
            "stop_when_sure = false".to_string()
        } else if line.starts_with("# law_file") {
            law_file.map_or(String::new(), |f| format!("law_file = \"{f}\""))
        } else {
            line.to_string()
        };
        s.push_str(&l);
        s.push('\n');
    }
    std::fs::write(dir.join("cut.toml"), s).unwrap();
}

/// Run the greybox binary in `cwd` under an address-space limit of `memory_mib` MiB and a
/// wall-clock limit of `seconds` (hostile-input tests: a reader without a budget fails by
/// being killed, which the caller sees as a signal or exit status 124/137, not as a clean
/// error). Uses util-linux `prlimit` and coreutils `timeout`, present on every Debian.
pub fn greybox_limited(args: &[&str], cwd: &Path, memory_mib: u64, seconds: u64) -> Output {
    let bytes = (memory_mib << 20).to_string();
    let mut cmd = Command::new("timeout");
    cmd.arg("--signal=KILL")
        .arg(seconds.to_string())
        .arg("prlimit")
        .arg(format!("--as={bytes}"))
        .arg("--")
        .arg(env!("CARGO_BIN_EXE_greybox"))
        .args(args)
        .current_dir(cwd);
    cmd.output().expect("run greybox under prlimit and timeout")
}

/// Assert a clean refusal under limits: the process exited by itself with a failure status
/// (not killed by the time or memory limit, not a panic) and its message contains every
/// one of `needles`; returns stderr.
pub fn refused_with(out: &Output, needles: &[&str]) -> String {
    use std::os::unix::process::ExitStatusExt;
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.signal().is_none() && !matches!(out.status.code(), Some(124 | 137)),
        "killed by a limit ({:?}); stderr: {stderr}",
        out.status
    );
    assert!(
        !out.status.success(),
        "expected a refusal, stdout: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    for n in needles {
        assert!(stderr.contains(n), "expected {n:?} in: {stderr}");
    }
    stderr
}

/// A small SVG plot (a polyline and a label), as greybox draws them.
pub const PLOT: &str = r#"<?xml version="1.0"?><svg xmlns="http://www.w3.org/2000/svg" width="200" height="100" viewBox="0 0 200 100"><rect width="200" height="100" fill="white"/><polyline fill="none" stroke="black" points="0,0 100,50 200,20"/><text x="10" y="20">forces</text></svg>"#;

/// A study directory `root/study` that `greybox report` recognises: a cut directory
/// (`summary.json`, a force plot and three frames) and a wear table.
pub fn study(root: &Path) -> std::path::PathBuf {
    let s = root.join("study");
    std::fs::create_dir_all(s.join("cut/frames")).unwrap();
    std::fs::write(
        s.join("cut/summary.json"),
        r#"{"cutting_force_n_per_mm": 201.5, "law": "coulomb"}"#,
    )
    .unwrap();
    std::fs::write(s.join("cut/forces.svg"), PLOT).unwrap();
    for k in 1..=3 {
        std::fs::write(s.join(format!("cut/frames/chip_00{k}.svg")), PLOT).unwrap();
    }
    std::fs::write(
        s.join("wear.csv"),
        "pin,normal_force_N,velocity_m_per_min,duration_s,k_1e-7_mm3_per_Nm,mean_depth_um\n1,100,60,30,2.5,1.2\n",
    )
    .unwrap();
    s
}

#[path = "../../../../tests/support/real_rigs.rs"]
mod real_rigs;
#[allow(unused_imports)] // only the real-rig tests use it
pub use real_rigs::real_rigs_dir;

/// The names in `dir`, sorted (to show that a refused run added nothing).
pub fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Writes the suite file `dir/name` on the bundled Ti6Al4V data and J-C template: these
/// calibration conditions, μ bracket [0.2, 0.8], then the TOML lines `extra`.
pub fn ti64_suite(dir: &Path, name: &str, calibration: &[&str], extra: &str) {
    let v = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation");
    let ids: Vec<String> = calibration.iter().map(|c| format!("\"{c}\"")).collect();
    std::fs::write(
        dir.join(name),
        format!(
            "data = \"{}\"\n[[material]]\nname = \"Ti6Al4V\"\nsetup = \"{}\"\nrun_speed_m_per_min = 600.0\ncalibration = [{}]\nmu_bracket = [0.2, 0.8]\n{extra}",
            v.join("orthogonal-cutting.csv").display(),
            v.join("ti64-setup.toml").display(),
            ids.join(", ")
        ),
    )
    .unwrap();
}

/// A suite run's JSON results without the wall times (which no two runs share).
pub fn without_wall_times(mut v: serde_json::Value) -> serde_json::Value {
    for o in v["outcomes"].as_array_mut().unwrap() {
        o.as_object_mut().unwrap().remove("wall_s");
    }
    for s in v["summaries"].as_array_mut().unwrap() {
        s.as_object_mut().unwrap().remove("cut_seconds");
    }
    v
}

/// One stump on the pressure (XGBoost's JSON schema).
pub const BOOSTER: &str = r#"{"version": [3, 2, 0], "learner": {
  "objective": {"name": "reg:squarederror"},
  "feature_names": ["hertz_pressure_MPa", "sliding_velocity_m_per_min"],
  "learner_model_param": {"base_score": "[3.3E-1]", "num_feature": "2", "num_class": "0", "num_target": "1"},
  "gradient_booster": {"name": "gbtree", "model": {"trees": [{
    "left_children": [1, -1, -1], "right_children": [2, -1, -1], "split_indices": [0, 0, 0],
    "split_conditions": [1000.5, 0.0123, -0.0456], "split_type": [0, 0, 0], "default_left": [0, 0, 0],
    "tree_param": {"num_nodes": "3", "size_leaf_vector": "1"}}]}}}}"#;

/// [`BOOSTER`] written to `d/booster.json` and imported (pressure 150..2000 MPa, speed
/// 20..250 m/min) as the greybox model `d/m.json`.
pub fn imported_model(d: &Path) {
    std::fs::write(d.join("booster.json"), BOOSTER).unwrap();
    let args = [
        "import",
        "booster.json",
        "--domain",
        "150:2000,20:250",
        "--out",
        "m.json",
    ];
    ok(&greybox(&args, d));
}
