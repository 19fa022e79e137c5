//! Model files and friction laws, evaluated on NumPy arrays.

use crate::{py_err, run_sequential, to_json};
use greybox_core::law::{Range, ValidityDomain};
use greybox_core::ContactState;
use greybox_core::FrictionLaw;
use greybox_friction::learned::LearnedLaw;
use greybox_model::modelfile::{DomainPolicy, ModelFile};
use greybox_pipeline::settings::from_keywords;
use greybox_pipeline::settings::predict::DomainCheck;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use std::path::PathBuf;

/// μ and the in-domain flag per state, and the warning for states outside the validity
/// domain (`None` when all lie inside).
type LawArrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
    Option<String>,
);

/// Value, low, high and the in-domain flag per point, and the warning for points outside the
/// training domain (`None` when all lie inside; the Python layer emits it as a
/// `greybox.DomainWarning`).
type Arrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
    Option<String>,
);

/// The domain check of a call: JSON of the library's [`DomainCheck`] (`outside`, `margin`;
/// a key not given takes the library's default), checked.
fn domain_check(check: &str) -> PyResult<DomainCheck> {
    from_keywords::<DomainCheck>(check)
        .and_then(DomainCheck::checked)
        .map_err(py_err)
}

/// The contact states of equally long pressure, velocity (and temperature) arrays.
fn states(p: &[f64], v: &[f64], t: Option<&[f64]>) -> anyhow::Result<Vec<ContactState>> {
    if v.len() != p.len() || t.is_some_and(|t| t.len() != p.len()) {
        anyhow::bail!(
            "pressure_pa, velocity_m_s (and temperature_k) must have equal lengths, got {}, {}{}",
            p.len(),
            v.len(),
            t.map(|t| format!(", {}", t.len())).unwrap_or_default()
        );
    }
    greybox_core::contact::check_states(p, v, t).map_err(|e| anyhow::anyhow!(e))?;
    (0..p.len())
        .map(|i| {
            let s = ContactState {
                pressure_pa: p[i],
                sliding_velocity_m_s: v[i],
                temperature_k: t.map_or(ContactState::ROOM_TEMPERATURE_K, |t| t[i]),
            };
            if !(s.pressure_pa.is_finite()
                && s.sliding_velocity_m_s.is_finite()
                && s.temperature_k.is_finite())
            {
                anyhow::bail!("point {i} is not finite: {s:?}");
            }
            Ok(s)
        })
        .collect()
}

/// A contact variable of a validity domain: its name, range (if the law has one), value in a
/// state and SI unit.
type Axis = (
    &'static str,
    Option<Range>,
    fn(&ContactState) -> f64,
    &'static str,
);

/// How many of the states lie outside the law's validity domain, and on which contact
/// variables (with the domain's range); `None` when all lie inside.
fn outside_validity(d: &ValidityDomain, s: &[ContactState], inside: &[bool]) -> Option<String> {
    let outside = inside.iter().filter(|i| !**i).count();
    if outside == 0 {
        return None;
    }
    let axes: [Axis; 3] = [
        ("pressure", Some(d.pressure_pa), |s| s.pressure_pa, "Pa"),
        (
            "sliding velocity",
            Some(d.sliding_velocity_m_s),
            |s| s.sliding_velocity_m_s,
            "m/s",
        ),
        ("temperature", d.temperature_k, |s| s.temperature_k, "K"),
    ];
    let on: Vec<String> = axes
        .iter()
        .filter_map(|(name, r, get, unit)| {
            let r = (*r)?;
            s.iter()
                .any(|s| !r.contains(get(s)))
                .then(|| format!("{name} (valid {:.6e}..{:.6e} {unit})", r.min, r.max))
        })
        .collect();
    Some(format!(
        "{outside} of {} states lie outside the law's validity domain on {}: μ there is an extrapolation",
        s.len(),
        on.join(", ")
    ))
}

/// A greybox model file (from `greybox fit`, `greybox import` or `from_sklearn`).
#[pyclass(module = "greybox._native", frozen)]
pub struct Model {
    pub(crate) file: ModelFile,
}

impl Model {
    /// Predictions with interval and domain flag for feature rows.
    fn predict_rows<'py>(
        &self,
        py: Python<'py>,
        rows: Vec<Vec<f64>>,
        check: DomainCheck,
    ) -> PyResult<Arrays<'py>> {
        let DomainCheck { outside, margin } = check;
        let out = run_sequential(py, || {
            Ok(rows
                .iter()
                .map(|x| self.file.predict(x, outside, margin))
                .collect::<greybox_core::Result<Vec<_>>>()?)
        })?;
        let warning = self
            .file
            .outside_domain(rows.iter().map(|r| r.as_slice()), margin)
            .map(|o| o.to_string());
        Ok((
            out.iter()
                .map(|p| p.value)
                .collect::<Vec<_>>()
                .into_pyarray(py),
            out.iter()
                .map(|p| p.low)
                .collect::<Vec<_>>()
                .into_pyarray(py),
            out.iter()
                .map(|p| p.high)
                .collect::<Vec<_>>()
                .into_pyarray(py),
            out.iter()
                .map(|p| p.in_domain)
                .collect::<Vec<_>>()
                .into_pyarray(py),
            warning,
        ))
    }
}

#[pymethods]
impl Model {
    /// Load and verify a model file (schema, content hash, structure).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let file = run_sequential(py, || Ok(ModelFile::load(&path)?))?;
        Ok(Model { file })
    }

    /// A model from the text of a model file.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Self> {
        Ok(Model {
            file: ModelFile::parse(text, "model JSON").map_err(py_err)?,
        })
    }

    /// The model file's JSON text.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string_pretty(&self.file).map_err(py_err)
    }

    /// Write the model file (atomically).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        self.file.save(&path).map_err(py_err)
    }

    #[getter]
    fn family(&self) -> &'static str {
        self.file.family.name()
    }
    #[getter]
    fn features(&self) -> Vec<String> {
        self.file.features.iter().map(|f| f.name.clone()).collect()
    }
    #[getter]
    fn units(&self) -> Vec<String> {
        self.file.features.iter().map(|f| f.unit.clone()).collect()
    }
    #[getter]
    fn target(&self) -> String {
        self.file.target.name.clone()
    }
    /// Per feature, (min, max) of the training data.
    #[getter]
    fn training_domain(&self) -> Vec<(f64, f64)> {
        self.file
            .training_domain
            .iter()
            .map(|r| (r.min, r.max))
            .collect()
    }
    /// The prediction interval as JSON: coverage, half_width, method.
    #[getter]
    fn interval_json(&self) -> PyResult<String> {
        to_json(&self.file.prediction_interval)
    }
    /// Hyperparameters (or where an imported model came from) as JSON.
    #[getter]
    fn hyperparameters_json(&self) -> PyResult<String> {
        to_json(&self.file.hyperparameters)
    }
    #[getter]
    fn held_out_r2(&self) -> Option<f64> {
        self.file.held_out_r2
    }
    #[getter]
    fn content_hash(&self) -> String {
        self.file.content_hash.clone()
    }

    /// Predictions for an (n, n_features) array in the model's feature units: value, low,
    /// high, in_domain.
    /// `check` is JSON of the library's [`DomainCheck`] (`outside`, `margin`).
    #[pyo3(signature = (x, check = "{}"))]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray2<'py, f64>,
        check: &str,
    ) -> PyResult<Arrays<'py>> {
        let check = domain_check(check)?;
        let a = x.as_array();
        let n = self.file.features.len();
        if a.ncols() != n {
            return Err(py_err(anyhow::anyhow!(
                "x has {} columns; the model takes {n} features ({})",
                a.ncols(),
                self.features().join(", ")
            )));
        }
        let rows: Vec<Vec<f64>> = a.rows().into_iter().map(|r| r.to_vec()).collect();
        self.predict_rows(py, rows, check)
    }

    /// μ at contact states in SI (Pa, m/s, K), through the model's feature units (a normal
    /// force feature through the training contact's Hertz map): value, low, high, in_domain.
    /// `check` as in `predict`.
    #[pyo3(signature = (pressure_pa, velocity_m_s, temperature_k = None, check = "{}"))]
    fn mu<'py>(
        &self,
        py: Python<'py>,
        pressure_pa: PyReadonlyArray1<'py, f64>,
        velocity_m_s: PyReadonlyArray1<'py, f64>,
        temperature_k: Option<PyReadonlyArray1<'py, f64>>,
        check: &str,
    ) -> PyResult<Arrays<'py>> {
        let check = domain_check(check)?;
        let law = LearnedLaw::new(self.file.clone(), None).map_err(py_err)?;
        let t = temperature_k.as_ref().map(|t| t.as_slice()).transpose()?;
        let s = states(pressure_pa.as_slice()?, velocity_m_s.as_slice()?, t).map_err(py_err)?;
        let rows = s
            .iter()
            .map(|s| law.inputs.iter().map(|i| i.value(s)).collect())
            .collect();
        self.predict_rows(py, rows, check)
    }

    fn __repr__(&self) -> String {
        format!(
            "Model({} {}: {} → {})",
            self.file.family.name(),
            self.file.hyperparameters.label(),
            self.features().join(", "),
            self.file.target.name
        )
    }
}

/// Any greybox friction law: a law file, a model file or a table.
#[pyclass(module = "greybox._native", frozen)]
pub struct Law {
    law: Box<dyn FrictionLaw>,
}

#[pymethods]
impl Law {
    /// Load a law file (JSON), a model file or a surrogate table.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let law = run_sequential(py, || Ok(greybox_friction::spec::load_law(&path)?))?;
        Ok(Law { law })
    }

    /// The law of a model (its feature units mapped from SI).
    #[staticmethod]
    fn from_model(model: &Model) -> PyResult<Self> {
        let law = LearnedLaw::new(model.file.clone(), None).map_err(py_err)?;
        Ok(Law { law: Box::new(law) })
    }

    #[getter]
    fn name(&self) -> String {
        self.law.name()
    }

    /// The validity domain as JSON (pressure_pa, sliding_velocity_m_s, temperature_k ranges),
    /// or None.
    #[getter]
    fn domain_json(&self) -> PyResult<Option<String>> {
        self.law.domain().map(|d| to_json(&d)).transpose()
    }

    /// μ at contact states in SI (Pa, m/s, K), whether each lies in the validity domain, and
    /// the warning for those outside (`outside="refuse"`: an error instead).
    #[pyo3(signature = (pressure_pa, velocity_m_s, temperature_k = None, outside = None))]
    fn mu<'py>(
        &self,
        py: Python<'py>,
        pressure_pa: PyReadonlyArray1<'py, f64>,
        velocity_m_s: PyReadonlyArray1<'py, f64>,
        temperature_k: Option<PyReadonlyArray1<'py, f64>>,
        outside: Option<&str>,
    ) -> PyResult<LawArrays<'py>> {
        let policy = match outside {
            Some(o) => o.parse::<DomainPolicy>().map_err(py_err)?,
            None => DomainCheck::default().outside,
        };
        let t = temperature_k.as_ref().map(|t| t.as_slice()).transpose()?;
        let s = states(pressure_pa.as_slice()?, velocity_m_s.as_slice()?, t).map_err(py_err)?;
        let (mu, inside) = run_sequential(py, || {
            let d = self.law.domain();
            let mu: Vec<f64> = s.iter().map(|s| self.law.mu(s)).collect();
            let inside: Vec<bool> = s.iter().map(|s| d.is_none_or(|d| d.contains(s))).collect();
            Ok((mu, inside))
        })?;
        if let Some(i) = mu.iter().position(|m| !m.is_finite()) {
            return Err(py_err(anyhow::anyhow!(
                "the law gives μ = {} at point {i} ({:?})",
                mu[i],
                s[i]
            )));
        }
        let warning = self
            .law
            .domain()
            .and_then(|d| outside_validity(&d, &s, &inside));
        if let (Some(w), DomainPolicy::Refuse) = (&warning, policy) {
            return Err(py_err(anyhow::anyhow!("{w}")));
        }
        Ok((mu.into_pyarray(py), inside.into_pyarray(py), warning))
    }

    fn __repr__(&self) -> String {
        format!("Law({})", self.law.name())
    }
}

/// The files loading the law at `path` reads: the file itself first, then the model files
/// and tables it names (resolved against its folder). The Python layer keeps their bytes so
/// that a `Law` pickles (and is passed on) with its content, not a path to re-read later.
#[pyfunction]
pub fn law_files(py: Python<'_>, path: PathBuf) -> PyResult<Vec<PathBuf>> {
    run_sequential(py, || Ok(greybox_friction::spec::law_inputs(&path)?))
}
