//! Real public tribometer exports (kept outside the project in `../shared/data/real-rigs`;
//! sources, licences and reader settings in tests/data/real-rigs/SOURCES.md and manifest.toml)
//! identified by the binary with the flags each rig's profile needs, against reference μ per
//! step from an independent script (scripts/real_rig_reference.py: pandas + numpy, the
//! manifest's explicit reader settings, μ = mean |F_t|/|F_n| over the final 50 % of each
//! step's sliding time). The same steady-state rule is asked of greybox (`--steady last:50%`),
//! and no other flag unless the file lacks a channel (the `.dwf` rig's load and speed);
//! the layout, the columns, their units and the blocks are greybox's own: the profile is
//! detected from each file's preamble and header.

use std::path::{Path, PathBuf};
mod common;
use common::{csv_column, greybox, ok};

/// The corpus of raw exports (`../shared/data/real-rigs` beside the checkout, or
/// `GREYBOX_REAL_RIGS_DIR`); `None` skips, unless `GREYBOX_REQUIRE_REAL_RIGS=1` (`.ci/run`).
fn corpus() -> Option<PathBuf> {
    common::real_rigs_dir()
}

/// The project's own files about the corpus: manifest, sources, reference values.
fn project_side() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/real-rigs")
}

/// Reference μ of a file, in step order (reference.csv written by the independent script).
fn reference(file: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(project_side().join("reference.csv")).unwrap();
    text.lines()
        .skip(1)
        .filter(|l| l.starts_with(&format!("{file},")))
        .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
        .collect()
}

/// μ per identified step (`cof_apparent`, dataset order) and the read notes.
/// `None` when the corpus is not there (the test then skips; see [`corpus`]).
fn identify(file: &str, extra: &[&str]) -> Option<Vec<f64>> {
    let d = tempfile::tempdir().unwrap();
    let path = corpus()?.join(file);
    let mut args = vec![
        "identify",
        "-q",
        "--steady",
        "last:50%",
        "--recordings",
        path.to_str().unwrap(),
        "--out",
        "data.csv",
    ];
    args.extend_from_slice(extra);
    ok(&greybox(&args, d.path()));
    let data = d.path().join("data.csv");
    // every value says how sure it is: a finite, non-negative 95 % half-width per row
    let ci = csv_column(&data, "cof_apparent_ci95");
    let mu = csv_column(&data, "cof_apparent");
    assert_eq!(ci.len(), mu.len(), "{file}: an interval per row");
    for (m, h) in mu.iter().zip(&ci) {
        assert!(h.is_finite() && *h >= 0.0, "{file}: μ {m} ± {h}");
        eprintln!("{file}: μ {m:.4} ± {h:.4}");
    }
    Some(mu)
}

fn check(file: &str, extra: &[&str], tol: f64) {
    let want = reference(file);
    assert!(!want.is_empty(), "no reference for {file}");
    let Some(got) = identify(file, extra) else {
        return;
    };
    assert_eq!(
        got.len(),
        want.len(),
        "{file}: steps {got:?} vs reference {want:?}"
    );
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!(
            (g - w).abs() <= tol,
            "{file} step {k}: μ {g:.4} vs reference {w:.4}"
        );
    }
}

#[test]
fn phoenix_te67_compend_exports() {
    // 15 preamble lines, tab, decimal comma, a name repeated twice, 1 Hz, 30-60 min tests
    for f in [
        "PPS_60N_1.tsv",
        "PPS_100N_1.tsv",
        "PPS+30PTFE_100N_200RPM_30MINS_1.tsv",
    ] {
        check(&format!("phoenix-te/{f}"), &[], 0.005);
    }
}

#[test]
fn pcs_mtm_single_step_exports() {
    // sparse tab table: empty and repeated column names, many empty fields
    for f in ["demo_5.txt", "demo_7.txt", "demo_8.txt"] {
        check(&format!("pcs-mtm/{f}"), &[], 0.005);
    }
}

#[test]
fn pcs_mtm_file_of_blocks() {
    // 49 blocks (profile steps), each with its own preamble and header; 24 sliding steps.
    // The first sliding step's load is still ramping (38.6 N mean against 50 N); with sliding
    // taken from the speed channel it is identified like the others (it used to be left out)
    // and agrees with the reference like every other step.
    check("pcs-mtm/demo-mtm-output.txt", &[], 0.005);
}

#[test]
fn pin_on_disc_dwf_exports_without_load_or_speed_channels() {
    // bare-CR lines, `;` with decimal commas; load from the file name (50 N), speed not
    // recorded: the two constants are the only flags; μ drifts by more than 0.01 within the
    // steady part (σ 0.014-0.046), hence the wider tolerance
    for f in [
        "9-Al10Cu-50N-140m-328.dwf",
        "1-2-MoS2-2.5-Al2O3-Al10Cu-50N-130m-353.dwf",
        "3-2-MoS2-7.5-Al2O3-Al10Cu-50N-.dwf",
    ] {
        check(
            &format!("custom-pod-dwf/{f}"),
            &[
                "--constant-normal-force-N",
                "50",
                "--constant-sliding-velocity-m-per-min",
                "20",
            ],
            0.01,
        );
    }
}

/// Under the default rule (`--steady auto`) every long test is identified from its FINAL
/// stationary stretch: the window ends at the end of the test (never a short stretch early in
/// the run-in, which is what a jittering or quantised speed channel used to cause), after a
/// run-in that is reported.
#[test]
fn the_default_rule_takes_the_final_stationary_stretch() {
    for (file, end_s) in [
        ("phoenix-te/PPS_60N_1.tsv", 1804.7),
        ("phoenix-te/PPS_100N_1.tsv", 1804.7),
        ("phoenix-te/PPS+30PTFE_100N_200RPM_30MINS_1.tsv", 3606.2),
        ("pcs-mtm/demo_7.txt", 7500.0),
        ("pcs-mtm/demo_8.txt", 7500.0),
        ("pcs-mtm/demo_5.txt", 10000.0),
    ] {
        let d = tempfile::tempdir().unwrap();
        let Some(dir) = corpus() else { return };
        let path = dir.join(file);
        ok(&greybox(
            &[
                "identify",
                "-q",
                "--recordings",
                path.to_str().unwrap(),
                "--out",
                "data.csv",
            ],
            d.path(),
        ));
        let text = std::fs::read_to_string(d.path().join("data.csv")).unwrap();
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        let row: Vec<&str> = lines.next().expect("one row").split(',').collect();
        let col = |name: &str| row[header.iter().position(|h| *h == name).unwrap()];
        let end: f64 = col("plateau_end_s").parse().unwrap();
        assert!(
            end > end_s - 10.0,
            "{file}: the steady window ends at {end} s, the test at {end_s} s"
        );
        let mu: f64 = col("cof_apparent").parse().unwrap();
        assert!((0.05..0.2).contains(&mu), "{file}: μ {mu}");
    }
}
