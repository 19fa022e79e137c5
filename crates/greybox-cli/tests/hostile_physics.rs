//! The physics table consulted wherever a physical quantity enters (issue 62, mechanism 2):
//! flags, law files, set-ups. Outside a quantity's possible range the value is refused
//! naming the setting, the number and the likely unit slip; outside its usual range it is
//! accepted with a warning line that says the same (`greybox_core::notes`, printed once).

mod common;
use common::{greybox_limited, refused_with};
use std::path::Path;

fn run(args: &[&str], cwd: &Path) -> std::process::Output {
    greybox_limited(args, cwd, 1024, 60)
}

/// Accepted, with a warning holding every needle.
fn warned(out: &std::process::Output, needles: &[&str]) {
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "refused: {stderr}");
    let line = stderr
        .lines()
        .find(|l| l.starts_with("warning:") && needles.iter().all(|n| l.contains(n)));
    assert!(line.is_some(), "no warning with {needles:?} in: {stderr}");
}

#[test]
fn hertz_radii_moduli_and_loads_are_checked() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    warned(
        &run(&["hertz", "--force-N", "100", "--radius-mm", "0.017"], d),
        &["--radius-mm", "contact radius 1.7e-5 m", "×1000 → 0.017"],
    );
    refused_with(
        &run(&["hertz", "--force-N", "100", "--radius-mm", "1e308"], d),
        &["--radius-mm", "outside the possible range"],
    );
    refused_with(
        &run(&["hertz", "--force-N", "100", "--e2-GPa", "650e9"], d),
        &["Young's modulus 6.5e20 Pa", "Pa given where GPa is asked"],
    );
    warned(
        &run(&["hertz", "--force-N", "5e-324"], d),
        &["--force-N (value 1)", "normal force 5e-324 N"],
    );
}

#[test]
fn export_grids_taumax_and_law_stresses_are_checked() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    std::fs::write(
        d.join("sf.json"),
        r#"{"law": "shear-factor", "m": 0.8, "k_MPa": 0.5}"#,
    )
    .unwrap();
    let export = |extra: &[&str]| {
        let mut a = vec!["export", "--law", "sf.json", "--out", "t.out"];
        a.extend_from_slice(extra);
        run(&a, d)
    };
    warned(
        &export(&["--format", "csv"]),
        &[
            "k_MPa",
            "shear flow stress 500000 Pa",
            "GPa given where MPa is asked",
        ],
    );
    refused_with(
        &export(&["--format", "csv", "--pressure-MPa", "500000:2500000:3"]),
        &[
            "--pressure-MPa",
            "contact pressure 5e11 Pa",
            "possible range",
        ],
    );
    refused_with(
        &export(&["--format", "csv", "--velocity-m-per-min", "20000:30000:3"]),
        &[
            "--velocity-m-per-min",
            "sliding velocity 333.3 m/s",
            "m/min read as m/s",
        ],
    );
    warned(
        &export(&["--format", "abaqus", "--taumax-MPa", "0.6"]),
        &["--taumax-MPa", "shear flow stress 600000 Pa"],
    );
    refused_with(
        &export(&["--format", "csv", "--temperature-K=-20:20:3"]),
        &["--temperature-K", "temperature -20 K"],
    );
}

#[test]
fn set_ups_and_track_widths_are_checked() {
    let d = tempfile::tempdir().unwrap();
    let d = d.path();
    // a density in g/cm³: refused with the slip named
    common::coarse_config(d, None);
    let cut = std::fs::read_to_string(d.join("cut.toml"))
        .unwrap()
        .replace("density_kg_m3 = 7850.0", "density_kg_m3 = 7.85");
    std::fs::write(d.join("bad.toml"), cut).unwrap();
    refused_with(
        &run(
            &["simulate", "cutting", "--config", "bad.toml", "--out", "o"],
            d,
        ),
        &[
            "density_kg_m3",
            "density 7.85 kg/m³",
            "g/cm³ read as kg/m³ (×1000 → 7850)",
        ],
    );
    // μ = 1.5 in a cut too short to run: accepted, said, then the refusal
    let cut = std::fs::read_to_string(d.join("cut.toml")).unwrap();
    let mu_line = cut
        .lines()
        .find(|l| l.starts_with("mu "))
        .expect("the set-up's μ");
    std::fs::write(d.join("mu.toml"), cut.replace(mu_line, "mu = 1.5")).unwrap();
    let e = refused_with(
        &run(
            &[
                "simulate",
                "cutting",
                "--config",
                "mu.toml",
                "--fraction",
                "1e-9",
                "--out",
                "o",
            ],
            d,
        ),
        &["less than one time step"],
    );
    assert!(
        e.contains("warning: mu: μ 1.5 is outside the usual range"),
        "{e}"
    );
    greybox_testkit::dataset::write_dataset(
        &d.join("ds.csv"),
        &[(100.0, 0.32), (200.0, 0.30), (300.0, 0.31)],
    );
    warned(
        &run(
            &[
                "adhesive",
                "--data",
                "ds.csv",
                "--track-width",
                "100:0.8",
                "--track-width",
                "200:1.2",
                "--track-width",
                "300:1.5",
                "--out",
                "a.csv",
            ],
            d,
        ),
        &["track width 1", "8e-7 m", "mm given where µm is asked"],
    );
    common::imported_model(d);
    // a blend fraction of 5 in a law file (the `law` command's flag refuses it already)
    std::fs::write(
        d.join("gb.json"),
        r#"{"law": "grey-box", "inner": {"law": "learned", "model": "m.json"}, "outside": {"law": "power-fit"}, "blend_fraction": 5, "shear_cap_k_MPa": 600}"#,
    )
    .unwrap();
    refused_with(
        &run(
            &[
                "export", "--law", "gb.json", "--format", "csv", "--out", "t.csv",
            ],
            d,
        ),
        &[
            "blend_fraction",
            "share 5 is outside the possible range 0..1",
        ],
    );
}
