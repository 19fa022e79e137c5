//! Each stage of the pipeline through its library call, on tiny inputs, against an
//! expectation found independently of the code under test: a textbook formula worked by
//! hand, a property that must hold, or the virtual rig's ground truth. (The command line's
//! tests, crates/greybox-cli/tests, run the same stages through the binary.)

use greybox_contact::ploughing::TrackWidth;
use greybox_core::dataset::PressureConvention;
use greybox_core::units::{M_PER_MM, PA_PER_GPA, PA_PER_MPA};
use greybox_core::ContactState;
use greybox_friction::export::engine::ExportFormat;
use greybox_learn::protocol::{FitConfig, Repeats, Resamples};
use greybox_model::modelfile::{DomainPolicy, ModelFile};
use greybox_model::Family;
use greybox_pipeline::adhesive::{adhesive, AdhesiveOptions};
use greybox_pipeline::characterize::{
    characterize, CharacterizeOptions, Harmonics, ImpactChannels,
};
use greybox_pipeline::export::{export, ExportOptions};
use greybox_pipeline::fit::{fit, FitOptions, FitResult};
use greybox_pipeline::hertz::{hertz, Geometry, HertzOptions};
use greybox_pipeline::identify::{identify_campaign, IdentifyOptions};
use greybox_pipeline::law::{grey_box_law, write_law, GreyBoxOptions};
use greybox_pipeline::material::fit_flow_curves;
use greybox_pipeline::plan::plan;
use greybox_pipeline::predict::predict_points;
use greybox_pipeline::simulate::{run_pin, RunOutput};
use greybox_pipeline::study::DEMO_STUDY;
use greybox_pipeline::synth::synth;
use greybox_pipeline::wear::{wear_rate, WearInput, WearVolume};
use greybox_pipeline::windows::windows;
use greybox_pipeline::Study;
use greybox_recording::readers::RecordingFormat;
use greybox_testkit::dataset::{write_dataset, write_rows, Row};
use greybox_testkit::law::{law_dir, ZOREV};
use greybox_testkit::mesh::unit_square_abaqus;
use greybox_tribo::plan::{PinCount, VelocityCount};
use std::collections::HashMap;
use std::f64::consts::PI;
use std::path::Path;
use std::sync::OnceLock;

/// The bundled example study cut down to `loads` × `velocities` steps.
fn small_study(loads: u64, velocities: u64) -> Study {
    let mut study = Study::parse(DEMO_STUDY, "demo").unwrap();
    study.plan.normal_force_count = PinCount::of(loads);
    study.plan.velocity_count = VelocityCount::of(velocities);
    study
}

/// A column of a CSV file by name, as numbers.
fn column(path: &Path, name: &str) -> Vec<f64> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let i = r.headers().unwrap().iter().position(|h| h == name).unwrap();
    r.records()
        .map(|x| x.unwrap()[i].parse().unwrap())
        .collect()
}

#[test]
fn plan_turns_velocities_into_spindle_speeds_on_the_track() {
    let d = tempfile::tempdir().unwrap();
    let mut study = Study::default();
    study.plan.track_radius_mm = Some(80.0);
    study.plan.normal_force_count = PinCount::of(3);
    study.plan.velocity_count = VelocityCount::of(4);
    let out = d.path().join("plan");
    let s = plan(&study, &out, false, &[]).unwrap();
    assert_eq!((s.pins, s.steps), (3, 12));
    assert_eq!(s.normal_forces_n.len(), 3);
    let (f_min, f_max) = (study.plan.normal_force_min_n, study.plan.normal_force_max_n);
    assert_eq!(s.normal_forces_n[0], f_min);
    assert_eq!(s.normal_forces_n[2], f_max);
    // the plan holds m/s: m/min back within rounding
    assert!((s.velocity_min_m_per_min / study.plan.velocity_min_m_per_min - 1.0).abs() < 1e-12);
    assert!((s.velocity_max_m_per_min / study.plan.velocity_max_m_per_min - 1.0).abs() < 1e-12);
    // n = v / (2π R), rpm (the NC programs hold 0.01 rpm)
    let rpm = |v_m_per_min: f64| v_m_per_min / (2.0 * PI * 80.0 * M_PER_MM);
    assert!((s.spindle_rpm_min - rpm(s.velocity_min_m_per_min)).abs() <= 0.005);
    assert!((s.spindle_rpm_max - rpm(s.velocity_max_m_per_min)).abs() <= 0.005);
    // one NC program per pin beside the run sheet and the resolved study
    for f in ["study.toml", "run_sheet.csv", "nc/pin01.nc", "nc/pin03.nc"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    assert!(!out.join("nc/pin04.nc").exists());
    assert_eq!(s.files.len(), 2 + 3);
}

#[test]
fn synth_then_identify_recovers_the_virtual_rigs_ground_truth() {
    let d = tempfile::tempdir().unwrap();
    let study = small_study(2, 3);
    let rec = d.path().join("recordings");
    let s = synth(&study, &[RecordingFormat::Csv], &rec, false, &[]).unwrap();
    assert_eq!((s.pins, s.seed), (2, study.synth.seed));
    assert_eq!(s.files.len(), 2 + 1, "two recordings and the ground truth");
    let truth_csv = rec.join("ground_truth.csv");
    let truth_mu = column(&truth_csv, "cof_true");
    assert_eq!(truth_mu.len(), 6);
    assert!(truth_mu
        .iter()
        .all(|m| (s.cof_true_min..=s.cof_true_max).contains(m)));

    let o = IdentifyOptions::new(vec![rec.clone()], d.path().join("dataset.csv"))
        .with_plan(study.plan.build().unwrap());
    let r = identify_campaign(&study, &o, None).unwrap();
    assert_eq!(r.dataset.records.len(), 6);
    assert_eq!(r.summary.plateaus, 6);
    // every identified μ against the truth of its (pin, step), read here from the CSV
    let pins = column(&truth_csv, "pin");
    let steps = column(&truth_csv, "step");
    let truth: HashMap<(u32, u32), f64> = (0..truth_mu.len())
        .map(|k| ((pins[k] as u32, steps[k] as u32), truth_mu[k]))
        .collect();
    for row in &r.dataset.records {
        let t = truth[&(row.pin, row.step)];
        assert!(
            (row.cof_apparent - t).abs() < 0.01,
            "pin {} step {}: identified {} against {t}",
            row.pin,
            row.step,
            row.cof_apparent
        );
        assert!(row.stationary);
    }
    assert!(d.path().join("dataset.csv").is_file());
}

/// Bowden–Tabor for a sphere of radius r in a track of width w, by hand:
/// μ_p = (2/π) [ (2r/w)² asin(w/2r) − √((2r/w)² − 1) ].
fn bowden_tabor(r: f64, w: f64) -> f64 {
    let q = 2.0 * r / w;
    2.0 / PI * (q * q * (w / (2.0 * r)).asin() - (q * q - 1.0).sqrt())
}

#[test]
fn the_analytic_correction_subtracts_the_bowden_tabor_ploughing_term() {
    let d = tempfile::tempdir().unwrap();
    let data = d.path().join("ds.csv");
    write_dataset(&data, &[(1000.0, 0.32), (1500.0, 0.30), (2000.0, 0.31)]);
    let mut o = AdhesiveOptions::analytic(data, d.path().join("adh.csv"));
    o.pin_radius_mm = 17.0;
    // two measured widths: the power law w = a F^b goes through both
    o.track_widths = vec![
        TrackWidth {
            normal_force_n: 1000.0,
            width_um: 1400.0,
        },
        TrackWidth {
            normal_force_n: 2000.0,
            width_um: 1900.0,
        },
    ];
    let (ds, correction) = adhesive(&o).unwrap();
    let b = (1900.0f64 / 1400.0).ln() / 2.0f64.ln();
    let width_um = |f: f64| 1400.0 * (f / 1000.0).powf(b);
    for row in &ds.records {
        let w = width_um(row.normal_force_n) * 1e-6;
        let expected = row.cof_apparent - bowden_tabor(17e-3, w);
        let got = row.cof_adhesive.unwrap();
        assert!((got - expected).abs() < 1e-9, "{got} against {expected}");
        assert!(got < row.cof_apparent);
    }
    assert_eq!(correction.per_load.len(), 3);
    assert!(o.out.is_file());
}

/// A smooth μ(p, v) on a 6 × 6 grid of 900–2150 MPa and 20–220 m/min.
fn smooth_mu(p_mpa: f64, v_m_per_min: f64) -> f64 {
    0.5 - 0.1 * (p_mpa - 900.0) / 1300.0 - 0.1 * (v_m_per_min / 250.0).sqrt()
}

/// One fit (SVR, one candidate, no nested CV) of [`smooth_mu`] against pressure and
/// velocity, shared by the fit, law and predict tests; its directory lives as long as the
/// test binary.
fn fitted() -> &'static (tempfile::TempDir, FitResult) {
    static FIT: OnceLock<(tempfile::TempDir, FitResult)> = OnceLock::new();
    FIT.get_or_init(|| {
        let d = tempfile::tempdir().unwrap();
        let mut rows = Vec::new();
        for i in 0..6 {
            for j in 0..6 {
                let (p, v) = (900.0 + 250.0 * i as f64, 20.0 + 40.0 * j as f64);
                rows.push(Row {
                    normal_force_n: 1000.0,
                    velocity_m_per_min: v,
                    pressure_mpa: p,
                    cof_apparent: smooth_mu(p, v),
                });
            }
        }
        let data = d.path().join("data.csv");
        write_rows(&data, &rows);
        let mut config = FitConfig {
            families: vec![Family::Svr],
            skip_nested: true,
            bootstrap_resamples: Resamples::of(10),
            importance_repeats: Repeats::of(1),
            ..FitConfig::default()
        };
        config.grid.svr.kernel = vec![greybox_model::svr::Kernel::Rbf];
        config.grid.svr.c = vec![10.0];
        config.grid.svr.epsilon = vec![0.001];
        let mut o = FitOptions::article(data, "cof_apparent", d.path().join("fit"));
        o.features = vec![
            "hertz_pressure_MPa".into(),
            "sliding_velocity_m_per_min".into(),
        ];
        o.config = config;
        let r = fit(&o).unwrap();
        (d, r)
    })
}

#[test]
fn fit_learns_a_smooth_mu_and_writes_its_model() {
    let (d, r) = fitted();
    assert_eq!(r.report.families.len(), 1);
    let svr = &r.report.families[0];
    assert_eq!(svr.family, Family::Svr);
    assert!(svr.held_out.is_none(), "nested CV was skipped");
    assert!(svr.training.r2.value > 0.95, "{}", svr.training.r2.value);
    let model = d.path().join("fit/models/svr.json");
    assert!(r.outputs.models.iter().any(|m| Path::new(m) == model));
    assert!(d.path().join("fit/report.json").is_file());
}

#[test]
fn predict_evaluates_the_model_and_flags_points_outside_its_domain() {
    let (d, _) = fitted();
    let model = ModelFile::load(&d.path().join("fit/models/svr.json")).unwrap();
    let at = vec![vec![1400.0, 100.0], vec![5000.0, 100.0]];
    let p = predict_points(&model, at, DomainPolicy::Warn, 0.05).unwrap();
    let inside = &p[0].prediction;
    assert!(
        (inside.value - smooth_mu(1400.0, 100.0)).abs() < 0.02,
        "{inside:?}"
    );
    assert!(inside.in_domain && inside.low <= inside.value && inside.value <= inside.high);
    assert!(!p[1].prediction.in_domain);
    assert!(predict_points(
        &model,
        vec![vec![5000.0, 100.0]],
        DomainPolicy::Refuse,
        0.05
    )
    .is_err());
    assert!(predict_points(&model, vec![vec![1400.0]], DomainPolicy::Warn, 0.05).is_err());
}

#[test]
fn the_grey_box_law_keeps_the_model_inside_and_zorevs_cap_above_it() {
    let (d, _) = fitted();
    let law_path = d.path().join("law.json");
    let cap_mpa = 600.0;
    let law = grey_box_law(
        "fit/models/svr.json".into(),
        None,
        &GreyBoxOptions {
            shear_cap_k_mpa: Some(cap_mpa),
            ..GreyBoxOptions::default()
        },
    );
    write_law(&law_path, &law).unwrap();
    let law = greybox_friction::spec::load_law(&law_path).unwrap();
    let model = ModelFile::load(&d.path().join("fit/models/svr.json")).unwrap();
    let state = |p_mpa: f64, v: f64| ContactState::new(p_mpa * PA_PER_MPA, v / 60.0);
    // inside the training domain, away from its edges: the model itself (τ below the cap)
    let x = [1400.0, 100.0];
    let expected = model.predict(&x, DomainPolicy::Warn, 0.0).unwrap().value;
    assert!((law.mu(&state(x[0], x[1])) - expected).abs() < 1e-12);
    // τ = μ p never exceeds k; far above the domain the cap binds: μ = k / p
    for p in [500.0, 1400.0, 2500.0, 4000.0, 8000.0] {
        for v in [10.0, 100.0, 400.0] {
            let mu = law.mu(&state(p, v));
            assert!((0.05..=1.0).contains(&mu), "μ({p}, {v}) = {mu}");
            assert!(
                mu * p <= cap_mpa * (1.0 + 1e-12),
                "τ({p}, {v}) = {}",
                mu * p
            );
        }
    }
    assert!((law.mu(&state(8000.0, 100.0)) - cap_mpa / 8000.0).abs() < 1e-12);
}

#[test]
fn export_writes_zorevs_law_on_the_asked_grid() {
    let d = law_dir(ZOREV);
    let out = d.path().join("table.csv");
    let o = ExportOptions::new(d.path().join("law.json"), ExportFormat::Csv, out.clone())
        .with_grid(greybox_friction::export::Grid {
            pressure_pa: [250.0, 500.0, 1000.0, 2000.0]
                .map(|p| p * PA_PER_MPA)
                .to_vec(),
            velocity_m_s: vec![1.0, 2.0],
            temperature_k: None,
        })
        .unwrap();
    let r = export(&o).unwrap();
    assert_eq!(r.shape.iter().product::<usize>(), 8);
    assert_eq!(r.bytes as u64, std::fs::metadata(&out).unwrap().len());
    let p = column(&out, "pressure_MPa");
    let mu = column(&out, "mu");
    assert_eq!(p.len(), 8);
    // Zorev: τ = min(μ p, k), so μ = min(0.4, 500 MPa / p)
    for (p, mu) in p.iter().zip(&mu) {
        assert!((mu - (500.0 / p).min(0.4)).abs() < 1e-9, "μ({p}) = {mu}");
    }
    assert!(Path::new(&format!("{}.provenance.json", out.display())).is_file());
}

#[test]
fn hertz_matches_the_textbook_for_a_sphere_and_a_cylinder() {
    let o = |geometry, convention| HertzOptions {
        geometry,
        radius_mm: 5.0,
        e1_gpa: 210.0,
        nu1: 0.3,
        e2_gpa: 210.0,
        nu2: 0.3,
        convention,
    };
    // E* = 1 / ((1 − ν₁²)/E₁ + (1 − ν₂²)/E₂) (Johnson, Contact Mechanics, §4.2)
    let e = 1.0 / (2.0 * (1.0 - 0.09) / (210.0 * PA_PER_GPA));
    let (r, f) = (5.0 * M_PER_MM, 200.0);

    let (e_star, rows) =
        hertz(&o(Geometry::Sphere, PressureConvention::TextbookMean), &[f]).unwrap();
    assert!((e_star / e - 1.0).abs() < 1e-12);
    // a = (3FR / 4E*)^⅓, p̄ = F / (π a²), p₀ = 3/2 p̄, δ = a² / R
    let a = (3.0 * f * r / (4.0 * e)).cbrt();
    let mean = f / (PI * a * a);
    let row = &rows[0];
    assert!((row.contact_half_width_mm * M_PER_MM / a - 1.0).abs() < 1e-9);
    assert!((row.mean_pressure_mpa * PA_PER_MPA / mean - 1.0).abs() < 1e-9);
    assert!((row.max_pressure_mpa * PA_PER_MPA / (1.5 * mean) - 1.0).abs() < 1e-9);
    assert!((row.approach_um.unwrap() * 1e-6 / (a * a / r) - 1.0).abs() < 1e-9);
    assert_eq!(row.convention_pressure_mpa, row.mean_pressure_mpa);

    let length = 10.0 * M_PER_MM;
    let (_, rows) = hertz(
        &o(
            Geometry::Cylinder { length_mm: 10.0 },
            PressureConvention::TextbookMax,
        ),
        &[f],
    )
    .unwrap();
    // line contact: b = √(4 F R / (π L E*)), p₀ = 2F / (π b L), p̄ = π/4 p₀
    let b = (4.0 * f * r / (PI * length * e)).sqrt();
    let p0 = 2.0 * f / (PI * b * length);
    let row = &rows[0];
    assert!((row.contact_half_width_mm * M_PER_MM / b - 1.0).abs() < 1e-9);
    assert!((row.max_pressure_mpa * PA_PER_MPA / p0 - 1.0).abs() < 1e-9);
    assert!((row.mean_pressure_mpa / row.max_pressure_mpa - PI / 4.0).abs() < 1e-9);
    assert_eq!(row.convention_pressure_mpa, row.max_pressure_mpa);
}

#[test]
fn wear_of_a_scar_is_the_spherical_caps_volume_over_load_and_distance() {
    let (r_mm, d_mm) = (17.0, 2.0);
    let w = wear_rate(&WearInput {
        normal_force_n: 500.0,
        velocity_m_per_min: 120.0,
        duration_s: 60.0,
        volume: WearVolume::ScarDiameter(d_mm),
        pin_radius_mm: r_mm,
        hardness_gpa: Some(2.0),
    })
    .unwrap();
    // the cap cut off by a flat scar: h = R − √(R² − (d/2)²), V = π h² (3R − h) / 3
    let h = r_mm - (r_mm * r_mm - d_mm * d_mm / 4.0f64).sqrt();
    let volume = PI * h * h * (3.0 * r_mm - h) / 3.0;
    let s = 120.0 / 60.0 * 60.0;
    assert!((w.sliding_distance_m - s).abs() < 1e-12);
    assert!((w.volume_mm3 / volume - 1.0).abs() < 1e-12);
    // Archard: k = V / (F s), mm³/(N m)
    assert!((w.k_mm3_per_nm / (volume / (500.0 * s)) - 1.0).abs() < 1e-12);
    assert!(w.k_dimensionless.unwrap() > 0.0);
}

#[test]
fn material_recovers_the_johnson_cook_parameters_of_noiseless_curves() {
    let d = tempfile::tempdir().unwrap();
    let truth = greybox_material::JohnsonCook {
        room_temperature_k: 298.15,
        ..greybox_material::JohnsonCook::aisi1045_article()
    };
    let temps: Vec<f64> = (0..5).map(|k| 25.0 + 200.0 * k as f64).collect();
    let pts = greybox_material::fit::synthetic_flow_curves(&truth, &temps, 4e-3, 0.0, 1, &|_| 1.0);
    let curves = d.path().join("curves.csv");
    greybox_material::fit::write_flow_curves(&curves, &pts).unwrap();
    let out = d.path().join("jc.json");
    let fitted = fit_flow_curves(
        &curves,
        &greybox_material::fit::FitOptions {
            c: truth.c,
            ref_strain_rate: Some(4e-3),
            room_temperature_k: Some(298.15),
            melt_temperature_k: truth.melt_temperature_k,
            misfit_threshold: 0.05,
        },
        Some(&out),
    )
    .unwrap();
    let p = fitted.params;
    for (name, got, want) in [
        ("A", p.a_pa, truth.a_pa),
        ("B", p.b_pa, truth.b_pa),
        ("n", p.n, truth.n),
        ("m", p.m, truth.m),
    ] {
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "{name}: {got} against {want}"
        );
    }
    assert!(fitted.relative_rms < 1e-3, "{}", fitted.relative_rms);
    assert!(out.is_file());
}

#[test]
fn windows_of_a_one_quad_coating_cover_its_perimeter() {
    let d = tempfile::tempdir().unwrap();
    let mesh = d.path().join("tool.inp");
    std::fs::write(&mesh, unit_square_abaqus("")).unwrap();
    let out = d.path().join("windows");
    let options = greybox_couple::windows::WindowOptions {
        outward: 0.02,
        inward: 0.005,
        segment_length: None,
    };
    let (_, w) = windows(&mesh, "COATING", options, 0.3, (2, 1), &out, false).unwrap();
    // one window per boundary segment of the unit square: four, 4 long in all
    assert_eq!(w.len(), 4);
    let total: f64 = w.iter().map(|x| x.length).sum();
    assert!((total - 4.0).abs() < 1e-12, "{total}");
    for f in [
        "windows.json",
        "windows.csv",
        "windows.vtk",
        "windows_frcwin.key",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
}

#[test]
fn characterize_finds_the_virtual_rigs_natural_frequency() {
    let d = tempfile::tempdir().unwrap();
    let f_hz = 300.0;
    let rec = greybox_tribo::frf_synth::Chain::sdof(2.0, f_hz, 0.02).record(
        20_000.0,
        1.2,
        &[150.0; 4],
        0.5e-3,
        0.0,
        1,
    );
    let csv = d.path().join("hammer.csv");
    greybox_testkit::hammer::write_hammer_csv(&csv, &rec);
    let report = characterize(&CharacterizeOptions {
        recordings: vec![(csv, Some(500.0))],
        channels: ImpactChannels {
            response: "response_m".into(),
            ..ImpactChannels::default()
        },
        impact: greybox_tribo::frf::ImpactConfig::default(),
        harmonics: Harmonics::of(3),
        plan: None,
        study: None,
        out: d.path().join("characterize"),
        force: false,
    })
    .unwrap();
    assert_eq!(report.loads.len(), 1);
    let load = &report.loads[0];
    assert_eq!(load.load_n, Some(500.0));
    assert!(
        (1..=4).contains(&load.impacts_used),
        "{}",
        load.impacts_used
    );
    // the peak of an SDOF's receptance lies at f √(1 − 2ζ²), 0.04 % below f for ζ = 0.02,
    // and its half-power width gives ζ back
    let first = &load.resonances[0];
    assert!(
        (first.frequency_hz - f_hz).abs() <= 1.0,
        "{} Hz",
        first.frequency_hz
    );
    assert!(
        (first.damping - 0.02).abs() <= 0.05 * 0.02,
        "ζ {}",
        first.damping
    );
    assert!(report.excitation_check.is_none());
}

/// A 1 mm pin 20 µm deep, sliding 0.2 mm with μ = 0.2 on a 0.12 mm high workpiece (the
/// command line's pin test): about a second with the test profile.
#[test]
fn a_pin_slide_ploughs_on_top_of_the_adhesive_mu() {
    let d = tempfile::tempdir().unwrap();
    let setup: greybox_pipeline::settings::pin::PinSettings = greybox_pipeline::settings::from_json(
        "pin",
        r#"{"pin_radius_mm": 1, "depth_um": 20, "slide_mm": 0.2, "height_mm": 0.12, "mu": 0.2}"#,
    )
    .unwrap();
    let setup = setup.setup().unwrap();
    let out = d.path().join("pin");
    let r = run_pin(&setup, &RunOutput::to(&out)).unwrap();
    // ploughing only adds: F_t/F_N = μ + a deformation share > 0
    assert!(r.force_ratio > setup.mu, "{}", r.force_ratio);
    assert!((r.deformation_share - (r.force_ratio - setup.mu)).abs() < 1e-12);
    assert!(r.normal_force_n_per_mm > 0.0);
    for f in ["forces.csv", "summary.json"] {
        assert!(out.join(f).is_file(), "{f}");
    }
}
