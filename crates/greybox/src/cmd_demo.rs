//! `greybox demo`: the whole pipeline on the bundled example study.

use crate::output::{print_json, stage_out_dir};
use crate::study::{Study, DEMO_STUDY};
use crate::{
    cmd_adhesive, cmd_characterize, cmd_export, cmd_fit, cmd_identify, cmd_material, cmd_plan,
    cmd_simulate, cmd_synth,
};
use anyhow::Result;
use greybox_core::atomic::write_string_atomic;
use greybox_friction::spec::LawSpec;
use greybox_tribo::readers::RecordingFormat;
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output directory.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once the demo is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct DemoSummary {
    plan: cmd_plan::PlanSummary,
    synth: cmd_synth::SynthSummary,
    identify: cmd_identify::IdentifySummary,
    correction: greybox_tribo::ploughing::Correction,
    fit: greybox_learn::protocol::FitReport,
    fit_outputs: cmd_fit::FitOutputs,
    law: String,
    dynamics: cmd_characterize::CharacterizeReport,
    wear_tests: Vec<greybox_tribo::wear::WearTest>,
    coupling: Option<greybox_couple::engine::CouplingResult>,
    material: greybox_material::fit::JcFit,
    cutting: cmd_simulate::CutSummary,
}

/// A rotary tribometer's CSV export (written by the independent test rig,
/// `crates/greybox-tribo/tests/support/exports.rs`, seed 1) and its ground truth.
const FOREIGN_EXPORT: &str = include_str!("../../../examples/foreign-rig/rotary-export.csv");
const FOREIGN_TRUTH: &str = include_str!("../../../examples/foreign-rig/rotary-export-truth.csv");
/// The export's wear-track radius per step, mm.
const FOREIGN_RADII_MM: [f64; 5] = [5.0, 6.0, 7.0, 8.0, 9.0];

pub fn run(a: Args) -> Result<()> {
    let study = Study::parse(DEMO_STUDY, "bundled examples/demo-study.toml")?;
    let plan = study.plan.build()?;
    let target = std::path::absolute(&a.out)?;
    let staged = stage_out_dir(&target, a.force, &[])?;
    // Every stage writes with paths relative to the demo's own directory, so that what the
    // outputs record (report sources, provenance inputs, the law's model reference) holds
    // after the swap, wherever the directory is moved.
    let cwd = WorkingDir::enter(staged.path())?;
    let out = Path::new("");
    let plan_files = cmd_plan::write_plan(&study, &plan, &out.join("plan"))?;
    let plan_summary = cmd_plan::summarize(&plan, plan_files);
    let rec_dir = out.join("recordings");
    let synth = cmd_synth::synthesize(
        &study,
        &plan,
        &rec_dir,
        &[RecordingFormat::Csv, RecordingFormat::Tdms],
    )?;
    let dataset = out.join("dataset.csv");
    let files = cmd_identify::recording_files(
        std::slice::from_ref(&rec_dir),
        Some(RecordingFormat::Tdms),
        Some(plan.pins.len()),
    )?;
    let expect = cmd_identify::Expectation::Plan(plan.clone());
    let (ds, id) = cmd_identify::identify(
        &study,
        &expect,
        &files,
        &[],
        &cmd_identify::IdentifyOutput {
            dataset: &dataset,
            inspect_dir: None,
            quiet: true,
            side_inputs: &[],
        },
    )?;
    let truth = cmd_identify::compare_with_truth(&ds, &rec_dir.join("ground_truth.csv"))?;
    let identify = cmd_identify::IdentifySummary {
        dataset: dataset.display().to_string(),
        plateaus: ds.records.len(),
        non_stationary: ds.records.iter().filter(|r| !r.stationary).count(),
        pressure_convention: study.contact.convention.name().into(),
        identification: id,
        truth: Some(truth),
    };
    // a recording from another rig: a rotary tribometer's CSV export (preamble, Step column,
    // time restarting per step, trailing delimiters, footer, rpm on a per-step track radius)
    let foreign_dir = out.join("foreign-rig");
    std::fs::create_dir_all(&foreign_dir)?;
    let foreign_file = foreign_dir.join("rotary-export.csv");
    greybox_core::atomic::write_string_atomic(&foreign_file, FOREIGN_EXPORT)?;
    let foreign_truth = foreign_dir.join("rotary-export-truth.csv");
    greybox_core::atomic::write_string_atomic(&foreign_truth, FOREIGN_TRUTH)?;
    let foreign_study = Study::default();
    let (foreign_ds, foreign_id) = cmd_identify::identify(
        &foreign_study,
        &cmd_identify::Expectation::None,
        std::slice::from_ref(&foreign_file),
        &FOREIGN_RADII_MM,
        &cmd_identify::IdentifyOutput {
            dataset: &foreign_dir.join("dataset.csv"),
            inspect_dir: None,
            quiet: true,
            side_inputs: &[],
        },
    )?;
    let foreign_error = cmd_identify::compare_with_truth(&foreign_ds, &foreign_truth)?;
    // ploughing correction with the article's Table 3 track widths
    let adhesive_args = cmd_adhesive::Args {
        data: dataset.clone(),
        method: cmd_adhesive::Method::Analytic,
        pin_radius_mm: study.contact.pin_tip_radius_mm,
        track_width: Vec::new(),
        track_widths_csv: None,
        out: out.join("dataset_adhesive.csv"),
        json: false,
        sim_loads: 3,
        sim_spacing_um: 10.0,
        sim_slide_mm: 1.5,
        sim_height_mm: 1.0,
        sim_tolerance: 0.002,
        sim_max_runs: 5,
    };
    let (_, correction) = cmd_adhesive::adhesive(&adhesive_args)?;
    // the article's protocol on the adhesive COF
    let mut fit_args = cmd_fit::Args::defaults(adhesive_args.out.clone(), out.join("fit"));
    fit_args.target = "cof_adhesive".into();
    let (fit, fit_outputs) = cmd_fit::fit(&fit_args)?;
    // grey-box law around the family with the best held-out R², exported for Abaqus, plus the C ABI files
    let best = fit
        .families
        .iter()
        .max_by(|a, b| {
            let r = |f: &greybox_learn::protocol::FamilyReport| {
                f.held_out
                    .as_ref()
                    .map(|h| h.metrics.r2.value)
                    .unwrap_or(f64::NEG_INFINITY)
            };
            r(a).total_cmp(&r(b))
        })
        .ok_or_else(|| anyhow::anyhow!("no model family was fitted"))?;
    let law = LawSpec::GreyBox {
        inner: Box::new(LawSpec::Learned {
            model: PathBuf::from(format!("fit/models/{}.json", best.family.name())),
            contact: Some(study.contact),
        }),
        outside: Box::new(LawSpec::PowerFit),
        blend_fraction: 0.1,
        shear_cap_k_mpa: Some(DEMO_SHEAR_CAP_MPA),
        clamp: Some((0.05, 1.0)),
    };
    let law_path = out.join("law.json");
    write_string_atomic(&law_path, &serde_json::to_string_pretty(&law)?)?;
    let export_args = cmd_export::Args {
        law: law_path.clone(),
        format: cmd_export::Format::Abaqus,
        out: out.join("abaqus_friction.inp"),
        pressure_mpa: "900:2200:14".into(),
        velocity: "20:250:24".into(),
        temperature: None,
        pressure_unit: "MPa".into(),
        speed_unit: "mm/s".into(),
        temperature_unit: "C".into(),
        taumax_mpa: Some(DEMO_SHEAR_CAP_MPA),
        deform_windows: None,
        deform_reference_velocity_m_per_min: 150.0,
        deform_objects: vec![2, 1],
        lsdyna_table_id: 1000,
        check_points: 0,
    };
    let export_line = cmd_export::export(&export_args)?;
    write_string_atomic(&out.join("ffi/greybox.h"), GREYBOX_H)?;
    write_string_atomic(&out.join("ffi/greybox.f90"), GREYBOX_F90)?;
    // rig dynamics: virtual impact-hammer tests at the article's three loads
    let mut recordings = Vec::new();
    for (load, f_hz, zeta) in VIRTUAL_RIG {
        let rec = greybox_tribo::frf_synth::Chain::sdof(3.0, f_hz, zeta).record(
            20_000.0,
            1.2,
            &[200.0; 5],
            0.5e-3,
            2e-9,
            load as u64,
        );
        let mut csv = String::from("time_s,hammer_N,response_m\n");
        for k in 0..rec.hammer.len() {
            csv.push_str(&format!(
                "{},{},{}\n",
                k as f64 / rec.sample_rate_hz,
                rec.hammer[k],
                rec.response[k]
            ));
        }
        let p = out.join("hammer").join(format!("hammer_{load:.0}N.csv"));
        write_string_atomic(&p, &csv)?;
        recordings.push(format!("{}@{load}", p.display()));
    }
    let char_args = cmd_characterize::Args {
        recordings,
        hammer: "hammer_N".into(),
        response: "response_m".into(),
        time: "time_s".into(),
        sample_rate_hz: None,
        tdms_group: "Hammer".into(),
        block_s: None,
        exponential_end: None,
        harmonics: 3,
        plan: cmd_plan::PlanFlags {
            study: Some(out.join("plan").join("study.toml")),
            ..Default::default()
        },
        out: out.join("characterize"),
        force: false,
        json: false,
    };
    let dynamics = cmd_characterize::characterize(&char_args)?;
    // wear: the article's five pin tests (digest §4), k → V = k F s → k
    let wear_path = out.join("wear-tests.csv");
    write_string_atomic(&wear_path, WEAR_TESTS)?;
    let wear_tests = greybox_tribo::wear::read_wear_tests(&wear_path)?;
    // coupling: the bundled CalculiX example, run when ccx is installed
    let couple_dir = out.join("couple");
    greybox_couple::example::write_example(&couple_dir, 5)?;
    let coupling = if std::process::Command::new("ccx").arg("-v").output().is_ok() {
        let law = greybox_friction::spec::load_law(&couple_dir.join("law.json"))?;
        let mut engine = greybox_couple::calculix::CalculixEngine::new(
            greybox_couple::calculix::CalculixConfig {
                ccx: "ccx".into(),
                deck: couple_dir.join("model.inp"),
                segment_template: couple_dir.join("segment.inp"),
                work: couple_dir.join("run"),
                pressure_pa_per_unit: 1e6,
                length_m_per_unit: 1e-3,
                segment_s: 1e-3,
            },
        )?;
        Some(greybox_couple::engine::couple(
            &mut engine,
            law.as_ref(),
            20,
            1e-3,
            Some(&couple_dir.join("run").join("history.csv")),
        )?)
    } else {
        None
    };
    // material: J-C A, B, n, m from the article's compression programme (virtual curves with
    // 1 % noise and the blue-brittleness anomaly at 359 °C)
    let curves = out.join("material").join("flow-curves.csv");
    let truth = greybox_material::JohnsonCook {
        room_temperature_k: 298.15,
        ..greybox_material::JohnsonCook::aisi1045_article()
    };
    let temps: Vec<f64> = (0..7).map(|k| 25.0 + 167.0 * k as f64).collect();
    let pts = greybox_material::fit::synthetic_flow_curves(&truth, &temps, 4e-3, 0.01, 7, &|tc| {
        if (tc - 359.0).abs() < 1.0 {
            1.12
        } else {
            1.0
        }
    });
    greybox_material::fit::write_flow_curves(&curves, &pts)?;
    let material = cmd_material::fit(&cmd_material::FitArgs {
        curves: curves.clone(),
        c: truth.c,
        ref_strain_rate: Some(4e-3),
        room_temperature_c: Some(25.0),
        melt_temperature_k: truth.melt_temperature_k,
        misfit_threshold: 0.05,
        out: Some(out.join("material").join("jc-fit.json")),
        json: false,
    })?;
    // cutting: the article's case (coarser: 12.5 µm spacing) with the grey-box law in 12.5 µm
    // windows along rake and flank, re-evaluated every 500 steps, until the force is steady
    let mut setup: greybox_sim::cutting::CuttingSetup = toml::from_str(DEMO_CUT)?;
    setup.spacing_m = 12.5e-6;
    setup.friction.window_length_m = 12.5e-6;
    setup.cut_length_m = 0.6e-3;
    setup.friction.law_file = Some("law.json".into());
    let cut_case = cmd_simulate::cut_case(setup, out)?;
    let cut_out = cmd_simulate::Output {
        out: out.join("cutting"),
        vtk_every: 0,
        checkpoint_every: 0,
        resume: None,
        force: false,
        json: false,
    };
    let cutting = cmd_simulate::run_cut(&cut_case, 1.0, &cut_out)?;
    // the run is complete: swap it in, then report the paths where the files now are
    crate::output::provenance(&[])?
        .with_seed(study.synth.seed)
        .write_into(Path::new("."))?;
    drop(cwd);
    staged.commit()?;
    let shown = |p: &Path| -> PathBuf { a.out.join(p) };
    if a.json {
        let v = serde_json::to_value(DemoSummary {
            plan: plan_summary,
            synth,
            identify,
            correction,
            fit,
            fit_outputs,
            law: law_path.display().to_string(),
            dynamics,
            wear_tests,
            coupling,
            material,
            cutting,
        })?;
        return print_json(&v);
    }
    let out = a.out.as_path();
    let (rec_dir, dataset, foreign_dir, law_path, wear_path, couple_dir, curves) = (
        shown(&rec_dir),
        shown(&dataset),
        shown(&foreign_dir),
        shown(&law_path),
        shown(&wear_path),
        shown(&couple_dir),
        shown(&curves),
    );
    let adhesive_out = shown(&adhesive_args.out);
    let cut_dir = shown(&cut_out.out);
    let mut identify = identify;
    identify.dataset = shown(Path::new(&identify.dataset)).display().to_string();
    let models: Vec<String> = fit_outputs
        .models
        .iter()
        .map(|m| shown(Path::new(m)).display().to_string())
        .collect();
    let plots: Vec<String> = fit_outputs
        .plots
        .iter()
        .map(|m| shown(Path::new(m)).display().to_string())
        .collect();
    println!("greybox demo — the seed article's tribometer campaign on a virtual rig\n");
    println!(
        "[0/6] rig dynamics: virtual impact-hammer tests at 500, 1000, 2000 N -> {}",
        out.join("characterize").display()
    );
    cmd_characterize::print_report(&dynamics);
    println!();
    println!("[1/6] plan -> {}", out.join("plan").display());
    cmd_plan::print_summary(&plan_summary);
    println!("\n[2/6] synth -> {}", rec_dir.display());
    cmd_synth::print_summary(&synth);
    println!(
        "\n[3/6] identify (TDMS recordings) -> {}",
        dataset.display()
    );
    print!("{}", cmd_identify::summary_table(&ds));
    cmd_identify::print_identify_footer(&identify);
    println!(
        "\n[3b] identify a foreign rig's export (rotary tribometer CSV, no plan) -> {}",
        foreign_dir.join("dataset.csv").display()
    );
    print!("{}", cmd_identify::inspect_text(&foreign_id.files));
    println!(
        "  against its ground truth: max |COF - COF_true| = {:.5} over {} steps",
        foreign_error.max_abs_error, foreign_error.plateaus
    );
    println!(
        "\n[4/6] adhesive COF (Bowden-Tabor ploughing, the article's Table 3 track widths) -> {}",
        adhesive_out.display()
    );
    cmd_adhesive::print_correction(&correction);
    println!(
        "\n[5/6] fit: the article's four model families and grids on cof_adhesive -> {}",
        out.join("fit").display()
    );
    println!("{}", greybox_learn::protocol::markdown(&fit));
    println!("models: {}", models.join(", "));
    println!("plots:  {}", plots.join(", "));
    println!("\n[6/6] grey-box law ({} inside its training domain, fitted power law outside, Zorev cap {DEMO_SHEAR_CAP_MPA} MPa) -> {}", best.family.name(), law_path.display());
    println!("{export_line}");
    println!(
        "C ABI for user routines: {} and {} (library: cargo build --release -p greybox-ffi)",
        out.join("ffi/greybox.h").display(),
        out.join("ffi/greybox.f90").display()
    );
    println!(
        "\nwear (the article's pin tests, {}): implied volumes V = k F s and k back from V",
        wear_path.display()
    );
    for w in &wear_tests {
        let v = w.implied_volume_mm3();
        let k_back = greybox_tribo::wear::archard_k(v, w.normal_force_n, w.distance_m())? * 1e7;
        println!(
            "  {}: {} N, {} m/min, {} s -> s = {:.1} m, V = {:.3e} mm3, k = {:.2}e-7 mm3/(N m)",
            w.pin,
            w.normal_force_n,
            w.velocity_m_per_min,
            w.duration_s,
            w.distance_m(),
            v,
            k_back
        );
    }
    match &coupling {
        Some(r) => {
            println!(
                "\ncoupling with CalculiX ({}): the restart loop {} after {} cycles; final μ per window:",
                couple_dir.display(),
                if r.converged { "converged" } else { "did not converge" },
                r.cycles
            );
            for (w, mu) in &r.final_mu {
                println!("  {w}: {mu:.4}");
            }
        }
        None => println!(
            "\ncoupling: example deck written to {} (install calculix-ccx to run it: greybox couple --deck {}/model.inp --segment {}/segment.inp --law {}/law.json)",
            couple_dir.display(),
            couple_dir.display(),
            couple_dir.display(),
            couple_dir.display()
        ),
    }
    println!(
        "\nmaterial: Johnson-Cook A, B, n, m from virtual compression curves at 25-1027 °C ({}; truth: the article's Table 4, 1 % noise, 12 % dynamic strain ageing at 359 °C)",
        curves.display()
    );
    cmd_material::print_fit(&material);
    println!(
        "\ncutting: AISI 1045, 150 m/min, h = 0.1 mm, grey-box law in friction windows along the tool -> {}",
        cut_dir.display()
    );
    cmd_simulate::print_cut_summary(&cutting);
    println!(
        "  contact profile along the rake face (pressure, sliding velocity, temperature, mu, shear stress): {}",
        cut_dir.join("contact_profile.csv").display()
    );
    Ok(())
}

/// The process working directory set to a directory while the demo writes into it, and
/// restored when dropped (also on an error).
struct WorkingDir {
    previous: PathBuf,
}

impl WorkingDir {
    fn enter(dir: &Path) -> Result<Self> {
        let previous = std::env::current_dir()?;
        std::env::set_current_dir(dir)?;
        Ok(WorkingDir { previous })
    }
}

impl Drop for WorkingDir {
    fn drop(&mut self) {
        let _ = std::env::set_current_dir(&self.previous);
    }
}

/// The demo's virtual rig, one single-degree-of-freedom model per normal load: (load N,
/// natural frequency Hz, damping ratio). The contact stiffens and damps more with load
/// (the article saw the vibration amplitude fall with load).
const VIRTUAL_RIG: [(f64, f64, f64); 3] = [
    (500.0, 420.0, 0.02),
    (1000.0, 500.0, 0.026),
    (2000.0, 590.0, 0.034),
];

/// Shear flow stress used for the demo's Zorev cap, MPa (≈ AISI 1045 at cutting strain rates).
const DEMO_SHEAR_CAP_MPA: f64 = 600.0;
/// The article's cutting case (examples/aisi1045-cut.toml).
const DEMO_CUT: &str = include_str!("../../../examples/aisi1045-cut.toml");
/// The article's five wear tests (Table 2).
const WEAR_TESTS: &str = include_str!("../../../examples/wear-tests.csv");
/// The C header and Fortran module of the C ABI, copied into the demo output.
const GREYBOX_H: &str = include_str!("../../greybox-ffi/include/greybox.h");
const GREYBOX_F90: &str = include_str!("../../greybox-ffi/fortran/greybox.f90");
