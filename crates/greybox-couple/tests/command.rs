//! The command engine with a scripted stand-in solver: each window's pressure is fixed and the
//! script applies the μ it is given (shear ratio = μ); with a constant law the loop converges
//! after one update.

use greybox_couple::engine::{couple, CommandEngine};

#[test]
fn scripted_engine_loop() {
    let d = tempfile::tempdir().unwrap();
    let script = d.path().join("solver.sh");
    std::fs::write(
        &script,
        "#!/bin/sh\n# stand-in solver: window i has pressure 50*i MPa; shear ratio = the μ it was given (0.3 when empty)\ncd \"$1\"\necho 'window,pressure_MPa,sliding_velocity_m_per_min,temperature_K,shear_ratio' > states.csv\ni=0\ntail -n +2 friction.csv | while IFS=, read w mu; do i=$((i+1)); [ -z \"$mu\" ] && mu=0.3; echo \"$w,$((50*i)),100,,$mu\" >> states.csv; done\n",
    )
    .unwrap();
    let mut e = CommandEngine {
        windows: vec!["W1".into(), "W2".into(), "W3".into()],
        command: format!("sh {} {{dir}}", script.display()),
        work: d.path().join("work"),
    };
    let law = greybox_friction::classical::Coulomb { mu: 0.25 };
    let r = couple(&mut e, &law, 5, 1e-3, None).unwrap();
    assert!(r.converged && r.cycles == 1, "{r:?}");
    assert!(r
        .history
        .iter()
        .filter(|h| h.cycle == 1)
        .all(|h| (h.shear_ratio - 0.25).abs() < 1e-12));
    assert!(d.path().join("work/cycle_001/friction.csv").exists());
    // a failing command stops with its output
    let mut bad = CommandEngine {
        windows: vec!["W1".into()],
        command: "echo solver exploded >&2; exit 3".into(),
        work: d.path().join("bad"),
    };
    let e = couple(&mut bad, &law, 5, 1e-3, None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("solver exploded") && e.contains("cycle 0"),
        "{e}"
    );
}

/// The stand-in solver of [`scripted_engine_loop`], written into `d`.
fn solver(d: &std::path::Path) -> std::path::PathBuf {
    let script = d.join("solver.sh");
    std::fs::write(
        &script,
        "#!/bin/sh\ncd \"$1\" || exit 9\n[ \"$#\" -eq 2 ] || { echo \"got $# arguments\" >&2; exit 8; }\necho 'window,pressure_MPa,sliding_velocity_m_per_min,temperature_K,shear_ratio' > states.csv\ntail -n +2 friction.csv | while IFS=, read w mu; do [ -z \"$mu\" ] && mu=0.3; echo \"$w,50,100,,$mu\" >> states.csv; done\n",
    )
    .unwrap();
    script
}

/// Work directories a shell would split or run: `;`, blanks, quotes, `$()`, a newline. Each
/// reaches the solver as one argument; nothing the name spells is run.
#[test]
fn hostile_work_directories_are_one_argument() {
    let d = tempfile::tempdir().unwrap();
    let script = solver(d.path());
    let law = greybox_friction::classical::Coulomb { mu: 0.25 };
    for name in [
        "w;touch PWNED;x",
        "my runs",
        "it's here",
        "$(touch PWNED)",
        "`touch PWNED`",
        "a\nb",
        "{prev_dir}",
    ] {
        let mut e = CommandEngine {
            windows: vec!["W1".into()],
            command: format!("sh '{}' {{dir}} {{prev_dir}}", script.display()),
            work: d.path().join(name),
        };
        let r = couple(&mut e, &law, 5, 1e-3, None)
            .unwrap_or_else(|err| panic!("work dir {name:?}: {err}"));
        assert!(r.converged, "{name:?}: {r:?}");
        assert!(d.path().join(name).join("cycle_001/states.csv").exists());
    }
    for dir in [d.path().to_path_buf(), std::env::current_dir().unwrap()] {
        assert!(
            !dir.join("PWNED").exists(),
            "PWNED created in {}",
            dir.display()
        );
    }
}

/// A template that quotes a placeholder itself is refused before anything runs.
#[test]
fn quoted_placeholders_are_refused() {
    let d = tempfile::tempdir().unwrap();
    let law = greybox_friction::classical::Coulomb { mu: 0.25 };
    let mut e = CommandEngine {
        windows: vec!["W1".into()],
        command: "touch PWNED; sh solver.sh \"{dir}\"".into(),
        work: d.path().join("w"),
    };
    let err = couple(&mut e, &law, 5, 1e-3, None).unwrap_err().to_string();
    assert!(
        err.contains("quotes {dir}") && err.contains("without quotes"),
        "{err}"
    );
    assert!(!std::path::Path::new("PWNED").exists());
}
