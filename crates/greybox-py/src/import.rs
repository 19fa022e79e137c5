//! Models trained elsewhere: XGBoost files and scikit-learn exports (built by the Python
//! layer from the fitted estimator) into greybox models.

use crate::laws::Model;
use crate::{py_err, run_interruptible};
use greybox_contact::PinContact;
use greybox_core::dataset::PressureConvention;
use greybox_core::units::mpa_to_pa;
use greybox_import::{Calibration, Domain, ImportOptions};
use greybox_model::modelfile::{FeatureRange, ForcePressure};
use greybox_pipeline::import::{import_inputs, with_import_provenance, ContactSpec, CONTACT_KEYS};
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

/// The pin contact stated as `contact=` in Python: the `[contact]` keys as JSON, over a
/// study's `[contact]` table.
fn contact(json: Option<&str>, study: Option<PathBuf>) -> PyResult<Option<PinContact>> {
    let fields = match json {
        Some(text) => match serde_json::from_str(text).map_err(py_err)? {
            serde_json::Value::Object(m) => m,
            _ => {
                return Err(py_err(anyhow::anyhow!(
                "contact: expected a dict of the study's [contact] keys ({}) or a study TOML path",
                CONTACT_KEYS.join(", ")
            )))
            }
        },
        None => serde_json::Map::new(),
    };
    ContactSpec { study, fields }.resolve().map_err(py_err)
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

/// Import a model: `source` is a file path (XGBoost JSON/UBJSON, a greybox-sklearn JSON) or,
/// with `is_json`, the JSON text of a scikit-learn export. The domain comes from `domain`
/// ((min, max) per feature) or `x_train`; `x_cal`/`y_cal` give the split-conformal interval.
#[pyfunction]
/// `contact_json` (a JSON object of the study's `[contact]` keys) and `contact_study` (a study
/// TOML whose `[contact]` table it overrides) state the pin contact of a model trained on a
/// normal force.
/// `training_data` is a CSV of the training rows (as `greybox import --training-data`: a
/// greybox friction dataset also gives its contact); `training_contact` the friction
/// dataset columns (pressure_convention, hertz_pressure_MPa, normal_force_N) of `x_train`'s
/// table, from which its contact is taken the same way.
#[pyo3(signature = (source, features = None, target = None, domain = None, x_train = None, x_cal = None, y_cal = None, coverage = None, is_json = false, contact_json = None, contact_study = None, training_data = None, training_contact = None))]
#[allow(clippy::too_many_arguments)]
fn import_model(
    py: Python<'_>,
    source: &str,
    features: Option<Vec<String>>,
    target: Option<String>,
    domain: Option<Vec<(f64, f64)>>,
    x_train: Option<PyReadonlyArray2<'_, f64>>,
    x_cal: Option<PyReadonlyArray2<'_, f64>>,
    y_cal: Option<PyReadonlyArray1<'_, f64>>,
    coverage: Option<f64>,
    is_json: bool,
    contact_json: Option<&str>,
    contact_study: Option<PathBuf>,
    training_data: Option<PathBuf>,
    training_contact: Option<(Vec<String>, Vec<f64>, Vec<f64>)>,
) -> PyResult<Model> {
    let contact = contact(contact_json, contact_study.clone())?;
    let domain = match (domain, &x_train, training_data) {
        (Some(d), None, None) => Domain::Stated(
            d.into_iter()
                .map(|(min, max)| FeatureRange { min, max })
                .collect(),
        ),
        (None, Some(x), None) => Domain::Rows {
            x: rows(x),
            force_to_pressure: training_contact.and_then(force_to_pressure),
        },
        (None, None, Some(path)) => Domain::Data(path),
        _ => {
            return Err(py_err(anyhow::anyhow!(
                "state the training domain, one way: domain=[(min, max), …], the training rows X_train, or the training_data CSV"
            )))
        }
    };
    let calibration = match (&x_cal, &y_cal) {
        (Some(x), Some(y)) => Some(Calibration::Rows(rows(x), y.as_slice()?.to_vec())),
        (None, None) => None,
        _ => {
            return Err(py_err(anyhow::anyhow!(
                "calibration needs both x_cal and y_cal"
            )))
        }
    };
    let opts = ImportOptions {
        features,
        target: target.unwrap_or_else(|| greybox_import::DEFAULT_TARGET.into()),
        domain,
        calibration,
        coverage: coverage.unwrap_or(greybox_import::DEFAULT_COVERAGE),
        contact,
    };
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
