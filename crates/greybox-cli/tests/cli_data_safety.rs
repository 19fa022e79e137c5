//! Outputs that used to destroy inputs or mix runs (issue "never lose data"): each case here
//! succeeded, and lost data, before outputs were checked against inputs and staged.

use std::path::Path;
mod common;
use common::{err, greybox, ok};

fn campaign(p: &Path) {
    ok(&greybox(
        &[
            "plan",
            "--track-radius-mm",
            "100",
            "--normal-force-count",
            "3",
            "--velocity-count",
            "4",
            "--out",
            "plan",
        ],
        p,
    ));
    ok(&greybox(
        &["synth", "--study", "plan/study.toml", "--out", "r"],
        p,
    ));
}

fn identify(p: &Path, out: &str) -> std::process::Output {
    greybox(
        &[
            "identify",
            "--study",
            "plan/study.toml",
            "--recordings",
            "r",
            "--out",
            out,
        ],
        p,
    )
}

#[test]
fn an_output_that_is_an_input_is_refused_and_the_input_kept() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    campaign(p);
    let raw = std::fs::read(p.join("r/pin01.csv")).unwrap();
    let e = err(&identify(p, "r/pin01.csv"));
    assert!(e.contains("--out is the input --recordings"), "{e}");
    assert_eq!(
        std::fs::read(p.join("r/pin01.csv")).unwrap(),
        raw,
        "the recording was replaced"
    );
    // the same file through another name
    std::fs::hard_link(p.join("r/pin02.csv"), p.join("alias.csv")).unwrap();
    let e = err(&identify(p, "alias.csv"));
    assert!(e.contains("input --recordings"), "{e}");
    ok(&identify(p, "data.csv"));
    // what produced the dataset: the command and every recording with its SHA-256
    let prov: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(p.join("data.csv.provenance.json")).unwrap())
            .unwrap();
    assert!(prov["command"]
        .as_array()
        .unwrap()
        .iter()
        .any(|c| c == "identify"));
    let inputs = prov["inputs"].as_array().unwrap();
    let pin1 = inputs
        .iter()
        .find(|i| i["path"].as_str().unwrap().ends_with("pin01.csv"))
        .expect("pin01.csv recorded");
    let sum = std::process::Command::new("sha256sum")
        .arg(p.join("r/pin01.csv"))
        .output()
        .unwrap();
    let want = String::from_utf8_lossy(&sum.stdout)
        .split_whitespace()
        .next()
        .unwrap()
        .to_string();
    assert_eq!(pin1["sha256"], want.as_str());
    assert!(inputs.iter().any(|i| i["role"] == "study"));
    // adhesive --out = --data, export --out = --law
    let data = std::fs::read(p.join("data.csv")).unwrap();
    let e = err(&greybox(
        &["adhesive", "--data", "data.csv", "--out", "data.csv"],
        p,
    ));
    assert!(e.contains("--out is the input --data"), "{e}");
    assert_eq!(std::fs::read(p.join("data.csv")).unwrap(), data);
    std::fs::write(p.join("law.json"), r#"{"law": "coulomb", "mu": 0.4}"#).unwrap();
    let e = err(&greybox(
        &[
            "export", "--law", "law.json", "--format", "csv", "--out", "law.json",
        ],
        p,
    ));
    assert!(e.contains("--out is the input --law"), "{e}");
    assert!(std::fs::read_to_string(p.join("law.json"))
        .unwrap()
        .contains("coulomb"));
}

#[cfg(unix)]
#[test]
fn devices_and_fifos_are_never_replaced_by_regular_files() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    campaign(p);
    let e = err(&identify(p, "/dev/null"));
    assert!(e.contains("character device"), "{e}");
    assert!(!std::fs::metadata("/dev/null").unwrap().is_file());
    assert!(std::process::Command::new("mkfifo")
        .arg(p.join("pipe"))
        .status()
        .unwrap()
        .success());
    let e = err(&identify(p, "pipe"));
    assert!(e.contains("FIFO"), "{e}");
    assert!(!std::fs::metadata(p.join("pipe")).unwrap().is_file());
}

#[test]
fn a_directory_holds_one_complete_run() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    campaign(p);
    ok(&identify(p, "data.csv"));
    let fit = |extra: &[&str]| {
        let mut args = vec![
            "fit",
            "--data",
            "data.csv",
            "--families",
            "random-forest",
            "--skip-nested",
            "--out",
            "fit",
        ];
        args.extend_from_slice(extra);
        greybox(&args, p)
    };
    ok(&fit(&[]));
    // an old run's file that the new run does not write
    std::fs::write(p.join("fit/models/svr.json"), "stale").unwrap();
    let e = err(&fit(&[]));
    assert!(e.contains("--force"), "{e}");
    assert!(
        p.join("fit/models/svr.json").exists(),
        "a refused run changed the directory"
    );
    ok(&fit(&["--force"]));
    assert!(
        !p.join("fit/models/svr.json").exists(),
        "stale model from the previous run kept"
    );
    assert!(p.join("fit/models/random-forest.json").exists());
    // no staging directory or temp file left beside it
    let leftovers: Vec<String> = std::fs::read_dir(p)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // an output directory holding the input is refused
    std::fs::copy(p.join("data.csv"), p.join("fit/data.csv")).unwrap();
    let e = err(&greybox(
        &[
            "fit",
            "--data",
            "fit/data.csv",
            "--families",
            "random-forest",
            "--skip-nested",
            "--out",
            "fit",
            "--force",
        ],
        p,
    ));
    assert!(e.contains("holds the input --data"), "{e}");
}

/// SIGTERM while a large plan is being written: no hidden temporary is left behind.
#[cfg(unix)]
#[test]
fn an_interrupted_run_leaves_no_temporaries() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_greybox"))
        .args([
            "plan",
            "--track-radius-mm",
            "100",
            "--normal-force-count",
            "200000",
            "--out",
            "big",
        ])
        .current_dir(p)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // wait until it is writing (a staging directory exists), then interrupt it
    let staging = || {
        std::fs::read_dir(p).unwrap().any(|e| {
            e.unwrap()
                .file_name()
                .to_string_lossy()
                .contains("greybox-staging")
        })
    };
    let t0 = std::time::Instant::now();
    while !staging() && t0.elapsed().as_secs() < 60 {
        if child.try_wait().unwrap().is_some() {
            panic!("the plan finished before it could be interrupted: make it bigger");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(staging(), "no staging directory appeared");
    std::thread::sleep(std::time::Duration::from_millis(200));
    assert!(std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let out = child.wait_with_output().unwrap();
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(out.status.signal(), Some(15), "{:?}", out.status);
    let left: Vec<String> = std::fs::read_dir(p)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    assert!(left.is_empty(), "left behind after SIGTERM: {left:?}");
}

/// A bare model used as a law used to assume the textbook-max convention whatever its
/// dataset used (μ +26 % at the demo's point); the model now records its dataset's map from
/// pressure to force, and a law that states a different contact is refused.
#[test]
fn a_bare_model_law_uses_its_datasets_pressure_convention() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    campaign(p);
    ok(&greybox(
        &[
            "identify",
            "--study",
            "plan/study.toml",
            "--recordings",
            "r",
            "--convention",
            "article-eq7",
            "--out",
            "data.csv",
        ],
        p,
    ));
    ok(&greybox(
        &[
            "fit",
            "--data",
            "data.csv",
            "--families",
            "gradient-boosting",
            "--skip-nested",
            "--out",
            "fit",
        ],
        p,
    ));
    let model: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(p.join("fit/models/gradient-boosting.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(
        model["force_to_pressure"]["pressure_convention"],
        "article-eq7"
    );
    assert!(
        model["provenance"]["inputs"][0]["sha256"]
            .as_str()
            .unwrap()
            .len()
            == 64
    );
    let law = |contact: &str| {
        format!(
            r#"{{"law": "learned", "model": "fit/models/gradient-boosting.json", "contact": {{"convention": "{contact}"}}}}"#
        )
    };
    std::fs::write(p.join("eq7.json"), law("article-eq7")).unwrap();
    std::fs::write(p.join("max.json"), law("textbook-max")).unwrap();
    let export = |law: &str, out: &str| {
        greybox(
            &[
                "export",
                "--law",
                law,
                "--format",
                "csv",
                "--out",
                out,
                "--pressure-MPa",
                "600:900:4",
                "--velocity-m-per-min",
                "30:90:3",
            ],
            p,
        )
    };
    ok(&export("fit/models/gradient-boosting.json", "bare.csv"));
    ok(&export("eq7.json", "eq7.csv"));
    let bare = std::fs::read_to_string(p.join("bare.csv")).unwrap();
    assert_eq!(
        bare,
        std::fs::read_to_string(p.join("eq7.csv")).unwrap(),
        "bare model and its dataset's convention differ"
    );
    let e = err(&export("max.json", "max.csv"));
    assert!(e.contains("article-eq7") && e.contains("Pa at 1 N"), "{e}");
}
