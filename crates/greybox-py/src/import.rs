//! Models trained elsewhere: XGBoost files and scikit-learn exports (built by the Python
//! layer from the fitted estimator) into greybox models.

use crate::laws::Model;
use crate::{py_err, run_interruptible};
use greybox_core::dataset::PressureConvention;
use greybox_core::units::mpa_to_pa;
use greybox_model::modelfile::ForcePressure;
use greybox_pipeline::import::{import_inputs, with_import_provenance};
use greybox_pipeline::settings::from_keywords;
use greybox_pipeline::settings::import::{ImportRows, ImportSettings};
use numpy::{PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use std::path::PathBuf;

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(import_model, m)?)?;
    Ok(())
}

fn rows(x: &PyReadonlyArray2<'_, f64>) -> Vec<Vec<f64>> {
    x.as_array()
        .rows()
        .into_iter()
        .map(|r| r.to_vec())
        .collect()
}

/// The contact of a friction dataset's columns (pressure convention names, Hertz pressures
/// in MPa, normal forces in N), when they share one.
fn force_to_pressure(
    (conventions, pressure_mpa, force_n): (Vec<String>, Vec<f64>, Vec<f64>),
) -> Option<ForcePressure> {
    let rows: Option<Vec<_>> = conventions
        .iter()
        .zip(pressure_mpa.iter().zip(&force_n))
        .map(|(c, (p, f))| Some((PressureConvention::parse(c)?, mpa_to_pa(*p), *f)))
        .collect();
    ForcePressure::of_rows(&rows?)
}

/// Import a model: `source` is a file path (XGBoost JSON/UBJSON, ONNX, a greybox-sklearn
/// JSON) or, with `is_json`, the JSON text of a scikit-learn export. `settings` is JSON of
/// the library's [`ImportSettings`] (features, target, domain, training_data, calibration,
/// coverage, contact), as `greybox import` takes them; the rows are data beside it:
/// `x_train` (with `training_contact`, the friction dataset columns pressure_convention,
/// hertz_pressure_MPa, normal_force_N of its table, from which its contact is taken), and
/// `calibration_rows` (X_cal, y_cal) for the split-conformal interval.
#[pyfunction]
#[pyo3(signature = (source, is_json, settings, x_train = None, calibration_rows = None, training_contact = None))]
fn import_model(
    py: Python<'_>,
    source: &str,
    is_json: bool,
    settings: &str,
    x_train: Option<PyReadonlyArray2<'_, f64>>,
    calibration_rows: Option<(PyReadonlyArray2<'_, f64>, PyReadonlyArray1<'_, f64>)>,
    training_contact: Option<(Vec<String>, Vec<f64>, Vec<f64>)>,
) -> PyResult<Model> {
    let settings: ImportSettings = from_keywords(settings).map_err(py_err)?;
    let calibration = match &calibration_rows {
        Some((x, y)) => Some((rows(x), y.as_slice()?.to_vec())),
        None => None,
    };
    let data = ImportRows {
        training: x_train.as_ref().map(rows),
        training_contact: training_contact.and_then(force_to_pressure),
        calibration,
    };
    let opts = settings.options(data).map_err(py_err)?;
    let contact_study = settings.contact.study.clone();
    let source = source.to_string();
    let file = run_interruptible(py, || -> anyhow::Result<_> {
        let source_path = (!is_json).then(|| PathBuf::from(&source));
        let imported = match &source_path {
            Some(path) => greybox_import::read_model(path)?,
            None => {
                let v: serde_json::Value = serde_json::from_str(&source).map_err(|e| {
                    greybox_core::Error::invalid("scikit-learn export", e.to_string())
                })?;
                greybox_import::from_json(v, "scikit-learn export")?
            }
        };
        // the same provenance as `greybox import` records (the call and its inputs)
        let inputs = import_inputs(source_path.as_deref(), &opts, contact_study.as_deref());
        with_import_provenance(greybox_import::model_file(imported, &opts)?, &inputs)
    })?;
    Ok(Model { file })
}
