//! Learned, grey-box and tabulated laws on a model fitted here; Abaqus round trip; law files.

use greybox_contact::PinContact;
use greybox_core::units::{PressureUnit, TemperatureUnit, VelocityUnit};
use greybox_core::{ContactState, FrictionLaw};
use greybox_friction::export::{abaqus, parse_abaqus_friction, Grid, Units};
use greybox_friction::greybox::{GreyBoxLaw, PowerLaw};
use greybox_friction::learned::LearnedLaw;
use greybox_friction::spec::load_law;
use greybox_friction::table::{Axis, TabulatedLaw};
use greybox_learn::protocol::{run_protocol, FitConfig};
use greybox_learn::table::read_dataset_from;
use greybox_model::Family;

/// A smooth SVR (rbf) model of μ(hertz_pressure_MPa, sliding_velocity_m_per_min).
fn fitted_model(family: Family) -> greybox_model::modelfile::ModelFile {
    fitted_model_scaled(family, 1.0)
}

/// [`fitted_model`] trained on `scale` × μ (100: a target in %).
fn fitted_model_scaled(family: Family, scale: f64) -> greybox_model::modelfile::ModelFile {
    let mut csv = String::from("hertz_pressure_MPa,sliding_velocity_m_per_min,mu\n");
    for i in 0..12 {
        for j in 0..12 {
            let p = 900.0 + 120.0 * i as f64;
            let v = 20.0 + 20.0 * j as f64;
            csv.push_str(&format!(
                "{p},{v},{}\n",
                scale * (0.5 - 0.1 * (p - 900.0) / 1300.0 - 0.1 * (v / 250.0).sqrt())
            ));
        }
    }
    let feats = vec![
        "hertz_pressure_MPa".to_string(),
        "sliding_velocity_m_per_min".to_string(),
    ];
    let data = read_dataset_from(csv.as_bytes(), "mem.csv", &feats, "mu", None).unwrap();
    let mut cfg = FitConfig {
        families: vec![family],
        skip_nested: true,
        bootstrap_resamples: greybox_learn::protocol::Resamples::of(10),
        importance_repeats: greybox_learn::protocol::Repeats::of(1),
        ..Default::default()
    };
    cfg.grid.svr.kernel = vec![greybox_model::svr::Kernel::Rbf];
    cfg.grid.svr.c = vec![10.0];
    cfg.grid.svr.epsilon = vec![0.001];
    cfg.grid.gradient_boosting.n_estimators = vec![100];
    cfg.grid.gradient_boosting.max_depth = vec![3];
    cfg.grid.gradient_boosting.learning_rate = vec![0.1];
    run_protocol(&data, &cfg).unwrap().1.remove(0)
}

fn st(p_mpa: f64, v_m_min: f64) -> ContactState {
    ContactState::new(p_mpa * 1e6, v_m_min / 60.0)
}

#[test]
fn learned_law_maps_units_and_domain() {
    let m = fitted_model(Family::Svr);
    let law = LearnedLaw::new(m.clone(), Some(&PinContact::default())).unwrap();
    let x = [1500.0, 100.0];
    assert_eq!(
        law.mu(&st(1500.0, 100.0)),
        greybox_model::Predictor::predict_one(&m.model, &x)
    );
    let d = law.domain().unwrap();
    assert!((d.pressure_pa.min - 900e6).abs() < 1.0 && (d.pressure_pa.max - 2220e6).abs() < 1.0);
    assert!((d.sliding_velocity_m_s.max - 240.0 / 60.0).abs() < 1e-12);
}

#[test]
fn grey_box_is_continuous_and_never_extrapolates_trees() {
    let m = fitted_model(Family::GradientBoosting);
    let inner = LearnedLaw::new(m, Some(&PinContact::default())).unwrap();
    let outside = PowerLaw::fit_to(&inner, 20).unwrap();
    let gb = GreyBoxLaw::new(Box::new(inner.clone()), Box::new(outside), 0.1, None, None).unwrap();
    // inside: exactly the learned law
    assert_eq!(gb.mu(&st(1500.0, 100.0)), inner.mu(&st(1500.0, 100.0)));
    // far outside: exactly the physics law
    let far = st(5000.0, 100.0);
    assert_eq!(gb.mu(&far), outside.mu(&far));
    // continuous across the band: small steps give small changes
    let mut prev = gb.mu(&st(2200.0, 100.0));
    for k in 1..=400 {
        let p = 2200.0 + k as f64 * 1.0;
        let mu = gb.mu(&st(p, 100.0));
        assert!((mu - prev).abs() < 2e-3, "jump at {p} MPa: {prev} -> {mu}");
        prev = mu;
    }
    // Zorev cap and clamp
    let capped = GreyBoxLaw::new(
        Box::new(inner),
        Box::new(outside),
        0.1,
        Some(300e6),
        Some((0.05, 0.25)),
    )
    .unwrap();
    let s = st(2000.0, 100.0);
    assert!(capped.mu(&s) * s.pressure_pa <= 300e6 * (1.0 + 1e-12));
    assert!(capped.mu(&st(900.0, 20.0)) <= 0.25);
}

#[test]
fn surrogate_table_within_1e4_of_its_source() {
    let m = fitted_model(Family::Svr);
    let law = LearnedLaw::new(m, Some(&PinContact::default())).unwrap();
    let mut t = TabulatedLaw::bake(
        &law,
        Axis::new(900e6, 2220e6, 121).unwrap(),
        Axis::new(20.0 / 60.0, 4.0, 101).unwrap(),
        None,
    );
    let dev = t.check(&law, 100_000, 7);
    eprintln!("surrogate max deviation {dev:e}");
    assert!(dev <= 1e-4, "{dev}");
    // exact at grid nodes
    assert_eq!(
        t.mu(&ContactState::new(t.pressure.value(3), t.velocity.value(5))),
        t.values[5 * 121 + 3]
    );
}

#[test]
fn abaqus_table_round_trip() {
    let m = fitted_model(Family::Svr);
    let law = LearnedLaw::new(m, Some(&PinContact::default())).unwrap();
    let grid = Grid {
        pressure_pa: vec![1000e6, 1500e6, 2000e6],
        velocity_m_s: vec![0.5, 1.0, 2.0, 4.0],
        temperature_k: Some(vec![293.15, 873.15]),
    };
    let u = Units {
        pressure: PressureUnit::MPa,
        speed: VelocityUnit::MmPerS,
        temperature: TemperatureUnit::C,
    };
    let text = abaqus(&law, &grid, u, Some(450e6)).unwrap();
    assert!(text.contains("*FRICTION, TAUMAX=450.0") && text.contains("Abaqus has no unit system"));
    let rows = parse_abaqus_friction(&text, "t.inp").unwrap();
    assert_eq!(rows.len(), 3 * 4 * 2);
    // first variable (slip rate) fastest, ascending; μ reproduced at every grid point
    assert_eq!((rows[0][1], rows[1][1], rows[4][1]), (500.0, 1000.0, 500.0));
    for r in &rows {
        let s = ContactState {
            pressure_pa: r[2] * 1e6,
            sliding_velocity_m_s: r[1] / 1e3,
            temperature_k: r[3] + 273.15,
        };
        assert_eq!(r[0], law.mu(&s));
    }
}

#[test]
fn law_files() {
    let dir = tempfile::tempdir().unwrap();
    let m = fitted_model(Family::Svr);
    m.save(&dir.path().join("m.json")).unwrap();
    std::fs::write(
        dir.path().join("law.json"),
        r#"{"law": "grey-box", "inner": {"law": "learned", "model": "m.json"}, "outside": {"law": "power-fit"}, "shear_cap_k_MPa": 500}"#,
    )
    .unwrap();
    let law = load_law(&dir.path().join("law.json")).unwrap();
    assert!(law.name().starts_with("grey-box"));
    let direct = load_law(&dir.path().join("m.json")).unwrap();
    assert_eq!(law.mu(&st(1000.0, 100.0)), direct.mu(&st(1000.0, 100.0)));
    // the 500 MPa shear cap binds at 1500 MPa: μ = 500/1500
    assert!((law.mu(&st(1500.0, 100.0)) - 1.0 / 3.0).abs() < 1e-15);
    std::fs::write(
        dir.path().join("bad.json"),
        r#"{"law": "zorev", "mu": 0.3}"#,
    )
    .unwrap();
    let e = load_law(&dir.path().join("bad.json"))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("invalid law file") && e.contains("k_MPa"), "{e}");
    let e = load_law(&dir.path().join("missing.json"))
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("missing.json"), "{e}");
}

/// One read of a law file serves both its inputs and the law: a model file is its own only
/// input (tables: `tables.rs`), a law file adds the files it names; the law built from the
/// read file is the one `load_law` gives.
#[test]
fn a_law_file_read_once_names_its_inputs_and_builds_the_law() {
    use greybox_friction::spec::LawFile;
    let dir = tempfile::tempdir().unwrap();
    let model = dir.path().join("m.json");
    fitted_model(Family::Svr).save(&model).unwrap();
    let law_path = dir.path().join("law.json");
    std::fs::write(
        &law_path,
        r#"{"law": "grey-box", "inner": {"law": "learned", "model": "m.json"}, "outside": {"law": "coulomb", "mu": 0.4}}"#,
    )
    .unwrap();
    let at = st(1200.0, 150.0);
    for (path, inputs) in [
        (&model, vec![model.clone()]),
        (&law_path, vec![law_path.clone(), model.clone()]),
    ] {
        let file = LawFile::read(path).unwrap();
        assert_eq!(file.inputs(), inputs, "{}", path.display());
        let mu = file.build().unwrap().mu(&at);
        assert_eq!(mu.to_bits(), load_law(path).unwrap().mu(&at).to_bits());
        assert!(mu.is_finite() && mu > 0.0, "{mu}");
    }
}

/// A model trained on a normal force: without a recorded or stated contact it is refused
/// (never the textbook-max default); with its recorded map it needs none.
#[test]
fn force_feature_models_need_their_datasets_contact() {
    use greybox_core::dataset::PressureConvention;
    use greybox_model::modelfile::ForcePressure;
    let mut m = fitted_model(Family::GradientBoosting);
    m.features[0] = greybox_model::column::Column::new("normal_force_N");
    let e = LearnedLaw::new(m.clone(), None).unwrap_err().to_string();
    assert!(
        e.contains("does not record") && e.contains("contact"),
        "{e}"
    );
    let eq7 = PinContact {
        convention: PressureConvention::ArticleEq7,
        ..PinContact::default()
    };
    let c = eq7.pressure_pa(1.0).unwrap();
    m.force_to_pressure = Some(ForcePressure {
        pressure_convention: PressureConvention::ArticleEq7,
        pressure_pa_at_1_n: c,
    });
    let bare = LearnedLaw::new(m.clone(), None).unwrap();
    let stated = LearnedLaw::new(m.clone(), Some(&eq7)).unwrap();
    let s = st(1200.0, 100.0);
    assert_eq!(bare.mu(&s), stated.mu(&s));
    // the textbook maximum is 4^(1/3) ≈ 1.59 × the article's value: a different force, refused
    let e = LearnedLaw::new(m, Some(&PinContact::default()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("article-eq7"), "{e}");
}

/// A shear cap ≤ 0 used to be accepted and gave μ = 0.05 everywhere.
#[test]
fn a_non_positive_shear_cap_is_refused() {
    let d = tempfile::tempdir().unwrap();
    for k in ["0", "-600"] {
        let p = d.path().join("law.json");
        std::fs::write(
            &p,
            format!(r#"{{"law": "grey-box", "inner": {{"law": "coulomb", "mu": 0.4}}, "outside": {{"law": "coulomb", "mu": 0.4}}, "shear_cap_k_MPa": {k}}}"#),
        )
        .unwrap();
        let e = load_law(&p).err().expect("refused").to_string();
        assert!(e.contains("shear_cap_k_MPa must be > 0"), "{e}");
    }
}

/// A cap typed in GPa where MPa is meant (0.6 or 1 for 600 MPa) gave μ = 0.05 everywhere.
#[test]
fn a_shear_cap_in_gpa_is_refused_with_the_number() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().join("law.json");
    for k in ["0.6", "1", "49.9"] {
        std::fs::write(
            &p,
            format!(r#"{{"law": "grey-box", "inner": {{"law": "coulomb", "mu": 0.4}}, "outside": {{"law": "coulomb", "mu": 0.4}}, "shear_cap_k_MPa": {k}}}"#),
        )
        .unwrap();
        let e = load_law(&p).err().expect("refused").to_string();
        assert!(
            e.contains(&format!("shear_cap_k_MPa is {k} MPa")) && e.contains("GPa"),
            "{e}"
        );
    }
    std::fs::write(
        &p,
        r#"{"law": "grey-box", "inner": {"law": "coulomb", "mu": 0.4}, "outside": {"law": "coulomb", "mu": 0.4}, "shear_cap_k_MPa": 50}"#,
    )
    .unwrap();
    if let Err(e) = load_law(&p) {
        assert!(
            !e.to_string().contains("shear_cap"),
            "50 MPa is accepted: {e}"
        );
    }
}

// ---- physics as data (issue 46 item 4): laws outside the physics table are refused with
// the number and the likely unit mistake.

fn law_error(json: &str) -> String {
    let d = greybox_testkit::law::law_dir(json);
    load_law(&d.path().join("law.json"))
        .err()
        .expect("refused")
        .to_string()
}

#[test]
fn a_law_with_mu_1e300_is_refused() {
    let e = law_error(r#"{"law": "coulomb", "mu": 1e300}"#);
    assert!(
        e.contains("mu: μ 1e300 is outside the possible range 0..3"),
        "{e}"
    );
    let e = law_error(r#"{"law": "zorev", "mu": 30, "k_MPa": 500}"#);
    assert!(
        e.contains("μ 30 is outside") && e.contains("in % read as a fraction"),
        "{e}"
    );
}

#[test]
fn a_clamp_of_50_to_100_is_refused() {
    let e = law_error(
        r#"{"law": "grey-box", "inner": {"law": "coulomb", "mu": 0.4}, "outside": {"law": "coulomb", "mu": 0.4}, "clamp": [50, 100]}"#,
    );
    assert!(
        e.contains("clamp[0]: μ 50 is outside the possible range 0..3")
            && e.contains("clamp[1]: μ 100 is outside")
            && e.contains("in % read as a fraction (÷100 → 0.5)"),
        "{e}"
    );
}

#[test]
fn a_shear_factor_of_5_is_refused() {
    let e = law_error(r#"{"law": "shear-factor", "m": 5, "k_MPa": 500}"#);
    assert!(
        e.contains("m: shear factor m 5 is outside the possible range 0..1"),
        "{e}"
    );
    let e = law_error(r#"{"law": "shear-factor", "m": 80, "k_MPa": 500}"#);
    assert!(
        e.contains("a share in % read as a fraction (÷100 → 0.8)"),
        "{e}"
    );
    let e = law_error(r#"{"law": "usui-childs", "mu": 0.5, "m": 1.5, "n": 1, "k_MPa": 500}"#);
    assert!(e.contains("m: shear factor m 1.5"), "{e}");
    // a shear flow stress in Pa where MPa is asked
    let e = law_error(r#"{"law": "zorev", "mu": 0.3, "k_MPa": 5e8}"#);
    assert!(
        e.contains("k_MPa: shear flow stress 5e14 Pa") && e.contains("MPa is asked"),
        "{e}"
    );
}

/// A model trained on μ in % (or predicting 1000) is refused when a law is built from it.
#[test]
fn a_model_of_a_target_in_percent_or_of_1000_is_refused() {
    let e = LearnedLaw::new(fitted_model_scaled(Family::GradientBoosting, 100.0), None)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("the model's prediction at p = ")
            && e.contains("is outside the possible range 0..3")
            && e.contains("a model's target) in % read as a fraction"),
        "{e}"
    );
    let e = LearnedLaw::new(fitted_model_scaled(Family::GradientBoosting, 2500.0), None)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("the model's prediction at p = ")
            && e.contains("is outside the possible range 0..3"),
        "{e}"
    );
}

/// Engine tables: μ beyond 3 refused, beyond the usual 1 written with a line in the header.
#[test]
fn engine_tables_bound_mu() {
    use greybox_friction::classical::{Coulomb, ShearFactor};
    use greybox_friction::export::{abaqus_checked, TableOptions};
    let grid = Grid {
        pressure_pa: vec![500e6, 1000e6],
        velocity_m_s: vec![1.0, 2.0],
        temperature_k: None,
    };
    let u = Units {
        pressure: PressureUnit::MPa,
        speed: VelocityUnit::MmPerS,
        temperature: TemperatureUnit::C,
    };
    let o = TableOptions::default();
    // a law object built without its law file (no parameter check): the table refuses it
    let e = abaqus_checked(&Coulomb { mu: 40.0 }, &grid, u, None, &o)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("the law at p = 500000000 Pa") || e.contains("the law at p = 5e8 Pa"),
        "{e}"
    );
    assert!(e.contains("μ 40 is outside the possible range 0..3"), "{e}");
    let e = abaqus_checked(&Coulomb { mu: 1.5 }, &grid, u, None, &o).unwrap();
    assert!(
        e.text.contains("** unusual: the law at p = ")
            && e.text.contains("μ 1.5 is outside the usual range 0.005..1")
            && e.text.contains("(and 3 more nodes)"),
        "{}",
        e.text
    );
    // a shear-factor law's μ = m k / p stays in range at these pressures
    let ok = abaqus_checked(
        &ShearFactor {
            m: 0.8,
            k_pa: 500e6,
        },
        &grid,
        u,
        None,
        &o,
    )
    .unwrap();
    assert!(!ok.text.contains("unusual"), "{}", ok.text);
}
