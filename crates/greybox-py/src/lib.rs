//! The native module of greybox's Python package (`greybox._native`): PyO3 bindings over the
//! `greybox-pipeline` workflows and the model/law types. The Python layer (`python/greybox`)
//! turns its JSON reports into dicts and its tables into NumPy arrays or pandas DataFrames.
//!
//! Every call that reads files, fits or simulates releases the GIL. Errors arrive as
//! `greybox.GreyboxError` (a `ValueError`) carrying the same message the command line prints
//! after `error:`.

mod import;
mod laws;
mod stages;

use pyo3::prelude::*;

pyo3::create_exception!(
    greybox,
    GreyboxError,
    pyo3::exceptions::PyValueError,
    "An error of greybox: bad input (naming the file, line or field), or a failed stage."
);

/// A greybox error as a Python exception, with the command line's message (causes joined).
pub(crate) fn py_err(e: impl Into<anyhow::Error>) -> PyErr {
    GreyboxError::new_err(format!("{:#}", e.into()))
}

/// JSON of a serialisable value (for the Python layer to `json.loads`).
pub(crate) fn to_json(v: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string(v).map_err(py_err)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("GreyboxError", m.py().get_type::<GreyboxError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<laws::Model>()?;
    m.add_class::<laws::Law>()?;
    stages::register(m)?;
    import::register(m)?;
    Ok(())
}
