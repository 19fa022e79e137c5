//! The native module of greybox's Python package (`greybox._native`): PyO3 bindings over the
//! `greybox-pipeline` workflows and the model/law types. The Python layer (`python/greybox`)
//! turns its JSON reports into dicts and its tables into NumPy arrays or pandas DataFrames.
//!
//! Every call that reads files, fits or simulates releases the GIL and stays interruptible
//! with Ctrl-C ([`run_interruptible`]). Errors arrive as
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

/// The stack of the worker thread of [`run_interruptible`] (that of a main thread, as the
/// calls had when they ran on Python's own thread).
const WORKER_STACK_BYTES: usize = 8 << 20;

/// How often a waiting call looks for a pending signal (Ctrl-C).
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// Run `f` with the GIL released on a worker thread while this thread polls Python's
/// signal handlers every [`SIGNAL_POLL`]: on Ctrl-C (an error from `check_signals`, a
/// `KeyboardInterrupt`) it asks the work to stop ([`greybox_core::interrupt`]), waits for
/// the worker to return at its next check, and raises that `KeyboardInterrupt`. Other errors
/// of `f` become [`GreyboxError`].
pub(crate) fn run_interruptible<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> anyhow::Result<T> + Send,
) -> PyResult<T> {
    use std::sync::{Condvar, Mutex};
    greybox_core::interrupt::clear();
    let done = (Mutex::new(false), Condvar::new());
    let (result, signal) = std::thread::scope(|s| {
        let worker = std::thread::Builder::new()
            .stack_size(WORKER_STACK_BYTES)
            .spawn_scoped(s, || {
                // a panic must still wake the waiting thread: caught here, an error below
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f))
                    .unwrap_or_else(|_| Err(anyhow::anyhow!("internal error: a panic in greybox")));
                *done.0.lock().unwrap_or_else(|e| e.into_inner()) = true;
                done.1.notify_all();
                r
            });
        let worker = match worker {
            Ok(w) => w,
            Err(e) => {
                return (
                    Err(anyhow::anyhow!("cannot start a worker thread: {e}")),
                    None,
                )
            }
        };
        let signal = wait_or_signal(py, &done);
        if signal.is_some() {
            // asked again while waiting: another thread's new call clears the flag
            py.detach(|| loop {
                greybox_core::interrupt::request_stop();
                if wait_done(&done) {
                    break;
                }
            });
        }
        let result = py.detach(|| worker.join()).unwrap_or_else(|_| {
            Err(anyhow::anyhow!(
                "internal error: the worker thread panicked"
            ))
        });
        (result, signal)
    });
    match (result, signal) {
        (_, Some(interrupt)) => Err(interrupt),
        // stopped by Ctrl-C in another thread's call
        (Err(e), None) if e.root_cause().to_string() == "interrupted" => Err(
            pyo3::exceptions::PyKeyboardInterrupt::new_err("interrupted"),
        ),
        (r, None) => r.map_err(py_err),
    }
}

/// Wait (GIL released) until `done` is set, polling Python's signal handlers meanwhile: the
/// error a handler raised (KeyboardInterrupt on Ctrl-C), if any.
fn wait_or_signal(
    py: Python<'_>,
    done: &(std::sync::Mutex<bool>, std::sync::Condvar),
) -> Option<PyErr> {
    loop {
        if py.detach(|| wait_done(done)) {
            return None;
        }
        if let Err(e) = py.check_signals() {
            return Some(e);
        }
    }
}

/// Wait up to [`SIGNAL_POLL`] for `done` to be set; whether it is.
fn wait_done(done: &(std::sync::Mutex<bool>, std::sync::Condvar)) -> bool {
    let g = done.0.lock().unwrap_or_else(|e| e.into_inner());
    let (g, _) = done
        .1
        .wait_timeout_while(g, SIGNAL_POLL, |d| !*d)
        .unwrap_or_else(|e| e.into_inner());
    *g
}

/// JSON of a serialisable value (for the Python layer to `json.loads`).
pub(crate) fn to_json(v: &impl serde::Serialize) -> PyResult<String> {
    serde_json::to_string(v).map_err(py_err)
}

/// The bundled examples, by file name (the repository's `examples/`).
const EXAMPLES: [(&str, &str); 2] = [
    (
        "aisi1045-cut.toml",
        include_str!("../../../examples/aisi1045-cut.toml"),
    ),
    ("demo-study.toml", greybox_pipeline::study::DEMO_STUDY),
];

/// The text of a bundled example file: `aisi1045-cut.toml` (the article's orthogonal-cut
/// set-up) or `demo-study.toml` (the example study).
#[pyfunction]
fn example(name: &str) -> PyResult<&'static str> {
    EXAMPLES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, text)| *text)
        .ok_or_else(|| {
            py_err(anyhow::anyhow!(
                "name '{name}': expected one of {}",
                EXAMPLES.map(|(n, _)| n).join(", ")
            ))
        })
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("GreyboxError", m.py().get_type::<GreyboxError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<laws::Model>()?;
    m.add_class::<laws::Law>()?;
    stages::register(m)?;
    import::register(m)?;
    m.add_function(wrap_pyfunction!(example, m)?)?;
    Ok(())
}
