//! `greybox simulate cutting` with a law file (outputs, grey-box μ history, resume bit for
//! bit, bad law file) and `greybox material fit|fit-c`.
mod common;
use common::{coarse_config, err, greybox, last_particle_vtk, ok};

#[test]
fn cutting_with_a_law_file_writes_profiles_and_resumes_bit_for_bit() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("law.json"),
        r#"{"law": "exponential-velocity", "mu_static": 0.6, "mu_dynamic": 0.2, "v_c_m_per_min": 30}"#,
    )
    .unwrap();
    coarse_config(d.path(), Some("law.json"));
    let s = ok(&greybox(
        &[
            "simulate",
            "cutting",
            "--config",
            "cut.toml",
            "--out",
            "a",
            "--checkpoint-every",
            "2000",
            "--json",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    assert!(v["law"].as_str().unwrap().contains("law.json"));
    assert!(v["window_updates"].as_u64().unwrap() > 20);
    assert!(v["cutting_force_n_per_mm"].as_f64().unwrap() > 100.0);
    assert!(v["chip_thickness_mm"].as_f64().unwrap() > 0.1);
    for f in [
        "forces.csv",
        "forces.svg",
        "contact_profile.csv",
        "mu_history.csv",
        "profile_stress.svg",
        "profile_velocity.svg",
        "profile_mu.svg",
        "profile_temperature.svg",
        "summary.json",
        "checkpoint.json",
    ] {
        assert!(d.path().join("a").join(f).exists(), "{f}");
    }
    let profile = std::fs::read_to_string(d.path().join("a/contact_profile.csv")).unwrap();
    assert!(profile.starts_with("window,face,distance_from_edge_um,mu,pressure_MPa,normal_stress_MPa,sliding_velocity_m_per_min"));
    // μ follows the velocity law: the windows in contact do not all share one μ.
    let mus: Vec<f64> = std::fs::read_to_string(d.path().join("a/mu_history.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(5).unwrap().parse().unwrap())
        .collect();
    let (lo, hi) = mus
        .iter()
        .fold((1.0f64, 0.0f64), |(a, b), &m| (a.min(m), b.max(m)));
    assert!(hi - lo > 0.1, "μ {lo}..{hi}");
    // Resume: the final particle state and the final profile are identical.
    ok(&greybox(
        &[
            "simulate",
            "cutting",
            "--config",
            "cut.toml",
            "--out",
            "b",
            "--resume",
            "a/checkpoint.json",
        ],
        d.path(),
    ));
    let last_vtk = |dir: &str| last_particle_vtk(&d.path().join(dir));
    assert_eq!(last_vtk("a"), last_vtk("b"));
}

/// A refined cut with the machined surface coarsened behind the tool and local time
/// stepping, set up in the TOML a user writes: the summary says how many particles the
/// merges took away and what energy they averaged out, as JSON and as text.
#[test]
fn a_refined_cut_with_coarsening_says_what_the_merges_did() {
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), None);
    let cut = d.path().join("cut.toml");
    let mut toml = std::fs::read_to_string(&cut)
        .unwrap()
        .replace("cut_length_m = 0.25e-3", "cut_length_m = 0.3e-3")
        .replace("[numerics]\n", "[numerics]\nlocal_time_stepping = true\n");
    toml.push_str(
        "\n[refinement]\nregions = [{ ahead_m = 0.2e-3, behind_m = 0.02e-3, below_m = 0.04e-3, \
         above_m = 0.3e-3 }]\ncoarsen_behind_m = 0.06e-3\n",
    );
    std::fs::write(&cut, toml).unwrap();
    let s = ok(&greybox(
        &[
            "simulate", "cutting", "--config", "cut.toml", "--out", "a", "--json",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    let merged = v["coarsened"]["particles"].as_u64().unwrap();
    let share = v["coarsened"]["share_of_work"].as_f64().unwrap();
    assert!(merged > 30 && merged.is_multiple_of(3), "{merged}");
    assert!(share > 0.0 && share < 0.01, "{share}");
    let text = ok(&greybox(
        &[
            "-q", "simulate", "cutting", "--config", "cut.toml", "--out", "b",
        ],
        d.path(),
    ));
    assert!(
        text.contains(&format!(
            "coarsening: {merged} refined particles merged away"
        )),
        "{text}"
    );
}

#[test]
fn cutting_and_material_input_errors_name_the_problem() {
    let d = tempfile::tempdir().unwrap();
    coarse_config(d.path(), Some("no-such-law.json"));
    let e = err(&greybox(
        &["simulate", "cutting", "--config", "cut.toml"],
        d.path(),
    ));
    assert!(
        e.contains("friction.law_file") && e.contains("no-such-law.json"),
        "{e}"
    );
    std::fs::write(
        d.path().join("curves.csv"),
        "strain,stress_MPa,temperature_C,strain_rate_per_s\n0.1,500,25,0.004\n0.2,abc,25,0.004\n",
    )
    .unwrap();
    let e = err(&greybox(
        &["material", "fit", "--curves", "curves.csv"],
        d.path(),
    ));
    assert!(
        e.contains("curves.csv") && e.contains("line 3") && e.contains("stress_MPa"),
        "{e}"
    );
    coarse_config(d.path(), None);
    let e = err(&greybox(
        &[
            "material",
            "fit-c",
            "--config",
            "cut.toml",
            "--measured-force-n-per-mm",
            "300",
            "--c-min",
            "0.1",
            "--c-max",
            "0.05",
        ],
        d.path(),
    ));
    assert!(e.contains("C_min < C_max"), "{e}");
}

#[test]
fn material_fit_recovers_the_parameters_of_written_curves() {
    let d = tempfile::tempdir().unwrap();
    let truth = greybox_material::JohnsonCook {
        room_temperature_k: 298.15,
        ..greybox_material::JohnsonCook::aisi1045_article()
    };
    let pts = greybox_material::fit::synthetic_flow_curves(
        &truth,
        &[25.0, 192.0, 359.0, 526.0, 693.0],
        4e-3,
        0.005,
        3,
        &|_| 1.0,
    );
    greybox_material::fit::write_flow_curves(&d.path().join("c.csv"), &pts).unwrap();
    let s = ok(&greybox(
        &[
            "material",
            "fit",
            "--curves",
            "c.csv",
            "--c",
            "0.045",
            "--room-temperature-c",
            "25",
            "--out",
            "fit.json",
            "--json",
        ],
        d.path(),
    ));
    let v: serde_json::Value = serde_json::from_str(&s).unwrap();
    let a = v["params"]["a_pa"].as_f64().unwrap();
    let n = v["params"]["n"].as_f64().unwrap();
    assert!((a / truth.a_pa - 1.0).abs() < 0.02, "A {a}");
    assert!((n / truth.n - 1.0).abs() < 0.05, "n {n}");
    assert!(d.path().join("fit.json").exists());
    let text = ok(&greybox(
        &["material", "fit", "--curves", "c.csv", "--c", "0.045"],
        d.path(),
    ));
    assert!(
        text.contains("Johnson-Cook: A =") && text.contains("temperature °C"),
        "{text}"
    );
}
