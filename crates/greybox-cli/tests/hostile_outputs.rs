//! Hostile and careless input (issue 30): data loss one step beside the earlier fixes, and
//! silently wrong values. Each case runs the binary under a memory and a time limit and checks
//! the error text and that nothing was written or lost.

use std::path::Path;
mod common;
use common::{greybox, greybox_limited, ok, refused_with};

const MIB: u64 = 1024;
const SECONDS: u64 = 60;

fn run(args: &[&str], cwd: &Path) -> std::process::Output {
    greybox_limited(args, cwd, MIB, SECONDS)
}

/// `export --law law.json --out fit/models/svr.json` where the law names that model: the
/// model was replaced (files reached through a law file were not inputs).
#[test]
fn a_model_reached_through_a_law_file_is_an_input() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::create_dir_all(p.join("fit/models")).unwrap();
    std::fs::write(p.join("fit/models/svr.json"), "the trained model").unwrap();
    std::fs::write(p.join("fit/models/table.json"), "a table").unwrap();
    std::fs::write(
        p.join("law.json"),
        r#"{"law": "grey-box", "inner": {"law": "learned", "model": "fit/models/svr.json"}, "outside": {"law": "table", "file": "fit/models/table.json"}}"#,
    )
    .unwrap();
    for target in ["fit/models/svr.json", "fit/models/table.json"] {
        let e = refused_with(
            &run(
                &[
                    "export", "--law", "law.json", "--format", "csv", "--out", target,
                ],
                p,
            ),
            &["is the input a file the law reads", target],
        );
        assert!(!e.contains("panicked"));
    }
    assert_eq!(
        std::fs::read_to_string(p.join("fit/models/svr.json")).unwrap(),
        "the trained model"
    );
    assert_eq!(
        std::fs::read_to_string(p.join("fit/models/table.json")).unwrap(),
        "a table"
    );
    assert!(!p.join("fit/models/svr.json.provenance.json").exists());
}

/// `adhesive --data y.csv.provenance.json --out y.csv`: the input was overwritten by the
/// provenance record written beside the output.
#[test]
fn the_provenance_record_beside_an_output_must_not_be_an_input() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("y.csv.provenance.json"), "precious").unwrap();
    refused_with(
        &run(
            &[
                "adhesive",
                "--data",
                "y.csv.provenance.json",
                "--out",
                "y.csv",
            ],
            p,
        ),
        &["the provenance record beside --out", "is the input --data"],
    );
    assert_eq!(
        std::fs::read_to_string(p.join("y.csv.provenance.json")).unwrap(),
        "precious"
    );
    assert!(!p.join("y.csv").exists());
}

/// `export --out /dev/stdout` with stdout redirected to a file replaced the user's log file
/// and wrote `/dev/stdout.provenance.json` into /dev.
#[test]
fn outputs_under_dev_are_refused_whatever_they_point_to() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(p.join("law.json"), r#"{"law": "coulomb", "mu": 0.4}"#).unwrap();
    let log = p.join("log.txt");
    std::fs::write(&log, "the user's log\n").unwrap();
    for out in ["/dev/stdout", "/dev/stderr", "/dev/fd/1", "/proc/self/fd/1"] {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_greybox"))
            .args([
                "export", "--law", "law.json", "--format", "csv", "--out", out,
            ])
            .current_dir(p)
            .stdout(std::fs::OpenOptions::new().append(true).open(&log).unwrap())
            .output()
            .unwrap();
        refused_with(&o, &["the output path is under /"]);
        assert_eq!(
            std::fs::read_to_string(&log).unwrap(),
            "the user's log\n",
            "{out}"
        );
    }
    assert!(!Path::new("/dev/stdout.provenance.json").exists());
}

/// A grey-box shear cap typed in GPa (0.6 or 1 for 600 MPa) gave μ = 0.05 everywhere.
#[test]
fn a_shear_cap_below_any_metal_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(
        p.join("law.json"),
        r#"{"law": "grey-box", "inner": {"law": "coulomb", "mu": 0.4}, "outside": {"law": "coulomb", "mu": 0.4}, "shear_cap_k_MPa": 0.6}"#,
    )
    .unwrap();
    refused_with(
        &run(
            &[
                "export", "--law", "law.json", "--format", "csv", "--out", "t.csv",
            ],
            p,
        ),
        &["shear_cap_k_MPa is 0.6 MPa", "GPa"],
    );
    assert!(!p.join("t.csv").exists());
}

/// The tangential channel in kN in every pin read as N: μ 0.0002-0.0007 for steel on steel.
#[test]
fn a_campaign_with_implausible_mu_is_refused_with_the_numbers() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    ok(&greybox(
        &[
            "plan",
            "--track-radius-mm",
            "100",
            "--normal-force-count",
            "3",
            "--velocity-count",
            "3",
            "--out",
            "plan",
        ],
        p,
    ));
    ok(&greybox(
        &["synth", "--study", "plan/study.toml", "--out", "r"],
        p,
    ));
    // every pin's tangential channel rewritten in kN, its header still saying N
    for e in std::fs::read_dir(p.join("r")).unwrap() {
        let f = e.unwrap().path();
        if f.file_name().unwrap().to_string_lossy().starts_with("pin") {
            let text = std::fs::read_to_string(&f).unwrap();
            let mut lines = text.lines();
            let header = lines.next().unwrap();
            let col = header
                .split(',')
                .position(|c| c.starts_with("tangential"))
                .unwrap();
            let mut out = format!("{header}\n");
            for l in lines {
                let mut v: Vec<String> = l.split(',').map(str::to_string).collect();
                v[col] = format!("{}", v[col].parse::<f64>().unwrap() * 1e-3);
                out.push_str(&v.join(","));
                out.push('\n');
            }
            std::fs::write(&f, out).unwrap();
        }
    }
    refused_with(
        &run(
            &[
                "identify",
                "--study",
                "plan/study.toml",
                "--recordings",
                "r",
                "--out",
                "data.csv",
            ],
            p,
        ),
        &["the campaign's median μ", "0.005..3", "kN"],
    );
    assert!(!p.join("data.csv").exists());
}

/// A law naming `/dev/zero` (or a FIFO) as its model: read until the allocator gave up (or
/// waited for a writer forever). Model, law and table files are read only as regular files.
#[test]
fn a_law_whose_model_is_a_device_or_a_fifo_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    assert!(std::process::Command::new("mkfifo")
        .arg(p.join("pipe.json"))
        .status()
        .unwrap()
        .success());
    for model in ["/dev/zero", "pipe.json"] {
        std::fs::write(
            p.join("law.json"),
            format!(r#"{{"law": "learned", "model": "{model}"}}"#),
        )
        .unwrap();
        refused_with(
            &run(
                &[
                    "export", "--law", "law.json", "--format", "csv", "--out", "t.csv",
                ],
                p,
            ),
            &["model file is a", "not a regular file"],
        );
        assert!(!p.join("t.csv").exists());
    }
    refused_with(
        &run(
            &[
                "export",
                "--law",
                "/dev/zero",
                "--format",
                "csv",
                "--out",
                "t.csv",
            ],
            p,
        ),
        &["law file is a character device"],
    );
}
