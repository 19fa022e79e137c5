//! `greybox identify` on a log without a header line, its columns mapped by number
//! (`--map normal=#3:N`) or named with `--columns`, and `--list-rigs` without recordings.
//! The log is written here at a known μ, so the identified μ is known.

use std::fmt::Write as _;
mod common;
use common::{csv_column, err, greybox, ok};

/// 100 Hz, 80 s at 20 N, μ = 0.3 with a small ripple; fields time (s), friction force (N),
/// normal force (N), semicolon-delimited with decimal commas.
fn log() -> String {
    let mut s = String::new();
    for k in 0..8000 {
        let t = k as f64 * 0.01;
        let fn_n = 20.0;
        let ripple = 0.002 * (k as f64 * 0.7).sin();
        let line = format!("{t:.2};{:.5};{fn_n:.3}\n", (0.3 + ripple) * fn_n);
        let _ = write!(s, "{}", line.replace('.', ","));
    }
    s
}

#[test]
fn headerless_log_by_column_number_and_by_columns() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("logger"), log()).unwrap();
    let base = [
        "identify",
        "-q",
        "--recordings",
        "logger",
        "--out",
        "data.csv",
        "--constant-sliding-velocity-m-per-min",
        "30",
    ];
    let by_number = [
        "--map",
        "time=#1:s",
        "--map",
        "tangential=#2:N",
        "--map",
        "normal=#3:N",
    ];
    let by_name = ["--columns", "t_s,Ft_N,Fn_N"];
    let mut datasets = Vec::new();
    for extra in [&by_number[..], &by_name[..]] {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        ok(&greybox(&args, d.path()));
        let mu = csv_column(&d.path().join("data.csv"), "cof_apparent");
        assert!(!mu.is_empty(), "{extra:?}");
        assert!(
            mu.iter().all(|m| (m - 0.3).abs() < 0.002),
            "{extra:?}: {mu:?}"
        );
        datasets.push(std::fs::read(d.path().join("data.csv")).unwrap());
    }
    assert_eq!(
        datasets[0], datasets[1],
        "by number and by --columns differ"
    );
    // without a mapping the error lists the columns by number with their first values
    let e = err(&greybox(&base, d.path()));
    assert!(
        e.contains("#1: 0, 0.01, 0.02, 0.03, … (increasing: time?)") && e.contains("--columns"),
        "{e}"
    );
}

#[test]
fn rig_list_needs_no_recordings() {
    let d = tempfile::tempdir().unwrap();
    let out = ok(&greybox(&["identify", "--list-rigs"], d.path()));
    assert!(
        out.contains("phoenix-te") && out.contains("pod-dwf"),
        "{out}"
    );
    // anything else still needs them
    let e = err(&greybox(&["identify", "--out", "x.csv"], d.path()));
    assert!(e.contains("--recordings"), "{e}");
    let e = err(&greybox(&["identify", "--rig", "rtec"], d.path()));
    assert!(e.contains("--recordings"), "{e}");
    // `list` is no rig: the names are checked where the flag is read, and listed
    let e = err(&greybox(
        &["identify", "--rig", "list", "--recordings", "x.csv"],
        d.path(),
    ));
    assert!(
        e.contains("'list'") && e.contains("phoenix-te") && e.contains("auto"),
        "{e}"
    );
}
