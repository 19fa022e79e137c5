//! The pipeline's stages as Python functions: file paths and plain options in, a JSON report
//! out (the Python layer turns it into a dict and reads the tables it wrote). Each releases
//! the GIL while it works.

use crate::{py_err, run_interruptible, to_json};
use greybox_core::dataset::PressureConvention;
use greybox_pipeline::adhesive::adhesive;
use greybox_pipeline::export::{export, ExportFormat, ExportOptions, ExportOverrides};
use greybox_pipeline::fit::{fit, FitOptions};
use greybox_pipeline::hertz::{hertz, Geometry, HertzOptions};
use greybox_pipeline::identify::{identify_campaign, IdentifyOptions};
use greybox_pipeline::settings::adhesive::AdhesiveSettings;
use greybox_pipeline::settings::couple::CoupleSettings;
use greybox_pipeline::settings::from_json;
use greybox_pipeline::settings::identify::IdentifySettings;
use greybox_pipeline::settings::pin::PinSettings;
use greybox_pipeline::simulate::{read_cutting_setup, run_cut, run_pin, RunOutput};
use greybox_pipeline::study::Study;
use greybox_pipeline::synth::synth as synth_campaign;
use greybox_tribo::plan::{PinCount, VelocityCount};
use greybox_tribo::readers::RecordingFormat;
use numpy::PyReadonlyArray1;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(hertz_rows, m)?)?;
    m.add_function(wrap_pyfunction!(synth, m)?)?;
    m.add_function(wrap_pyfunction!(read_recording, m)?)?;
    m.add_function(wrap_pyfunction!(identify, m)?)?;
    m.add_function(wrap_pyfunction!(ploughing_correction, m)?)?;
    m.add_function(wrap_pyfunction!(fit_models, m)?)?;
    m.add_function(wrap_pyfunction!(grey_box_law, m)?)?;
    m.add_function(wrap_pyfunction!(export_table, m)?)?;
    m.add_function(wrap_pyfunction!(export_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_cut, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_pin, m)?)?;
    m.add_function(wrap_pyfunction!(couple, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    Ok(())
}

/// The study file, or the bundled example study (the article's campaign), with the plan's
/// numbers of loads and velocities overridden where given.
fn study_or_example(
    path: Option<&std::path::Path>,
    normal_force_count: Option<usize>,
    velocity_count: Option<usize>,
) -> anyhow::Result<Study> {
    let mut s = match path {
        Some(p) => Study::load(p)?,
        None => Study::parse(
            greybox_pipeline::study::DEMO_STUDY,
            "the bundled example study",
        )?,
    };
    if let Some(n) = normal_force_count {
        s.plan.normal_force_count =
            PinCount::of_usize(n, "normal_force_count").map_err(anyhow::Error::msg)?;
    }
    if let Some(n) = velocity_count {
        s.plan.velocity_count =
            VelocityCount::of_usize(n, "velocity_count").map_err(anyhow::Error::msg)?;
    }
    Ok(s)
}

fn convention(name: &str) -> anyhow::Result<PressureConvention> {
    PressureConvention::parse(name).ok_or_else(|| {
        anyhow::anyhow!(
            "convention '{name}': expected one of {}",
            PressureConvention::ALL.map(|c| c.name()).join(", ")
        )
    })
}

/// Hertz contact of a sphere (or a cylinder of `length_mm`) on a flat for each normal force:
/// JSON {"effective_modulus_pa", "rows": [{force_n, contact_half_width_mm, max_pressure_mpa,
/// mean_pressure_mpa, approach_um, convention, convention_pressure_mpa}]}.
#[pyfunction]
#[pyo3(signature = (normal_force_n, radius_mm, e1_gpa, nu1, e2_gpa, nu2, length_mm = None, convention = "textbook-max"))]
#[allow(clippy::too_many_arguments)]
fn hertz_rows(
    normal_force_n: PyReadonlyArray1<'_, f64>,
    radius_mm: f64,
    e1_gpa: f64,
    nu1: f64,
    e2_gpa: f64,
    nu2: f64,
    length_mm: Option<f64>,
    convention: &str,
) -> PyResult<String> {
    let o = HertzOptions {
        geometry: match length_mm {
            Some(length_mm) => Geometry::Cylinder { length_mm },
            None => Geometry::Sphere,
        },
        radius_mm,
        e1_gpa,
        nu1,
        e2_gpa,
        nu2,
        convention: self::convention(convention).map_err(py_err)?,
    };
    let (e_star, rows) = hertz(&o, normal_force_n.as_slice()?).map_err(py_err)?;
    to_json(&serde_json::json!({"effective_modulus_pa": e_star, "rows": rows}))
}

/// The virtual tribometer: the study's plan (default: the bundled example study, optionally
/// with fewer loads and velocities) simulated into recordings and `ground_truth.csv` in
/// `out`: JSON summary.
#[pyfunction]
#[pyo3(signature = (out, study = None, formats = vec!["csv".to_string()], normal_force_count = None, velocity_count = None, force = false))]
fn synth(
    py: Python<'_>,
    out: PathBuf,
    study: Option<PathBuf>,
    formats: Vec<String>,
    normal_force_count: Option<usize>,
    velocity_count: Option<usize>,
    force: bool,
) -> PyResult<String> {
    let formats = formats
        .iter()
        .map(|f| match f.as_str() {
            "csv" => Ok(RecordingFormat::Csv),
            "tdms" => Ok(RecordingFormat::Tdms),
            o => Err(py_err(anyhow::anyhow!(
                "format '{o}': expected csv or tdms"
            ))),
        })
        .collect::<PyResult<Vec<_>>>()?;
    let r = run_interruptible(py, || -> anyhow::Result<_> {
        let s = study_or_example(study.as_deref(), normal_force_count, velocity_count)?;
        let inputs: Vec<(&str, &std::path::Path)> =
            study.iter().map(|p| ("study", p.as_path())).collect();
        synth_campaign(&s, &formats, &out, force, &inputs)
    });
    to_json(&r?)
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
            None => study_or_example(study.as_deref(), None, None)?.recording,
        };
        Ok(greybox_tribo::readers::read_recording(&path, &map)?)
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
        Some(greybox_tribo::recording::SpeedTrace::SpindleRpm(v)) => {
            d.set_item("spindle_speed_rpm", v.into_pyarray(py))?
        }
        Some(greybox_tribo::recording::SpeedTrace::SlidingMPerS(v)) => {
            d.set_item("sliding_velocity_m_per_s", v.into_pyarray(py))?
        }
        None => {}
    }
    d.set_item("how_read", to_json(&rec.provenance)?)?;
    Ok(d)
}

/// Identify a campaign's recordings (files or directories, any supported rig format) into
/// the dataset CSV `dataset`: JSON summary. `study` is a study TOML (default: the bundled
/// example study, its plan's counts overridable); `use_plan` matches segments to its plan
/// instead of taking loads and velocities from the recordings. `settings`: JSON of the
/// library's [`IdentifySettings`] (the command line's flags by their library names).
/// `channels`: JSON of the `[recording]` settings (roles, `rig`, `constant_normal_n`, …),
/// replacing the study's; `settings` apply on top.
#[pyfunction]
#[pyo3(signature = (recordings, dataset, study = None, use_plan = false, truth = None, track_radii_mm = Vec::new(), normal_force_count = None, velocity_count = None, settings = None, channels = None))]
#[allow(clippy::too_many_arguments)]
fn identify(
    py: Python<'_>,
    recordings: Vec<PathBuf>,
    dataset: PathBuf,
    study: Option<PathBuf>,
    use_plan: bool,
    truth: Option<PathBuf>,
    track_radii_mm: Vec<f64>,
    normal_force_count: Option<usize>,
    velocity_count: Option<usize>,
    settings: Option<&str>,
    channels: Option<&str>,
) -> PyResult<String> {
    let r = run_interruptible(py, || -> anyhow::Result<_> {
        let mut s = study_or_example(study.as_deref(), normal_force_count, velocity_count)?;
        if let Some(c) = channels {
            s.recording = serde_json::from_str(c).map_err(|e| anyhow::anyhow!("channels: {e}"))?;
        }
        if let Some(settings) = settings {
            IdentifySettings::from_json(settings)?.apply(&mut s)?;
        }
        let mut o = IdentifyOptions::new(recordings, dataset);
        if use_plan {
            o = o.with_plan(s.plan.build()?);
        }
        o.truth = truth;
        o.track_radii_mm = track_radii_mm;
        if let Some(p) = &study {
            o.side_inputs.push(("study".into(), p.clone()));
        }
        identify_campaign(&s, &o, None)
    });
    to_json(&r?.summary)
}

/// The ploughing correction of a dataset (cof_adhesive column added): JSON of the
/// correction. `settings` is JSON of the library's adhesive settings (`data`, `out`,
/// `method`, `pin_radius_mm`, `track_width`, `track_widths_csv`, `sim_*`), the command
/// line's flags by their field names.
#[pyfunction]
fn ploughing_correction(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: AdhesiveSettings = from_json("adhesive", settings).map_err(py_err)?;
    let o = s.options().map_err(py_err)?;
    let (_, correction) = run_interruptible(py, || adhesive(&o))?;
    to_json(&correction)
}

/// Press and slide a pin (plane strain): JSON of the result. `settings` is JSON of the
/// library's pin settings (`depth_um` or `track_width_um`, `pin_radius_mm`, `mu`, …),
/// `output` of its run output (`out`, `force`, `vtk_every`, `checkpoint_every`, `resume`).
#[pyfunction]
fn simulate_pin(py: Python<'_>, settings: &str, output: &str) -> PyResult<String> {
    let s: PinSettings = from_json("pin", settings).map_err(py_err)?;
    let o: RunOutput = from_json("output", output).map_err(py_err)?;
    let setup = s.setup().map_err(py_err)?;
    to_json(&run_interruptible(py, || run_pin(&setup, &o))?)
}

/// The restart loop with an external FE engine: JSON of the coupling result. `settings` is
/// JSON of the library's couple settings (`engine`, `deck`, `segment`, `law`, `units`, …).
#[pyfunction]
fn couple(py: Python<'_>, settings: &str) -> PyResult<String> {
    let s: CoupleSettings = from_json("couple", settings).map_err(py_err)?;
    let o = s.options().map_err(py_err)?;
    to_json(&run_interruptible(py, || {
        greybox_pipeline::couple::couple(&o)
    })?)
}

/// The article's learning protocol on a dataset: JSON {report, outputs, warnings}. `config`
/// is JSON of the `[fit]` settings (families, folds, seed, grids …; absent: the article's).
/// `target` and `features` default as on the command line (the library's defaults).
#[pyfunction]
#[pyo3(signature = (data, out, target = None, features = None, config = None, force = false))]
fn fit_models(
    py: Python<'_>,
    data: PathBuf,
    out: PathBuf,
    target: Option<String>,
    features: Option<Vec<String>>,
    config: Option<&str>,
    force: bool,
) -> PyResult<String> {
    let target = match target {
        Some(t) => t,
        None => greybox_pipeline::fit::default_target(&data).map_err(py_err)?,
    };
    let mut o = FitOptions::article(data, &target, out);
    if let Some(f) = features {
        o.features = f;
    }
    o.force = force;
    if let Some(c) = config {
        o.config = greybox_pipeline::settings::from_json("fit config", c).map_err(py_err)?;
    }
    let r = run_interruptible(py, || fit(&o))?;
    to_json(&serde_json::json!({
        "report": r.report,
        "outputs": r.outputs,
        "warnings": r.warnings,
    }))
}

/// Write the grey-box law file `out` around the model file `model` (as the law file will
/// refer to it): the model inside its domain, a power law fitted to its training data
/// outside, blended over `blend_fraction` of each range, μ clamped and (optionally) the
/// shear stress capped at k. Returns the law file's JSON.
#[pyfunction]
#[pyo3(signature = (model, out, blend_fraction = 0.1, clamp = Some((0.05, 1.0)), shear_cap_k_mpa = None))]
fn grey_box_law(
    model: PathBuf,
    out: PathBuf,
    blend_fraction: f64,
    clamp: Option<(f64, f64)>,
    shear_cap_k_mpa: Option<f64>,
) -> PyResult<String> {
    let o = greybox_pipeline::law::GreyBoxOptions {
        blend_fraction,
        shear_cap_k_mpa,
        clamp,
    };
    let model_path = model.clone();
    let law = greybox_pipeline::law::grey_box_law(model, None, &o);
    let base = out.parent().unwrap_or(std::path::Path::new("."));
    // the law file must not replace the model it refers to (resolved as the law will)
    greybox_core::outputs::check_file_output(&out, "out", &[("model", &base.join(&model_path))])
        .map_err(py_err)?;
    law.build(base).map_err(py_err)?;
    greybox_pipeline::law::write_law(&out, &law).map_err(py_err)?;
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

/// The library's default export options of `format` as JSON (the keys `export_table`
/// takes, SI).
#[pyfunction]
fn export_defaults(format: &str) -> PyResult<String> {
    let format: ExportFormat = format.parse().map_err(py_err)?;
    to_json(&ExportOverrides::defaults_of(format))
}

/// Run the orthogonal-cutting simulation of a set-up TOML into `out` (optionally with the
/// friction law file `law` instead of the set-up's): JSON summary; forces.csv and
/// contact_profile.csv are in `out`.
#[pyfunction]
#[pyo3(signature = (setup, out, law = None, fraction = 1.0, force = false, frames = 0))]
fn simulate_cut(
    py: Python<'_>,
    setup: PathBuf,
    out: PathBuf,
    law: Option<PathBuf>,
    fraction: f64,
    force: bool,
    frames: usize,
) -> PyResult<String> {
    let summary = run_interruptible(py, || -> anyhow::Result<_> {
        let mut case = read_cutting_setup(&setup)?;
        if let Some(l) = law {
            case.law = Arc::from(greybox_friction::spec::load_law(&l)?);
            case.law_source = l.display().to_string();
            case.inputs.push(("law", l));
        }
        let mut o = RunOutput::to(out);
        o.force = force;
        o.frames = greybox_pipeline::simulate::Frames::of_usize(frames, "frames")
            .map_err(anyhow::Error::msg)?;
        run_cut(&case, fraction, &o)
    });
    to_json(&summary?)
}

/// Write the study directory's self-contained report page (default `study_dir/report.html`):
/// JSON summary (path, bytes, sections, figures, warnings).
#[pyfunction]
#[pyo3(signature = (study_dir, out = None))]
fn report(py: Python<'_>, study_dir: PathBuf, out: Option<PathBuf>) -> PyResult<String> {
    let mut o = greybox_pipeline::report::ReportOptions::new(study_dir);
    o.out = out;
    to_json(&run_interruptible(py, || {
        greybox_pipeline::report::report(&o)
    })?)
}
