//! The demo: the article's whole pipeline on the bundled example study and a virtual rig —
//! plan, recordings, identification (also of a foreign rig's export), ploughing correction,
//! the learning protocol, the grey-box law and its exports, rig dynamics, wear, coupling
//! with CalculiX (when installed), the material fit and a cut with friction windows.

use crate::report::{report, ReportOptions, ReportSummary};
use anyhow::Result;
use greybox_core::atomic::write_string_atomic;
use greybox_core::dataset::FrictionDataset;
use greybox_core::provenance::Provenance;
use greybox_core::units::{m_per_min_to_m_per_s, mpa_to_pa};
use greybox_couple::engine::CouplingResult;
use greybox_friction::export::engine::{
    equidistant, Engine, ExportFormat, DEFAULT_TEMPERATURE_UNIT, DEFAULT_UNITS,
};
use greybox_friction::export::Grid;
use greybox_model::modelfile::ModelFile;
use greybox_model::Family;
use greybox_pipeline::adhesive::{adhesive, AdhesiveOptions};
use greybox_pipeline::characterize::{
    characterize, CharacterizeOptions, CharacterizeReport, ExcitationPlan, ImpactChannels,
};
use greybox_pipeline::couple::{couple, CoupleOptions, EngineOptions};
use greybox_pipeline::export::{export, ExportOptions};
use greybox_pipeline::fit::{fit, write_report, FitOptions, FitOutputs, FitResult};
use greybox_pipeline::identify::{
    compare_with_truth, identify_campaign, Expectation, IdentifyOptions, IdentifyResult,
    IdentifySummary, TruthComparison,
};
use greybox_pipeline::law::{best_family, grey_box_law, write_law, GreyBoxOptions};
use greybox_pipeline::material::fit_flow_curves;
use greybox_pipeline::output::{provenance, stage_out_dir};
use greybox_pipeline::plan::{summarize, write_plan, PlanSummary};
use greybox_pipeline::simulate::{cut_case, run_cut, CutSummary, RunOutput};
use greybox_pipeline::study::{Study, DEMO_STUDY};
use greybox_pipeline::synth::{synthesize, SynthSummary};
use greybox_recording::readers::RecordingFormat;
use greybox_tribo::campaign::FileReport;
use greybox_tribo::frf::ImpactConfig;
use greybox_tribo::plan::Plan;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What the demo did, stage by stage (serialised as the demo's JSON summary).
#[derive(Debug, Clone, Serialize)]
pub struct DemoSummary {
    pub plan: PlanSummary,
    pub synth: SynthSummary,
    pub identify: IdentifySummary,
    pub correction: greybox_contact::ploughing::Correction,
    pub fit: greybox_learn::protocol::FitReport,
    pub fit_outputs: FitOutputs,
    pub law: String,
    pub dynamics: CharacterizeReport,
    pub wear_tests: Vec<greybox_contact::wear::WearTest>,
    pub coupling: Option<greybox_couple::engine::CouplingResult>,
    pub material: greybox_material::fit::JcFit,
    pub cutting: CutSummary,
    /// The study's report page.
    pub report: ReportSummary,
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
    pub law_family: Family,
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
/// swapped in whole; an existing non-empty `out` needs `force`).
///
/// Every stage writes under the staging directory by absolute paths; the process's working
/// directory is never changed, so the demo may run beside other work (threads, a Python
/// caller). What the outputs record stays valid wherever the directory is moved: before
/// the swap every provenance record's inputs under the staging directory are rewritten
/// relative to it (the demo's root), the law refers to its model relative to the law file,
/// and the summary's and [`Demo::paths`]' paths are relative to the demo's directory.
pub fn run(out_dir: &Path, force: bool) -> Result<Demo> {
    let study = Study::parse(DEMO_STUDY, "bundled examples/demo-study.toml")?;
    let plan = study.plan.build()?;
    let target = std::path::absolute(out_dir)?;
    let staged = stage_out_dir(&target, force, &[])?;
    let base = staged.path();
    let campaign = campaign(base, &study, &plan)?;
    let foreign = foreign_rig(base)?;
    let law = grey_box(base, &study, &campaign.dataset_csv)?;
    let dynamics = dynamics(base, &plan)?;
    // wear: the article's five pin tests (digest §4), k → V = k F s → k
    let wear_path = PathBuf::from("wear-tests.csv");
    write_string_atomic(&base.join(&wear_path), WEAR_TESTS)?;
    let wear_tests = greybox_contact::wear::read_wear_tests(&base.join(&wear_path))?;
    let (couple_dir, coupling) = coupling(base)?;
    let (curves, material) = material(base)?;
    let (cut_dir, cutting) = cut(base)?;
    // the run is complete: its records made relative to the demo's root, then swapped in
    provenance(&[])?
        .with_seed(study.synth.seed)
        .write_into(base)?;
    relative_provenance(base)?;
    staged.commit()?;
    // the page over everything, once the directory holds it all
    let report = report(&ReportOptions::new(out_dir))?;
    Ok(Demo {
        summary: DemoSummary {
            plan: campaign.plan,
            synth: campaign.synth,
            identify: campaign.identified.summary,
            correction: law.correction,
            fit: law.fitted.report,
            fit_outputs: law.fitted.outputs,
            law: law.path.display().to_string(),
            dynamics,
            wear_tests,
            coupling,
            material,
            cutting,
            report,
        },
        dataset: campaign.identified.dataset,
        foreign_files: foreign.identified.summary.identification.files,
        foreign_error: foreign.error,
        law_family: law.family,
        export_line: law.export_line,
        paths: DemoPaths {
            recordings: campaign.recordings,
            dataset: campaign.dataset_csv,
            foreign_rig: foreign.dir,
            dataset_adhesive: law.dataset_adhesive,
            law: law.path,
            wear_tests: wear_path,
            couple: couple_dir,
            flow_curves: curves,
            cutting: cut_dir,
        },
    })
}

/// The virtual campaign: the plan, its recordings and what identification found.
struct Campaign {
    plan: PlanSummary,
    synth: SynthSummary,
    recordings: PathBuf,
    dataset_csv: PathBuf,
    identified: IdentifyResult,
}

/// Plan the study's campaign, record it on the virtual rig (CSV and TDMS) and identify the
/// TDMS recordings against the plan and the ground truth.
fn campaign(base: &Path, study: &Study, plan: &Plan) -> Result<Campaign> {
    let plan_files = write_plan(study, plan, &base.join("plan"))?;
    let recordings = PathBuf::from("recordings");
    let mut synth = synthesize(
        study,
        plan,
        &base.join(&recordings),
        &[RecordingFormat::Csv, RecordingFormat::Tdms],
    )?;
    synth.files = relative_all(base, &synth.files);
    let dataset_csv = PathBuf::from("dataset.csv");
    let mut identified = identify_campaign(
        study,
        &IdentifyOptions {
            recordings: vec![base.join(&recordings)],
            format: Some(RecordingFormat::Tdms),
            expect: Expectation::Plan(plan.clone()),
            track_radii_mm: Vec::new(),
            dataset: base.join(&dataset_csv),
            inspect_dir: None,
            truth: Some(base.join(&recordings).join("ground_truth.csv")),
            side_inputs: Vec::new(),
        },
        None,
    )?;
    relative_identify(base, &mut identified);
    Ok(Campaign {
        plan: summarize(plan, relative_all(base, &plan_files)),
        synth,
        recordings,
        dataset_csv,
        identified,
    })
}

/// A recording from another rig, identified without a plan.
struct ForeignRig {
    dir: PathBuf,
    identified: IdentifyResult,
    error: TruthComparison,
}

/// A rotary tribometer's CSV export (preamble, Step column, time restarting per step,
/// trailing delimiters, footer, rpm on a per-step track radius), identified and compared
/// with its ground truth.
fn foreign_rig(base: &Path) -> Result<ForeignRig> {
    let dir = PathBuf::from("foreign-rig");
    let abs = base.join(&dir);
    std::fs::create_dir_all(&abs)?;
    let file = abs.join("rotary-export.csv");
    write_string_atomic(&file, FOREIGN_EXPORT)?;
    let truth = abs.join("rotary-export-truth.csv");
    write_string_atomic(&truth, FOREIGN_TRUTH)?;
    let mut options = IdentifyOptions::new(vec![file], abs.join("dataset.csv"));
    options.track_radii_mm = FOREIGN_RADII_MM.to_vec();
    let mut identified = identify_campaign(&Study::default(), &options, None)?;
    let error = compare_with_truth(&identified.dataset, &truth)?;
    relative_identify(base, &mut identified);
    Ok(ForeignRig {
        dir,
        identified,
        error,
    })
}

/// From the dataset to the grey-box law and its exports.
struct GreyBox {
    correction: greybox_contact::ploughing::Correction,
    dataset_adhesive: PathBuf,
    fitted: FitResult,
    family: Family,
    path: PathBuf,
    export_line: String,
}

/// The ploughing correction (the article's Table 3 track widths), the article's protocol on
/// the adhesive COF, the grey-box law around the family with the best held-out R², its
/// Abaqus table, and the C ABI's header and Fortran module.
fn grey_box(base: &Path, study: &Study, dataset_csv: &Path) -> Result<GreyBox> {
    let dataset_adhesive = PathBuf::from("dataset_adhesive.csv");
    let mut adhesive_options =
        AdhesiveOptions::analytic(base.join(dataset_csv), base.join(&dataset_adhesive));
    adhesive_options.pin_radius_mm = study.contact.pin_tip_radius_mm;
    let (_, correction) = adhesive(&adhesive_options)?;
    let mut fitted = fit(&FitOptions::article(
        adhesive_options.out.clone(),
        "cof_adhesive",
        base.join("fit"),
    ))?;
    relative_fit(base, &mut fitted)?;
    let family = best_family(&fitted.report)
        .ok_or_else(|| anyhow::anyhow!("no model family was fitted"))?
        .family;
    let law = grey_box_law(
        PathBuf::from(format!("fit/models/{}.json", family.name())),
        Some(study.contact),
        &GreyBoxOptions {
            shear_cap_k_mpa: Some(DEMO_SHEAR_CAP_MPA),
            ..GreyBoxOptions::default()
        },
    );
    // the law names its model relative to the law file (beside it: the demo's root)
    let path = PathBuf::from("law.json");
    write_law(&base.join(&path), &law)?;
    let table = PathBuf::from("abaqus_friction.inp");
    let export_line = export(
        &ExportOptions::new(base.join(&path), ExportFormat::Abaqus, base.join(&table))
            .with_grid(Grid {
                pressure_pa: equidistant(900.0, 2200.0, 14)
                    .into_iter()
                    .map(mpa_to_pa)
                    .collect(),
                velocity_m_s: equidistant(20.0, 250.0, 24)
                    .into_iter()
                    .map(m_per_min_to_m_per_s)
                    .collect(),
                temperature_k: None,
            })?
            .with_engine(Engine::Abaqus {
                units: DEFAULT_UNITS,
                temperature_unit: DEFAULT_TEMPERATURE_UNIT,
                taumax_pa: Some(mpa_to_pa(DEMO_SHEAR_CAP_MPA)),
            })?,
    )?
    .line
    // the line names the table relative to the demo's root, as the summary does
    .replace(
        &base.join(&table).display().to_string(),
        &table.display().to_string(),
    );
    write_string_atomic(&base.join("ffi/greybox.h"), GREYBOX_H)?;
    write_string_atomic(&base.join("ffi/greybox.f90"), GREYBOX_F90)?;
    Ok(GreyBox {
        correction,
        dataset_adhesive,
        fitted,
        family,
        path,
        export_line,
    })
}

/// Rig dynamics: virtual impact-hammer tests at the article's three loads, characterised
/// against the spindle excitation of the campaign `plan`.
fn dynamics(base: &Path, plan: &Plan) -> Result<CharacterizeReport> {
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
        let p = base.join("hammer").join(format!("hammer_{load:.0}N.csv"));
        write_string_atomic(&p, &rec.to_csv())?;
        recordings.push((p, Some(load)));
    }
    let study_file = base.join("plan").join("study.toml");
    let mut report = characterize(&CharacterizeOptions {
        recordings,
        channels: ImpactChannels {
            response: "response_m".into(),
            ..ImpactChannels::default()
        },
        impact: ImpactConfig::default(),
        harmonics: greybox_pipeline::characterize::Harmonics::of(3),
        // the demo study states its loads and velocities
        plan: Some(ExcitationPlan {
            plan: plan.clone(),
            velocities_stated: true,
        }),
        study: Some(study_file),
        out: base.join("characterize"),
        force: false,
    })?;
    // its report as the summary shows it: files relative to the demo's root
    report.files = relative_all(base, &report.files);
    write_string_atomic(
        &base.join("characterize/report.json"),
        &serde_json::to_string_pretty(&report)?,
    )?;
    Ok(report)
}

/// The bundled CalculiX restart-loop example: written, and run when ccx is installed.
fn coupling(base: &Path) -> Result<(PathBuf, Option<CouplingResult>)> {
    let rel = PathBuf::from("couple");
    let dir = base.join(&rel);
    greybox_couple::example::write_example(&dir, 5)?;
    if std::process::Command::new("ccx")
        .arg("-v")
        .output()
        .is_err()
    {
        return Ok((rel, None));
    }
    let result = couple(&CoupleOptions {
        engine: EngineOptions::Calculix {
            ccx: "ccx".into(),
            deck: dir.join("model.inp"),
            segment: dir.join("segment.inp"),
            pressure_pa_per_unit: 1e6,
            length_m_per_unit: 1e-3,
            segment_s: 1e-3,
        },
        law: dir.join("law.json"),
        work: dir.join("run"),
        max_cycles: 20,
        tol: 1e-3,
    })?;
    Ok((rel, Some(result)))
}

/// J-C A, B, n, m from the article's compression programme: virtual curves with 1 % noise
/// and the blue-brittleness anomaly at 359 °C.
fn material(base: &Path) -> Result<(PathBuf, greybox_material::fit::JcFit)> {
    let curves = Path::new("material").join("flow-curves.csv");
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
    greybox_material::fit::write_flow_curves(&base.join(&curves), &pts)?;
    let fitted = fit_flow_curves(
        &base.join(&curves),
        &greybox_material::fit::FitOptions {
            c: truth.c,
            ref_strain_rate: Some(4e-3),
            room_temperature_k: Some(25.0 + 273.15),
            melt_temperature_k: truth.melt_temperature_k,
            misfit_threshold: 0.05,
        },
        Some(&base.join("material").join("jc-fit.json")),
    )?;
    Ok((curves, fitted))
}

/// Pictures of the chip the demo's cut draws while it forms.
pub const DEMO_CHIP_FRAMES: greybox_pipeline::simulate::Frames =
    greybox_pipeline::simulate::Frames::of(8);

/// The article's cut (coarser: 12.5 µm spacing) with the grey-box law in 12.5 µm windows
/// along rake and flank, re-evaluated every 500 steps from smoothed window states.
fn cut(base: &Path) -> Result<(PathBuf, CutSummary)> {
    let mut setup: greybox_sim::cutting::CuttingSetup = toml::from_str(DEMO_CUT)?;
    setup.spacing_m = 12.5e-6;
    setup.friction.window_length_m = 12.5e-6;
    setup.cut_length_m = 0.6e-3;
    setup.friction.law_file = Some("law.json".into());
    // The law sees each window's state averaged over 4 updates and its two neighbours:
    // single-interval window states jump, and the law passes every jump on (docs/cutting.md).
    setup.friction.smoothing = greybox_sim::friction_loop::Smoothing {
        time_updates: 4.0,
        space_windows: 1,
    };
    // the law file is resolved against the demo's root, and named relative to it
    let mut case = cut_case(setup, base)?;
    case.law_source = relative(base, &case.law_source);
    let dir = PathBuf::from("cutting");
    let out = RunOutput {
        frames: DEMO_CHIP_FRAMES,
        ..RunOutput::to(base.join(&dir))
    };
    let mut summary = run_cut(&case, 1.0, &out)?;
    // its summary (also on disk) names its files relative to the demo's root
    summary.files = relative_all(base, &summary.files);
    write_string_atomic(
        &base.join(&dir).join("summary.json"),
        &serde_json::to_string_pretty(&summary)?,
    )?;
    Ok((dir, summary))
}

/// `p` relative to the demo's root `base` when it lies under it (the stages are given
/// absolute paths under the staging directory); any other path as it is.
fn relative(base: &Path, p: &str) -> String {
    Path::new(p)
        .strip_prefix(base)
        .map_or_else(|_| p.to_string(), |r| r.display().to_string())
}

/// [`relative`] of every path of a list.
fn relative_all(base: &Path, paths: &[String]) -> Vec<String> {
    paths.iter().map(|p| relative(base, p)).collect()
}

/// The paths of an identification's summary (dataset, per-cycle file, recordings)
/// relative to the demo's root.
fn relative_identify(base: &Path, identified: &mut IdentifyResult) {
    let s = &mut identified.summary;
    s.dataset = relative(base, &s.dataset);
    s.cycles = s.cycles.as_deref().map(|c| relative(base, c));
    for f in &mut s.identification.files {
        f.source = relative(base, &f.source);
    }
}

/// The paths of a fit into `base`/`fit` (its data and outputs) relative to the demo's
/// root: in its summary, its report (rewritten) and its models' provenance (resealed).
fn relative_fit(base: &Path, fitted: &mut FitResult) -> Result<()> {
    fitted.report.source = relative(base, &fitted.report.source);
    write_report(&base.join("fit"), &fitted.report)?;
    for model in &fitted.outputs.models {
        let path = Path::new(model);
        let mut m = ModelFile::load(path)?;
        m.provenance = m.provenance.map(|p| p.relative_to(base));
        m.seal()?.save(path)?;
    }
    let o = &mut fitted.outputs;
    o.report_json = relative(base, &o.report_json);
    o.report_md = relative(base, &o.report_md);
    o.models = relative_all(base, &o.models);
    o.plots = relative_all(base, &o.plots);
    Ok(())
}

/// Rewrite every provenance record under the demo's root (`*.provenance.json`,
/// `provenance.json`) with its inputs under `base` relative to it, atomically as the
/// stages wrote them: what the records name then holds wherever the directory is moved.
fn relative_provenance(base: &Path) -> Result<()> {
    let mut dirs = vec![base.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir)? {
            let entry = entry?;
            let path = entry.path();
            if entry.file_type()?.is_dir() {
                dirs.push(path);
                continue;
            }
            let name = entry.file_name().to_string_lossy().into_owned();
            // the record of a directory output, or the one beside a file output
            let output = if name == "provenance.json" {
                None
            } else if let Some(file) = name.strip_suffix(".provenance.json") {
                Some(dir.join(file))
            } else {
                continue;
            };
            let record = Provenance::read(&path)?;
            let relative = record.clone().relative_to(base);
            if relative == record {
                continue;
            }
            match output {
                None => relative.write_into(&dir)?,
                Some(output) => relative.write_beside(&output)?,
            };
        }
    }
    Ok(())
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
