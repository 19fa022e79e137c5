//! `greybox sweep run --executor slurm` against a real Slurm: a single-node cluster on this
//! machine (scripts/slurm_local.sh: munged, slurmctld, configless slurmd), a four-case sweep
//! of tiny cuts submitted as one array job, followed to the end and collected.
//!
//! Skips when Slurm is not installed, unless GREYBOX_REQUIRE_SLURM=1 (set by .ci/run), where
//! that is a failure.
mod common;
use common::{coarse_config, greybox, ok, ti64_suite, without_wall_times};
use std::path::{Path, PathBuf};
use std::process::Command;

fn have(cmd: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {cmd}")])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Stops the cluster when the test ends, also on a failure.
struct Cluster(PathBuf);

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(script()).arg("stop").arg(&self.0).status();
    }
}

fn script() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scripts/slurm_local.sh")
}

#[test]
fn a_four_case_sweep_runs_as_a_slurm_array_job_and_collects_every_result() {
    let missing: Vec<&str> = ["sbatch", "squeue", "slurmctld", "slurmd", "munged"]
        .into_iter()
        .filter(|c| !have(c))
        .collect();
    if !missing.is_empty() {
        assert!(
            std::env::var("GREYBOX_REQUIRE_SLURM").as_deref() != Ok("1"),
            "GREYBOX_REQUIRE_SLURM=1 but {missing:?} not installed (apt-get install slurm-wlm munge)"
        );
        eprintln!("skipped: {missing:?} not installed");
        return;
    }
    let d = tempfile::tempdir().unwrap();
    let state = d.path().join("slurm-state");
    let started = Command::new(script())
        .arg("start")
        .arg(&state)
        .output()
        .unwrap();
    let cluster = Cluster(state.clone());
    assert!(
        started.status.success(),
        "the cluster did not start:\n{}{}",
        String::from_utf8_lossy(&started.stdout),
        String::from_utf8_lossy(&started.stderr)
    );
    coarse_config(d.path(), None);
    std::fs::write(
        d.path().join("sweep.toml"),
        "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\nfraction = 0.3\n[[axis]]\nfield = \"cutting_speed_m_s\"\nvalues = [2.5, 3.5]\n[[axis]]\nfield = \"uncut_chip_thickness_m\"\nvalues = [8.0e-5, 1.0e-4]\n[slurm]\ncpus_per_task = 1\nmax_concurrent = 2\nextra = [\"--comment=greybox-test\"]\n",
    )
    .unwrap();
    let conf = state.join("slurm.conf");
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_greybox"))
            .args(args)
            .current_dir(d.path())
            .env("SLURM_CONF", &conf)
            .output()
            .unwrap()
    };
    // the script first, without submitting
    let dry = ok(&run(&[
        "sweep",
        "run",
        "sweep.toml",
        "--out",
        "o",
        "--executor",
        "slurm",
        "--dry-run",
    ]));
    assert!(
        dry.contains("#SBATCH --array=0-3%2") && dry.contains("--comment=greybox-test"),
        "{dry}"
    );
    let r: serde_json::Value = serde_json::from_str(&ok(&run(&[
        "-q",
        "sweep",
        "run",
        "sweep.toml",
        "--out",
        "o",
        "--executor",
        "slurm",
        "--poll-s",
        "0.5",
        "--json",
    ])))
    .unwrap();
    assert!(r["slurm_job"].as_str().is_some(), "{r}");
    assert_eq!(
        (r["done"].as_u64(), r["failed"].as_array().map(Vec::len)),
        (Some(4), Some(0)),
        "{r}"
    );
    let job = r["slurm_job"].as_str().unwrap();
    assert!(d.path().join(format!("o/slurm/logs/{job}_3.log")).is_file());
    // collect returns all four results
    let c: serde_json::Value = serde_json::from_str(&ok(&greybox(
        &["sweep", "collect", "o", "--json"],
        d.path(),
    )))
    .unwrap();
    assert_eq!(c["done"], 4, "{c}");
    // resubmitting submits nothing: every case is finished
    let again: serde_json::Value = serde_json::from_str(&ok(&run(&[
        "-q",
        "sweep",
        "run",
        "sweep.toml",
        "--out",
        "o",
        "--executor",
        "slurm",
        "--json",
    ])))
    .unwrap();
    assert_eq!(
        (again["skipped"].as_u64(), again["slurm_job"].as_str()),
        (Some(4), None)
    );
    suite_on_slurm(d.path(), &run);
    drop(cluster);
}

/// The validation suite file on the same cluster: each step of the suite one array job
/// with the suite's `[slurm]` resources, the results those of the cuts run in this process.
fn suite_on_slurm(dir: &Path, run: &dyn Fn(&[&str]) -> std::process::Output) {
    ti64_suite(
        dir,
        "suite.toml",
        &["D08"],
        "[slurm]\ncpus_per_task = 1\nmax_concurrent = 2\n",
    );
    let suite = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "-q",
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
            "0.3",
            "--json",
        ];
        args.extend_from_slice(extra);
        without_wall_times(serde_json::from_str(&ok(&run(&args))).unwrap())
    };
    let on_slurm = suite("v-slurm", &["--executor", "slurm", "--poll-s", "0.5"]);
    assert_eq!(on_slurm, suite("v-here", &[]));
    for batch in ["batch-01", "batch-02"] {
        let logs = dir.join("v-slurm/cuts").join(batch).join("slurm/logs");
        let n = std::fs::read_dir(&logs).map_or(0, |d| d.count());
        assert_eq!(
            n,
            2,
            "{batch}: one log per array task in {}",
            logs.display()
        );
    }
}
