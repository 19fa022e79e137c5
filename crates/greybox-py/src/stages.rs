//! The pipeline's stages as Python functions: file paths and plain options in, a JSON report
//! out (the Python layer turns it into a dict and reads the tables it wrote). Each releases
//! the GIL while it works.

use crate::{py_err, run_interruptible, to_json};
use greybox_friction::export::engine::ExportFormat;
use greybox_pipeline::adhesive::adhesive;
use greybox_pipeline::export::{export, ExportOptions, ExportOverrides};
use greybox_pipeline::fit::fit;
use greybox_pipeline::identify::identify_campaign;
use greybox_pipeline::settings::adhesive::AdhesiveSettings;
use greybox_pipeline::settings::couple::CoupleSettings;
use greybox_pipeline::settings::cut::CutSettings;
use greybox_pipeline::settings::fit::FitSettings;
use greybox_pipeline::settings::from_keywords;
use greybox_pipeline::settings::hertz::HertzSettings;
use greybox_pipeline::settings::identify::IdentifySettings;
use greybox_pipeline::settings::law::GreyBoxSettings;
use greybox_pipeline::settings::material::{FlowCurveSettings, RateSensitivitySettings};
use greybox_pipeline::settings::pin::PinSettings;
use greybox_pipeline::settings::synth::SynthSettings;
use greybox_pipeline::settings::windows::WindowsSettings;
use greybox_pipeline::simulate::{run_pin, RunOutput};
use greybox_pipeline::study::Study;
use greybox_sweep::settings::ValidateSettings;
use pyo3::prelude::*;
use std::path::PathBuf;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(hertz_rows, m)?)?;
    m.add_function(wrap_pyfunction!(synth, m)?)?;
    m.add_function(wrap_pyfunction!(read_recording, m)?)?;
    m.add_function(wrap_pyfunction!(rig_profiles, m)?)?;
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    m.add_function(wrap_pyfunction!(ploughing_correction, m)?)?;
    m.add_function(wrap_pyfunction!(fit_models, m)?)?;
    m.add_function(wrap_pyfunction!(grey_box_law, m)?)?;
    m.add_function(wrap_pyfunction!(export_table, m)?)?;
    m.add_function(wrap_pyfunction!(export_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(settings_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(windows, m)?)?;
    m.add_function(wrap_pyfunction!(fit_flow_curves, m)?)?;
    m.add_function(wrap_pyfunction!(fit_rate_sensitivity, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_cut, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_pin, m)?)?;
    m.add_function(wrap_pyfunction!(couple, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    Ok(())
}

/// Hertz contact of a sphere (or a cylinder) on a flat for each normal force: JSON
/// {"effective_modulus_pa", "rows": [{force_n, contact_half_width_mm, max_pressure_mpa,
/// mean_pressure_mpa, approach_um, convention, convention_pressure_mpa}]}. `settings` is
/// JSON of the library's [`HertzSettings`] (`force_N`, `radius_mm`, `geometry`, …).
#[pyfunction]
fn hertz_rows(settings: &str) -> PyResult<String> {
    let s: HertzSettings = from_keywords(settings).map_err(py_err)?;
    let (e_star, rows) = s.run().map_err(py_err)?;
    to_json(&serde_json::json!({"effective_modulus_pa": e_star, "rows": rows}))
}

/// The virtual tribometer: a study's plan (default: the bundled example study)
/// simulated into recordings and `ground_truth.csv`: JSON summary. `settings` is JSON of the
/// library's [`SynthSettings`] (`out`, `study`, `format`, `seed`, the plan's overrides).
#[pyfunction]
fn synth(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: SynthSettings = from_keywords(settings).map_err(py_err)?;
    to_json(&run_interruptible(py, || s.run())?)
}

/// One recording of any supported rig format, read through a channel map (`channels`: JSON
/// of the study's `[recording]` settings; default: the study's, else found by name): a dict
/// of NumPy arrays (time_s, normal_force_N, tangential_force_N and, where recorded,
/// radial_force_N, trigger_V, step, spindle_speed_rpm or sliding_velocity_m_per_s,
/// track_radius_m) and "how_read", the reader's JSON report.
#[pyfunction]
#[pyo3(signature = (path, study = None, channels = None))]
fn read_recording<'py>(
    py: Python<'py>,
    path: PathBuf,
    study: Option<PathBuf>,
    channels: Option<&str>,
) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    use numpy::IntoPyArray;
    let rec = run_interruptible(py, || -> anyhow::Result<_> {
        let map = match channels {
            Some(c) => serde_json::from_str(c).map_err(|e| anyhow::anyhow!("channels: {e}"))?,
            None => Study::load_or_default(study.as_deref())?.recording,
        };
        Ok(greybox_recording::readers::read_recording(&path, &map)?)
    })?;
    let d = pyo3::types::PyDict::new(py);
    d.set_item("time_s", rec.time_s.into_pyarray(py))?;
    d.set_item("normal_force_N", rec.normal_n.into_pyarray(py))?;
    d.set_item("tangential_force_N", rec.tangential_n.into_pyarray(py))?;
    let optional = [
        ("radial_force_N", rec.radial_n),
        ("trigger_V", rec.trigger_v),
        ("step", rec.step),
        ("track_radius_m", rec.track_radius_m),
        ("cof", rec.cof),
    ];
    for (name, v) in optional {
        if let Some(v) = v {
            d.set_item(name, v.into_pyarray(py))?;
        }
    }
    match rec.speed {
        Some(greybox_recording::SpeedTrace::SpindleRpm(v)) => {
            d.set_item("spindle_speed_rpm", v.into_pyarray(py))?
        }
        Some(greybox_recording::SpeedTrace::SlidingMPerS(v)) => {
            d.set_item("sliding_velocity_m_per_s", v.into_pyarray(py))?
        }
        None => {}
    }
    d.set_item("how_read", to_json(&rec.provenance)?)?;
    Ok(d)
}

/// Identify a campaign's recordings (files or directories, any supported rig format) into
/// a dataset CSV: JSON summary. `settings` is JSON of the library's [`IdentifySettings`]
/// (the command line's flags by their field names, its defaults: no study unless one is
/// given, a study's plan used when it has one).
#[pyfunction]
fn identify(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: IdentifySettings = from_keywords(settings).map_err(py_err)?;
    let r = run_interruptible(py, || -> anyhow::Result<_> {
        let (study, options) = s.prepare()?;
        identify_campaign(&study, &options, None)
    });
    to_json(&r?.summary)
}

/// The ploughing correction of a dataset (cof_adhesive column added): JSON of the
/// correction. `settings` is JSON of the library's adhesive settings (`data`, `out`,
/// `method`, `pin_radius_mm`, `track_width`, `track_widths_csv`, `sim_*`), the command
/// line's flags by their field names.
#[pyfunction]
fn ploughing_correction(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: AdhesiveSettings = from_keywords(settings).map_err(py_err)?;
    let o = s.options().map_err(py_err)?;
    let (_, correction) = run_interruptible(py, || adhesive(&o))?;
    to_json(&correction)
}

/// Press and slide a pin (plane strain): JSON of the result. `settings` is JSON of the
/// library's pin settings (`depth_um` or `track_width_um`, `pin_radius_mm`, `mu`, …),
/// `output` of its run output (`out`, `force`, `vtk_every`, `checkpoint_every`, `resume`).
#[pyfunction]
fn simulate_pin(py: Python<'_>, settings: &str, output: &str) -> PyResult<String> {
    let s: PinSettings = from_keywords(settings).map_err(py_err)?;
    let o: RunOutput = from_keywords(output).map_err(py_err)?;
    let setup = s.setup().map_err(py_err)?;
    to_json(&run_interruptible(py, || run_pin(&setup, &o))?)
}

/// The restart loop with an external FE engine: JSON of the coupling result. `settings` is
/// JSON of the library's couple settings (`engine`, `deck`, `segment`, `law`, `units`, …).
#[pyfunction]
fn couple(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: CoupleSettings = from_keywords(settings).map_err(py_err)?;
    let o = s.options().map_err(py_err)?;
    to_json(&run_interruptible(py, || {
        greybox_pipeline::couple::couple(&o)
    })?)
}

/// The article's learning protocol on a dataset: JSON {report, outputs, warnings}.
/// `settings` is JSON of the library's [`FitSettings`] (`data`, `out`, `target`,
/// `features`, `study`, `families`, `folds`, `bootstrap`, `mlp_hidden`, …: the command
/// line's flags by their field names and defaults).
#[pyfunction]
fn fit_models(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: FitSettings = from_keywords(settings).map_err(py_err)?;
    let o = s.options().map_err(py_err)?;
    let r = run_interruptible(py, || fit(&o))?;
    to_json(&serde_json::json!({
        "report": r.report,
        "outputs": r.outputs,
        "warnings": r.warnings,
    }))
}

/// Write a grey-box law file around a fitted model: the law's JSON. `settings` is JSON of
/// the library's [`GreyBoxSettings`] (`model`, `out`, `blend_fraction`, `mu_min`, `mu_max`,
/// `no_clamp`, `shear_cap_k_MPa`, `study`), the defaults of `greybox law`.
#[pyfunction]
fn grey_box_law(settings: &str) -> PyResult<String> {
    let s: GreyBoxSettings = from_keywords(settings).map_err(py_err)?;
    let law = s.write().map_err(py_err)?;
    serde_json::to_string_pretty(&law).map_err(py_err)
}

/// Export a law (law, model or table file) as `format` (abaqus, deform, lsdyna, csv, table):
/// JSON of the export report. `options` is JSON of the overrides ([`ExportOverrides`]: the
/// library's option names, SI); every option left out keeps the library's default, the same
/// as the command line's.
#[pyfunction]
#[pyo3(signature = (law, format, out, options = "{}"))]
fn export_table(
    py: Python<'_>,
    law: PathBuf,
    format: &str,
    out: PathBuf,
    options: &str,
) -> PyResult<String> {
    let format: ExportFormat = format.parse().map_err(py_err)?;
    let overrides = ExportOverrides::from_json(options).map_err(py_err)?;
    let o = ExportOptions::new(law, format, out)
        .overridden(&overrides)
        .map_err(py_err)?;
    to_json(&run_interruptible(py, || export(&o))?)
}

/// Friction windows from a coated tool mesh, written into `out`: JSON {windows, nodes,
/// elements}. `settings` is JSON of the library's [`WindowsSettings`].
#[pyfunction]
fn windows(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: WindowsSettings = from_keywords(settings).map_err(py_err)?;
    let (mesh, w) = run_interruptible(py, || s.run())?;
    to_json(&serde_json::json!({
        "windows": w,
        "nodes": mesh.nodes.len(),
        "elements": mesh.elements.len(),
    }))
}

/// Johnson–Cook A, B, n, m from flow curves: JSON of the fit. `settings` is JSON of the
/// library's [`FlowCurveSettings`].
#[pyfunction]
fn fit_flow_curves(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: FlowCurveSettings = from_keywords(settings).map_err(py_err)?;
    to_json(&run_interruptible(py, || s.run())?)
}

/// Johnson–Cook C from a measured cutting force: JSON of the search. `settings` is JSON of
/// the library's [`RateSensitivitySettings`].
#[pyfunction]
fn fit_rate_sensitivity(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: RateSensitivitySettings = from_keywords(settings).map_err(py_err)?;
    let o = s.options().map_err(py_err)?;
    to_json(&run_interruptible(py, || {
        greybox_pipeline::material::fit_rate_sensitivity(&o)
    })?)
}

/// The rig profiles greybox knows, as `greybox identify --list-rigs` prints them: JSON
/// [{name, vendor, mode, verified_against}].
#[pyfunction]
fn rig_profiles() -> PyResult<String> {
    let rows: Vec<_> = greybox_recording::profiles::PROFILES
        .iter()
        .map(|p| {
            serde_json::json!({
                "name": p.name,
                "vendor": p.vendor,
                "mode": p.mode.name(),
                "verified_against": p.verified_against,
            })
        })
        .collect();
    to_json(&rows)
}

/// The library's settings of `stage` with their defaults, as JSON (every key the stage's
/// function takes: the fields of its settings type, the command line's flags by name).
#[pyfunction]
fn settings_defaults(stage: &str) -> PyResult<String> {
    match stage {
        "output" => to_json(&RunOutput::default()),
        "validate" => to_json(&ValidateSettings::default()),
        "report" => to_json(&greybox_report::report::ReportOptions::default()),
        other => match greybox_pipeline::settings::stage_settings(other) {
            Ok(s) => to_json(&(s.defaults)()),
            Err(e) => Err(py_err(
                e.context("expected also output, validate or report"),
            )),
        },
    }
}

/// The library's default export options of `format` as JSON (the keys `export_table`
/// takes, SI).
#[pyfunction]
fn export_defaults(format: &str) -> PyResult<String> {
    let format: ExportFormat = format.parse().map_err(py_err)?;
    to_json(&ExportOverrides::defaults_of(format))
}

/// Run the orthogonal-cutting simulation: `settings` is JSON of the library's
/// [`CutSettings`] (`config`, `law`, `fraction`, as `greybox simulate cutting`), `output` of
/// its [`RunOutput`] (`out`, `force`, `vtk_every`, `checkpoint_every`, `resume`, `frames`),
/// as for the pin. JSON summary; forces.csv and contact_profile.csv are in the output
/// directory.
#[pyfunction]
fn simulate_cut(py: Python<'_>, settings: &str, output: &str) -> PyResult<String> {
    let s: CutSettings = from_keywords(settings).map_err(py_err)?;
    let o: RunOutput = from_keywords(output).map_err(py_err)?;
    to_json(&run_interruptible(py, || s.run(&o))?)
}

/// Write the study directory's self-contained report page (default `study_dir/report.html`):
/// JSON summary (path, bytes, sections, figures, warnings). `settings` is JSON of the
/// library's [`greybox_report::report::ReportOptions`] (`study_dir`, `out` and the caps:
/// `max_file_bytes`, `max_svg_bytes`, `max_header_bytes`, `max_entries`, `max_depth`,
/// `max_page_bytes`), the command line's flags by their field names.
#[pyfunction]
fn report(py: Python<'_>, settings: &str) -> PyResult<String> {
    let o: greybox_report::report::ReportOptions = from_keywords(settings).map_err(py_err)?;
    to_json(&run_interruptible(py, || {
        greybox_report::report::report(&o)
    })?)
}

/// The validation suite, as `greybox bench validate`: JSON {validation, files}. `settings`
/// is JSON of the library's [`ValidateSettings`] (`suite`, `out`, `only`, `tool`,
/// `fraction`, `force`, `executor`, `jobs`, `poll_s`); with an executor, the cases run by the
/// `greybox` program on PATH.
#[pyfunction]
fn validate(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: ValidateSettings = from_keywords(settings).map_err(py_err)?;
    let program = || greybox_sweep::launch::program_on_path("greybox");
    let (v, files) = run_interruptible(py, || s.run(&program))?;
    to_json(&serde_json::json!({"validation": v, "files": files}))
}
