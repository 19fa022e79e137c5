//! `greybox identify` on linear reciprocating tests (ASTM G133): recordings from the virtual
//! reciprocating rig (5 Hz, 1 mm stroke, μ 0.30 forward / 0.26 backward, run-in, reversal
//! transients, noise) written as text by the test, with and without a position column, and
//! as a UMT-like export of half-stroke blocks.

use greybox_recording::Recording;
use greybox_tribo::synth_recip::{reciprocating_recording, umt_export_text, RecipSpec};
use std::fmt::Write as _;
use std::path::Path;
mod common;
use common::{greybox, ok};

/// A plain CSV export: time, F_N, F_t and (optionally) the stroke position in mm.
fn plain_csv(rec: &Recording, position: bool) -> String {
    let mut s = String::from("time (s),Fn (N),Ft (N)");
    s.push_str(if position { ",x position (mm)\n" } else { "\n" });
    for k in 0..rec.len() {
        let _ = write!(
            s,
            "{:.4},{:.5},{:.5}",
            rec.time_s[k], rec.normal_n[k], rec.tangential_n[k]
        );
        if position {
            let _ = write!(s, ",{:.6}", rec.position_m.as_ref().unwrap()[k] * 1e3);
        }
        s.push('\n');
    }
    s
}

/// Run identify; the dataset's μ and flags, and the cycles file's rows.
fn identify(
    dir: &Path,
    file: &str,
    extra: &[&str],
) -> (String, Vec<(f64, String)>, Vec<Vec<String>>) {
    let mut args = vec![
        "identify",
        "--no-plan",
        "--inspect",
        "--recordings",
        file,
        "--out",
        "data.csv",
    ];
    args.extend_from_slice(extra);
    let stdout = ok(&greybox(&args, dir));
    if std::env::var("SHOW").is_ok() {
        eprintln!("{stdout}");
    }
    let text = std::fs::read_to_string(dir.join("data.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (kc, kf) = (
        header.iter().position(|h| *h == "cof_apparent").unwrap(),
        header.iter().position(|h| *h == "flags").unwrap(),
    );
    let rows = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[kc].parse().unwrap(), f[kf].to_string())
        })
        .collect();
    let cycles = std::fs::read_to_string(dir.join("data.csv.cycles.csv"))
        .map(|t| {
            t.lines()
                .map(|l| l.split(',').map(String::from).collect())
                .collect()
        })
        .unwrap_or_default();
    (stdout, rows, cycles)
}

/// Mean of a cycles-file column over the steady cycles.
fn steady_mean(cycles: &[Vec<String>], column: &str) -> f64 {
    let k = cycles[0].iter().position(|h| h == column).unwrap();
    let steady: Vec<f64> = cycles[1..]
        .iter()
        .filter(|r| r[8] == "1")
        .map(|r| r[k].parse().unwrap())
        .collect();
    steady.iter().sum::<f64>() / steady.len() as f64
}

fn check(stdout: &str, rows: &[(f64, String)], cycles: &[Vec<String>], n_cycles: usize) {
    assert_eq!(rows.len(), 1, "{rows:?}");
    assert!((rows[0].0 - 0.28).abs() < 0.003, "μ {}", rows[0].0);
    assert!(rows[0].1.contains("reciprocating"), "{}", rows[0].1);
    assert_eq!(
        cycles[0],
        [
            "file",
            "cycle",
            "time_s",
            "mu_forward",
            "mu_backward",
            "mu_mean",
            "pin",
            "step",
            "steady"
        ]
    );
    assert_eq!(cycles.len() - 1, n_cycles, "cycles counted exactly");
    let (f, b) = (
        steady_mean(cycles, "mu_forward"),
        steady_mean(cycles, "mu_backward"),
    );
    assert!(
        (f - 0.30).abs() < 0.003 && (b - 0.26).abs() < 0.003,
        "μ forward {f}, backward {b}"
    );
    assert!(
        stdout.contains(&format!("{} strokes", 2 * n_cycles)),
        "{stdout}"
    );
    assert!(
        stdout.contains("μ forward 0.30") && stdout.contains("backward 0.26"),
        "{stdout}"
    );
}

#[test]
fn with_a_position_column() {
    let d = tempfile::tempdir().unwrap();
    let (rec, _) = reciprocating_recording(&RecipSpec::default());
    std::fs::write(d.path().join("recip.csv"), plain_csv(&rec, true)).unwrap();
    let (stdout, rows, cycles) = identify(d.path(), "recip.csv", &[]);
    check(&stdout, &rows, &cycles, 100);
    assert!(
        stdout.contains("turning points of the position"),
        "{stdout}"
    );
    assert!(d.path().join("data_inspect/recip.csv.cycles.svg").is_file());
}

#[test]
fn without_a_position_from_the_force_sign() {
    let d = tempfile::tempdir().unwrap();
    let (rec, _) = reciprocating_recording(&RecipSpec::default());
    std::fs::write(d.path().join("recip.csv"), plain_csv(&rec, false)).unwrap();
    let v = ["--constant-sliding-velocity-m-per-min", "0.9"];
    let (stdout, rows, cycles) = identify(d.path(), "recip.csv", &v);
    check(&stdout, &rows, &cycles, 100);
    assert!(
        stdout.contains("sign changes of the friction force"),
        "{stdout}"
    );
    // named continuous: the old plateau identification, no cycles file
    std::fs::remove_file(d.path().join("data.csv.cycles.csv")).unwrap();
    let mut args = vec!["--test-mode", "continuous"];
    args.extend_from_slice(&v);
    let out = greybox(
        &[
            &[
                "identify",
                "--no-plan",
                "--recordings",
                "recip.csv",
                "--out",
                "data.csv",
            ][..],
            &args[..],
        ]
        .concat(),
        d.path(),
    );
    let _ = out; // a plateau mean of a reversing force may be refused as implausible; either way:
    assert!(!d.path().join("data.csv.cycles.csv").exists());
}

#[test]
fn umt_export_of_half_stroke_blocks() {
    let d = tempfile::tempdir().unwrap();
    let spec = RecipSpec {
        sample_rate_hz: 500.0,
        frequency_hz: 2.0,
        cycles: 60,
        run_in_cycles: 4.0,
        ..RecipSpec::default()
    };
    let (rec, block) = reciprocating_recording(&spec);
    std::fs::write(d.path().join("umt_001.csv"), umt_export_text(&rec, &block)).unwrap();
    let v = ["--constant-sliding-velocity-m-per-min", "0.24"];
    let (stdout, rows, cycles) = identify(d.path(), "umt_001.csv", &v);
    check(&stdout, &rows, &cycles, 60);
    assert!(
        stdout.contains("bruker-umt") && stdout.contains("blocks (one per half-stroke)"),
        "{stdout}"
    );
}

#[test]
fn study_mode_reciprocating_is_read() {
    let d = tempfile::tempdir().unwrap();
    let (rec, _) = reciprocating_recording(&RecipSpec::default());
    std::fs::write(d.path().join("recip.csv"), plain_csv(&rec, true)).unwrap();
    std::fs::write(
        d.path().join("study.toml"),
        "[identify]\nmode = \"reciprocating\"\n",
    )
    .unwrap();
    let (_, rows, cycles) = identify(d.path(), "recip.csv", &["--study", "study.toml"]);
    assert_eq!(rows.len(), 1);
    assert_eq!(cycles.len() - 1, 100);
}
