//! The demo: the article's whole pipeline on the bundled example study and a virtual rig —
//! plan, recordings, identification (also of a foreign rig's export), ploughing correction,
//! the learning protocol, the grey-box law and its exports, rig dynamics, wear, coupling
//! with CalculiX (when installed), the material fit and a cut with friction windows.

use crate::adhesive::{adhesive, AdhesiveOptions};
use crate::characterize::{characterize, CharacterizeOptions, CharacterizeReport, ImpactChannels};
use crate::export::{equidistant, export, ExportFormat, ExportOptions};
use crate::fit::{fit, FitOptions, FitOutputs};
use crate::identify::{
    compare_with_truth, identify_campaign, Expectation, IdentifyOptions, IdentifySummary,
    TruthComparison,
};
use crate::law::{best_family, grey_box_law, write_law, GreyBoxOptions};
use crate::material::fit_flow_curves;
use crate::output::{provenance, stage_out_dir};
use crate::plan::{summarize, write_plan, PlanSummary};
use crate::simulate::{cut_case, run_cut, CutSummary, RunOutput};
use crate::study::{Study, DEMO_STUDY};
use crate::synth::{synthesize, SynthSummary};
use anyhow::Result;
use greybox_core::atomic::write_string_atomic;
use greybox_core::dataset::FrictionDataset;
use greybox_friction::export::{Grid, PressureUnit, SpeedUnit, TempUnit, Units};
use greybox_tribo::campaign::FileReport;
use greybox_tribo::frf::ImpactConfig;
use greybox_tribo::readers::RecordingFormat;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What the demo did, stage by stage (serialised as the demo's JSON summary).
#[derive(Debug, Clone, Serialize)]
pub struct DemoSummary {
    pub plan: PlanSummary,
    pub synth: SynthSummary,
    pub identify: IdentifySummary,
    pub correction: greybox_tribo::ploughing::Correction,
    pub fit: greybox_learn::protocol::FitReport,
    pub fit_outputs: FitOutputs,
    pub law: String,
    pub dynamics: CharacterizeReport,
    pub wear_tests: Vec<greybox_tribo::wear::WearTest>,
    pub coupling: Option<greybox_couple::engine::CouplingResult>,
    pub material: greybox_material::fit::JcFit,
    pub cutting: CutSummary,
}

/// The demo's results. Paths are relative to the demo's directory.
pub struct Demo {
    pub summary: DemoSummary,
    /// The identified dataset of the virtual rig's TDMS recordings.
    pub dataset: FrictionDataset,
    /// What was found per file of the foreign rig's export.
    pub foreign_files: Vec<FileReport>,
    /// The foreign export identified against its ground truth.
    pub foreign_error: TruthComparison,
    /// The model family inside the grey-box law.
    pub law_family: String,
    /// One line on the Abaqus export.
    pub export_line: String,
    /// Where each part went, relative to the demo's directory.
    pub paths: DemoPaths,
}

/// Where the demo wrote its parts, relative to its directory.
pub struct DemoPaths {
    pub recordings: PathBuf,
    pub dataset: PathBuf,
    pub foreign_rig: PathBuf,
    pub dataset_adhesive: PathBuf,
    pub law: PathBuf,
    pub wear_tests: PathBuf,
    pub couple: PathBuf,
    pub flow_curves: PathBuf,
    pub cutting: PathBuf,
}

/// A rotary tribometer's CSV export (written by the independent test rig,
/// `crates/greybox-tribo/tests/support/exports.rs`, seed 1) and its ground truth.
const FOREIGN_EXPORT: &str = include_str!("../../../examples/foreign-rig/rotary-export.csv");
const FOREIGN_TRUTH: &str = include_str!("../../../examples/foreign-rig/rotary-export-truth.csv");
/// The export's wear-track radius per step, mm.
const FOREIGN_RADII_MM: [f64; 5] = [5.0, 6.0, 7.0, 8.0, 9.0];

/// Run the whole pipeline on the bundled example study into the directory `out` (staged and
/// swapped in whole; an existing non-empty `out` needs `force`). Every file is written
/// with paths relative to `out`, so what the outputs record stays valid wherever the
/// directory is moved.
///
/// While it runs, the process's working directory is `out`'s staging directory (restored
/// afterwards, also on an error): do not run other work that uses relative paths beside it.
pub fn run(out_dir: &Path, force: bool) -> Result<Demo> {
    let study = Study::parse(DEMO_STUDY, "bundled examples/demo-study.toml")?;
    let plan = study.plan.build()?;
    let target = std::path::absolute(out_dir)?;
    let staged = stage_out_dir(&target, force, &[])?;
    // Every stage writes with paths relative to the demo's own directory, so that what the
    // outputs record (report sources, provenance inputs, the law's model reference) holds
    // after the swap, wherever the directory is moved.
    let cwd = WorkingDir::enter(staged.path())?;
    let out = Path::new("");
    let plan_files = write_plan(&study, &plan, &out.join("plan"))?;
    let plan_summary = summarize(&plan, plan_files);
    let rec_dir = out.join("recordings");
    let synth = synthesize(
        &study,
        &plan,
        &rec_dir,
        &[RecordingFormat::Csv, RecordingFormat::Tdms],
    )?;
    let dataset = out.join("dataset.csv");
    let main = identify_campaign(
        &study,
        &IdentifyOptions {
            recordings: vec![rec_dir.clone()],
            format: Some(RecordingFormat::Tdms),
            expect: Expectation::Plan(plan.clone()),
            track_radii_mm: Vec::new(),
            dataset: dataset.clone(),
            inspect_dir: None,
            truth: Some(rec_dir.join("ground_truth.csv")),
            side_inputs: Vec::new(),
        },
        None,
    )?;
    // a recording from another rig: a rotary tribometer's CSV export (preamble, Step column,
    // time restarting per step, trailing delimiters, footer, rpm on a per-step track radius)
    let foreign_dir = out.join("foreign-rig");
    std::fs::create_dir_all(&foreign_dir)?;
    let foreign_file = foreign_dir.join("rotary-export.csv");
    greybox_core::atomic::write_string_atomic(&foreign_file, FOREIGN_EXPORT)?;
    let foreign_truth = foreign_dir.join("rotary-export-truth.csv");
    greybox_core::atomic::write_string_atomic(&foreign_truth, FOREIGN_TRUTH)?;
    let foreign = identify_campaign(
        &Study::default(),
        &IdentifyOptions {
            recordings: vec![foreign_file],
            format: None,
            expect: Expectation::None,
            track_radii_mm: FOREIGN_RADII_MM.to_vec(),
            dataset: foreign_dir.join("dataset.csv"),
            inspect_dir: None,
            truth: None,
            side_inputs: Vec::new(),
        },
        None,
    )?;
    let foreign_error = compare_with_truth(&foreign.dataset, &foreign_truth)?;
    // ploughing correction with the article's Table 3 track widths
    let mut adhesive_options =
        AdhesiveOptions::analytic(dataset.clone(), out.join("dataset_adhesive.csv"));
    adhesive_options.pin_radius_mm = study.contact.pin_tip_radius_mm;
    let (_, correction) = adhesive(&adhesive_options)?;
    // the article's protocol on the adhesive COF
    let fitted = fit(&FitOptions::article(
        adhesive_options.out.clone(),
        "cof_adhesive",
        out.join("fit"),
    ))?;
    // grey-box law around the family with the best held-out R², exported for Abaqus, plus the C ABI files
    let best = best_family(&fitted.report)
        .ok_or_else(|| anyhow::anyhow!("no model family was fitted"))?
        .family;
    let law = grey_box_law(
        PathBuf::from(format!("fit/models/{}.json", best.name())),
        Some(study.contact),
        &GreyBoxOptions {
            shear_cap_k_mpa: Some(DEMO_SHEAR_CAP_MPA),
            ..GreyBoxOptions::default()
        },
    );
    let law_path = out.join("law.json");
    write_law(&law_path, &law)?;
    let export_line = export(&ExportOptions {
        law: law_path.clone(),
        format: ExportFormat::Abaqus,
        out: out.join("abaqus_friction.inp"),
        grid: Grid {
            pressure_pa: equidistant(900.0, 2200.0, 14)
                .iter()
                .map(|p| p * 1e6)
                .collect(),
            velocity_m_s: equidistant(20.0, 250.0, 24)
                .iter()
                .map(|v| v / 60.0)
                .collect(),
            temperature_k: None,
        },
        units: Units {
            pressure: PressureUnit::MPa,
            speed: SpeedUnit::MmPerS,
            temperature: TempUnit::C,
        },
        taumax_pa: Some(DEMO_SHEAR_CAP_MPA * 1e6),
        deform_windows: None,
        deform_reference_velocity_m_s: 150.0 / 60.0,
        deform_objects: (2, 1),
        lsdyna_table_id: 1000,
        check_points: 0,
    })?;
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
        recordings.push((p, Some(load)));
    }
    let dynamics = characterize(&CharacterizeOptions {
        recordings,
        channels: ImpactChannels {
            response: "response_m".into(),
            ..ImpactChannels::default()
        },
        impact: ImpactConfig::default(),
        harmonics: 3,
        plan: Study::load(&out.join("plan").join("study.toml"))
            .ok()
            .and_then(|s| s.plan.build().ok()),
        study: Some(out.join("plan").join("study.toml")),
        out: out.join("characterize"),
        force: false,
    })?;
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
    let material = fit_flow_curves(
        &curves,
        &greybox_material::fit::FitOptions {
            c: truth.c,
            ref_strain_rate: Some(4e-3),
            room_temperature_k: Some(25.0 + 273.15),
            melt_temperature_k: truth.melt_temperature_k,
            misfit_threshold: 0.05,
        },
        Some(&out.join("material").join("jc-fit.json")),
    )?;
    // cutting: the article's case (coarser: 12.5 µm spacing) with the grey-box law in 12.5 µm
    // windows along rake and flank, re-evaluated every 500 steps, until the force is steady
    let mut setup: greybox_sim::cutting::CuttingSetup = toml::from_str(DEMO_CUT)?;
    setup.spacing_m = 12.5e-6;
    setup.friction.window_length_m = 12.5e-6;
    setup.cut_length_m = 0.6e-3;
    setup.friction.law_file = Some("law.json".into());
    let cut_case = cut_case(setup, out)?;
    let cut_dir = out.join("cutting");
    let cutting = run_cut(&cut_case, 1.0, &RunOutput::to(&cut_dir))?;
    // the run is complete: swap it in
    provenance(&[])?
        .with_seed(study.synth.seed)
        .write_into(Path::new("."))?;
    drop(cwd);
    staged.commit()?;
    Ok(Demo {
        summary: DemoSummary {
            plan: plan_summary,
            synth,
            identify: main.summary,
            correction,
            fit: fitted.report,
            fit_outputs: fitted.outputs,
            law: law_path.display().to_string(),
            dynamics,
            wear_tests,
            coupling,
            material,
            cutting,
        },
        dataset: main.dataset,
        foreign_files: foreign.summary.identification.files,
        foreign_error,
        law_family: best.name().to_string(),
        export_line,
        paths: DemoPaths {
            recordings: rec_dir,
            dataset,
            foreign_rig: foreign_dir,
            dataset_adhesive: adhesive_options.out,
            law: law_path,
            wear_tests: wear_path,
            couple: couple_dir,
            flow_curves: curves,
            cutting: cut_dir,
        },
    })
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
pub const DEMO_SHEAR_CAP_MPA: f64 = 600.0;
/// The article's cutting case (examples/aisi1045-cut.toml).
const DEMO_CUT: &str = include_str!("../../../examples/aisi1045-cut.toml");
/// The article's five wear tests (Table 2).
const WEAR_TESTS: &str = include_str!("../../../examples/wear-tests.csv");
/// The C header and Fortran module of the C ABI, copied into the demo output.
const GREYBOX_H: &str = include_str!("../../greybox-ffi/include/greybox.h");
const GREYBOX_F90: &str = include_str!("../../greybox-ffi/fortran/greybox.f90");
