//! The native module of greybox's Python package (`greybox._native`): PyO3 bindings over the
//! `greybox-pipeline` workflows and the model/law types. The Python layer (`python/greybox`)
//! turns its JSON reports into dicts and its tables into NumPy arrays or pandas DataFrames.
//!
//! Every call that reads files, fits or simulates releases the GIL and stays interruptible
//! with Ctrl-C ([`run_interruptible`]), each call on its own: its own stop token, progress
//! and provenance command ([`greybox_core::call_scope`]). Errors arrive as the classes of
//! `greybox._errors` ([`errors`]), carrying the same message the command line prints after
//! `error:`.

mod errors;
mod import;
mod laws;
mod stages;

use greybox_core::call_scope::{CallScope, StopToken};
use greybox_core::setting::{SettingError, SettingPath};
use pyo3::prelude::*;
use std::cell::RefCell;
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex};

pub(crate) use errors::py_err;

/// The stack of the threads running a call (that of a main thread, as the calls had when
/// they ran on Python's own thread).
const WORKER_STACK_BYTES: usize = 8 << 20;

/// How often a waiting call looks for a pending signal (Ctrl-C) and hands progress over.
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// What the Python layer set for the calls of this (Python) thread: the progress callback
/// `callable(stage, done, total)` and the provenance command ([`swap_call`]).
#[derive(Default)]
struct CallOptions {
    progress: Option<Py<PyAny>>,
    command: Option<Vec<String>>,
}

thread_local! {
    static CALL: RefCell<CallOptions> = RefCell::new(CallOptions::default());
}

/// Set this thread's progress callback and provenance command for the native calls it makes
/// next; returns the previous pair (for the caller to restore).
#[pyfunction]
#[pyo3(signature = (progress = None, command = None))]
fn swap_call(
    progress: Option<Py<PyAny>>,
    command: Option<Vec<String>>,
) -> (Option<Py<PyAny>>, Option<Vec<String>>) {
    CALL.with(|c| {
        let old = std::mem::replace(&mut *c.borrow_mut(), CallOptions { progress, command });
        (old.progress, old.command)
    })
}

/// A progress sink that queues updates for the calling thread, which hands them to the
/// Python callback with the GIL held ([`ProgressQueue::drain`]).
#[derive(Default)]
struct ProgressQueue {
    /// Open tasks: id → (label, total).
    tasks: Mutex<std::collections::HashMap<u64, (String, Option<u64>)>>,
    /// (stage, done, total) not yet handed over.
    pending: Mutex<Vec<(String, u64, Option<u64>)>>,
}

impl greybox_core::progress::Sink for ProgressQueue {
    fn begin(&self, id: u64, label: &str, total: Option<u64>, _unit: &str) {
        lock(&self.tasks).insert(id, (label.to_string(), total));
        lock(&self.pending).push((label.to_string(), 0, total));
    }
    fn update(&self, id: u64, done: u64, _message: Option<&str>) {
        if let Some((label, total)) = lock(&self.tasks).get(&id).cloned() {
            lock(&self.pending).push((label, done, total));
        }
    }
    fn end(&self, id: u64, _outcome: &str) {
        lock(&self.tasks).remove(&id);
    }
}

impl ProgressQueue {
    /// Call `callback(stage, done, total)` for each queued update; the callback's error.
    fn drain(&self, py: Python<'_>, callback: &Py<PyAny>) -> PyResult<()> {
        let pending = std::mem::take(&mut *lock(&self.pending));
        for (stage, done, total) in pending {
            callback.call1(py, (stage, done, total))?;
        }
        Ok(())
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Run `f` with the GIL released on a worker thread (its parallel work on a pool of its own,
/// every thread in the call's [`CallScope`]) while this thread polls Python's signal
/// handlers every [`SIGNAL_POLL`] and hands progress to the callback set by [`swap_call`].
/// On Ctrl-C (an error from `check_signals`, a `KeyboardInterrupt`, raised in the main
/// thread only) or an error of the callback it stops this call alone, waits for the worker
/// to return at its next check, and raises that error. Other errors of `f` become the
/// package's exceptions ([`py_err`]).
pub(crate) fn run_interruptible<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> anyhow::Result<T> + Send,
) -> PyResult<T> {
    run_call(py, true, f)
}

/// [`run_interruptible`] for work with no parallel part (a model's or law's evaluation, a
/// file read): on the worker thread alone, without starting a pool (a millisecond saved per
/// call of `Law.mu` in a loop).
pub(crate) fn run_sequential<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> anyhow::Result<T> + Send,
) -> PyResult<T> {
    run_call(py, false, f)
}

fn run_call<T: Send>(
    py: Python<'_>,
    pooled: bool,
    f: impl FnOnce() -> anyhow::Result<T> + Send,
) -> PyResult<T> {
    let (callback, command) = CALL.with(|c| {
        let c = c.borrow();
        (
            c.progress.as_ref().map(|p| p.clone_ref(py)),
            c.command.clone(),
        )
    });
    let queue = Arc::new(ProgressQueue::default());
    let stop = StopToken::new();
    let notes = greybox_core::notes::Notes::default();
    let scope = CallScope {
        stop: Some(stop.clone()),
        sink: callback
            .is_some()
            .then(|| queue.clone() as Arc<dyn greybox_core::progress::Sink>),
        command,
        notes: Some(notes.clone()),
    };
    let handover = |py: Python<'_>| match &callback {
        Some(cb) => queue.drain(py, cb),
        None => Ok(()),
    };
    let done = (Mutex::new(false), Condvar::new());
    let (result, stopped_by) = std::thread::scope(|s| {
        let worker = std::thread::Builder::new()
            .stack_size(WORKER_STACK_BYTES)
            .spawn_scoped(s, || {
                let _in = scope.enter();
                // a panic must still wake the waiting thread: caught here, an error below
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    if pooled {
                        call_pool(&scope)?.install(f)
                    } else {
                        f()
                    }
                }))
                .unwrap_or_else(|_| Err(anyhow::anyhow!("internal error: a panic in greybox")));
                *lock(&done.0) = true;
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
        let stopped_by = wait_or_signal(py, &done, &handover);
        if stopped_by.is_some() {
            stop.stop();
        }
        let result = py.detach(|| worker.join()).unwrap_or_else(|_| {
            Err(anyhow::anyhow!(
                "internal error: the worker thread panicked"
            ))
        });
        (result, stopped_by)
    });
    let last = handover(py);
    warn_notes(py, &notes)?;
    match (result, stopped_by) {
        (_, Some(e)) => Err(e),
        (r, None) => {
            let v = r.map_err(py_err)?;
            last?;
            Ok(v)
        }
    }
}

/// The call's notes ([`greybox_core::notes`]: values outside their usual range) as
/// `greybox.UnusualValueWarning`s (an error only if a warnings filter makes them one).
fn warn_notes(py: Python<'_>, notes: &greybox_core::notes::Notes) -> PyResult<()> {
    let notes = std::mem::take(&mut *lock(notes));
    if notes.is_empty() {
        return Ok(());
    }
    let class = py
        .import("greybox._errors")?
        .getattr("UnusualValueWarning")?;
    for n in notes {
        let text = std::ffi::CString::new(n.replace('\0', "\\0")).unwrap_or_default();
        PyErr::warn(py, &class, &text, 1)?;
    }
    Ok(())
}

/// The worker pool of one call: its threads carry the call's scope.
fn call_pool(scope: &CallScope) -> anyhow::Result<rayon::ThreadPool> {
    let scope = scope.clone();
    rayon::ThreadPoolBuilder::new()
        .stack_size(WORKER_STACK_BYTES)
        .start_handler(move |_| scope.adopt())
        .build()
        .map_err(|e| anyhow::anyhow!("cannot start the worker threads: {e}"))
}

/// Wait (GIL released) until `done` is set, polling Python's signal handlers and handing
/// progress over meanwhile: the error a handler (KeyboardInterrupt on Ctrl-C) or the
/// progress callback raised, if any.
fn wait_or_signal(
    py: Python<'_>,
    done: &(Mutex<bool>, Condvar),
    handover: &dyn Fn(Python<'_>) -> PyResult<()>,
) -> Option<PyErr> {
    loop {
        let finished = py.detach(|| wait_done(done));
        if let Err(e) = handover(py) {
            return Some(e);
        }
        if finished {
            return None;
        }
        if let Err(e) = py.check_signals() {
            return Some(e);
        }
    }
}

/// Wait up to [`SIGNAL_POLL`] for `done` to be set; whether it is.
fn wait_done(done: &(Mutex<bool>, Condvar)) -> bool {
    let g = lock(&done.0);
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

/// The bytes of the input file `what` ("law file", "table") at `path`, through greybox's one
/// safe open ([`greybox_core::input`]): a regular file under `max_data_bytes`; a FIFO,
/// device or directory is refused and a missing file is `FileNotFoundError`.
#[pyfunction]
fn read_input(py: Python<'_>, path: PathBuf, what: String) -> PyResult<Py<pyo3::types::PyBytes>> {
    let bytes = run_sequential(py, move || {
        Ok(greybox_core::input::read_bytes(
            &path,
            &what,
            greybox_core::budget::Cap::DataBytes,
        )?)
    })?;
    Ok(pyo3::types::PyBytes::new(py, &bytes).unbind())
}

/// Sets the readers' caps ([`greybox_core::budget::Budget`]) named in `json` (`{"max_data_bytes":
/// …}`; the others kept) for the rest of the process; returns the caps before, as JSON. A
/// key that is no cap is refused with the known ones.
#[pyfunction]
fn swap_budget(json: &str) -> PyResult<String> {
    let before = greybox_core::budget::current();
    let mut value = serde_json::to_value(before).map_err(py_err)?;
    let given: serde_json::Map<String, serde_json::Value> =
        serde_json::from_str(json).map_err(py_err)?;
    let known = value.as_object_mut().expect("Budget is a JSON object");
    for (k, v) in given {
        if !known.contains_key(&k) {
            let names: Vec<&String> = known.keys().collect();
            return Err(py_err(SettingError::new(
                SettingPath::new("budget", greybox_core::escape::excerpt(&k)),
                format!(
                    "not a cap (the caps: {})",
                    names
                        .iter()
                        .map(|s| s.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )));
        }
        known.insert(k, v);
    }
    let after: greybox_core::budget::Budget = serde_json::from_value(value).map_err(|e| {
        py_err(SettingError::between(
            Vec::new(),
            format!("budget: {e} (a cap is a whole number ≥ 0)"),
        ))
    })?;
    greybox_core::budget::set(after);
    to_json(&before)
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // the solver's SIMD path capped by `GREYBOX_SIMD` (the library reads no environment)
    let simd_cap = std::env::var(greybox_sim::cpu::SIMD_ENV).ok();
    if let Err(warning) = greybox_sim::cpu::apply_cap(simd_cap.as_deref()) {
        eprintln!("{warning}");
    }
    m.add(
        "GreyboxError",
        m.py().import("greybox._errors")?.getattr("GreyboxError")?,
    )?;
    m.add_function(wrap_pyfunction!(swap_call, m)?)?;
    m.add_function(wrap_pyfunction!(laws::law_files, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<laws::Model>()?;
    m.add_class::<laws::Law>()?;
    stages::register(m)?;
    import::register(m)?;
    m.add_function(wrap_pyfunction!(example, m)?)?;
    m.add_function(wrap_pyfunction!(read_input, m)?)?;
    m.add_function(wrap_pyfunction!(swap_budget, m)?)?;
    Ok(())
}
