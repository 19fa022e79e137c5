//! The restart loop against the real CalculiX (Debian's calculix-ccx). Skipped when `ccx` is
//! not installed, unless GREYBOX_REQUIRE_CCX is set (`.ci/run` installs it and sets it).

use greybox_core::ContactState;
use greybox_couple::calculix::{CalculixConfig, CalculixEngine};
use greybox_couple::engine::{couple, Engine};
use greybox_couple::example::write_example;
use std::path::{Path, PathBuf};

fn ccx() -> Option<PathBuf> {
    greybox_testkit::calculix::have_ccx("the CalculiX coupling test").then(|| PathBuf::from("ccx"))
}

fn engine(dir: &Path, ccx: PathBuf) -> CalculixEngine {
    CalculixEngine::new(CalculixConfig {
        ccx,
        deck: dir.join("model.inp"),
        segment_template: dir.join("segment.inp"),
        work: dir.join("work"),
        pressure_pa_per_unit: 1e6,
        length_m_per_unit: 1e-3,
        segment_s: 1e-3,
    })
    .unwrap()
}

#[test]
fn fixed_mu_per_window_reads_back() {
    let Some(ccx) = ccx() else { return };
    let d = tempfile::tempdir().unwrap();
    write_example(d.path(), 5).unwrap();
    let mut e = engine(d.path(), ccx);
    assert_eq!(e.windows().len(), 5);
    e.run_segment(0, None).unwrap();
    let mu = [0.1, 0.2, 0.3, 0.4, 0.5];
    let states = e.run_segment(1, Some(&mu)).unwrap();
    for (s, m) in states.iter().zip(mu) {
        assert!(
            (s.shear_ratio - m).abs() <= 1e-3,
            "window read back {} for μ = {m}",
            s.shear_ratio
        );
        assert!(s.pressure_pa > 0.0 && s.sliding_velocity_m_s > 0.0);
    }
    // the pressure rises from window to window
    assert!(states
        .windows(2)
        .all(|w| w[1].pressure_pa > w[0].pressure_pa));
    assert!(
        d.path().join("work/cycle_001/job.rin").exists()
            && d.path().join("work/cycle_000/job.dat").exists()
    );
}

#[test]
fn pressure_dependent_law_converges() {
    let Some(ccx) = ccx() else { return };
    let d = tempfile::tempdir().unwrap();
    write_example(d.path(), 5).unwrap();
    let law = greybox_friction::spec::load_law(&d.path().join("law.json")).unwrap();
    let mut e = engine(d.path(), ccx);
    let r = couple(
        &mut e,
        law.as_ref(),
        10,
        1e-3,
        Some(&d.path().join("history.csv")),
    )
    .unwrap();
    assert!(r.converged, "not converged after {} cycles", r.cycles);
    let last: Vec<_> = r.history.iter().filter(|h| h.cycle == r.cycles).collect();
    for (h, (_, mu)) in last.iter().zip(&r.final_mu) {
        let st = ContactState {
            pressure_pa: h.pressure_mpa * 1e6,
            sliding_velocity_m_s: h.velocity_m_per_min / 60.0,
            temperature_k: 293.15,
        };
        assert!((law.mu(&st) - mu).abs() < 1e-6);
        // the engine applied the μ of the previous cycle, which is within the tolerance
        assert!(
            (h.shear_ratio - h.mu_used.unwrap()).abs() < 2e-3,
            "{} vs {:?}",
            h.shear_ratio,
            h.mu_used
        );
    }
    let spread = r
        .final_mu
        .iter()
        .map(|m| m.1)
        .fold(f64::NEG_INFINITY, f64::max)
        - r.final_mu.iter().map(|m| m.1).fold(f64::INFINITY, f64::min);
    assert!(
        spread > 0.05,
        "windows should end with visibly different μ: {:?}",
        r.final_mu
    );
    assert!(
        std::fs::read_to_string(d.path().join("history.csv"))
            .unwrap()
            .lines()
            .count()
            > 5
    );
}

#[test]
fn bad_decks_and_failing_runs() {
    let d = tempfile::tempdir().unwrap();
    write_example(d.path(), 3).unwrap();
    // a deck without the force output of one window is rejected before any run
    let deck = std::fs::read_to_string(d.path().join("model.inp")).unwrap();
    std::fs::write(
        d.path().join("bad.inp"),
        deck.replace("*CONTACT PRINT,SLAVE=SWORK,MASTER=STOOL2\nCF,CFN,CFS\n", ""),
    )
    .unwrap();
    let cfg = |deck: &str, seg: &str| CalculixConfig {
        ccx: PathBuf::from("ccx"),
        deck: d.path().join(deck),
        segment_template: d.path().join(seg),
        work: d.path().join("work"),
        pressure_pa_per_unit: 1e6,
        length_m_per_unit: 1e-3,
        segment_s: 1e-3,
    };
    let e = CalculixEngine::new(cfg("bad.inp", "segment.inp"))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("bad.inp") && e.contains("MASTER=STOOL2"), "{e}");
    std::fs::write(
        d.path().join("nofric.inp"),
        "*STEP\n*STATIC\n*CONTACT PRINT\nCDIS\n*RESTART,WRITE\n*END STEP\n",
    )
    .unwrap();
    let e = CalculixEngine::new(cfg("model.inp", "nofric.inp"))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("MASTER=STOOL1") || e.contains("{{FRICTION}}"),
        "{e}"
    );
    assert!(!d.path().join("work").exists(), "nothing ran");
    // a crashing segment stops the loop with the log tail; earlier cycles stay intact
    let Some(ccx) = ccx() else { return };
    let seg = std::fs::read_to_string(d.path().join("segment.inp")).unwrap();
    std::fs::write(
        d.path().join("crash.inp"),
        seg.replace("NTOP,1,1,1.", "NOSUCHSET,1,1,1."),
    )
    .unwrap();
    let mut e = CalculixEngine::new(CalculixConfig {
        ccx,
        ..cfg("model.inp", "crash.inp")
    })
    .unwrap();
    e.run_segment(0, None).unwrap();
    let err = e
        .run_segment(1, Some(&[0.3, 0.3, 0.3]))
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("cycle 1 failed") && err.contains("log tail"),
        "{err}"
    );
    assert!(
        d.path().join("work/cycle_000/job.dat").exists()
            && d.path().join("work/cycle_000/job.rout").exists()
    );
}
