//! The seam between progress reports and their display ([`Sink`]), in its own module so
//! that both [`crate::progress`] (which reports) and [`crate::call_scope`] (which holds a
//! call's own sink) name it without naming each other.

/// What a progress display implements. Every call names the task by the id
/// [`crate::progress::task`] gave it.
///
/// A sink is installed for the whole process ([`crate::progress::install`], what the
/// command line does) or for one call ([`crate::call_scope::CallScope::sink`], what the
/// Python package does). Updates arrive throttled ([`crate::progress::MIN_INTERVAL`]);
/// `begin` and `end` always arrive. A sink that records what it is told, for one call:
///
/// ```
/// use greybox_core::call_scope::CallScope;
/// use greybox_core::progress::{self, Sink};
/// use std::sync::{Arc, Mutex};
///
/// #[derive(Default)]
/// struct Log(Mutex<Vec<String>>);
/// impl Sink for Log {
///     fn begin(&self, _id: u64, label: &str, total: Option<u64>, unit: &str) {
///         self.0.lock().unwrap().push(format!("{label}: {total:?} {unit}"));
///     }
///     fn update(&self, _id: u64, _done: u64, _message: Option<&str>) {}
///     fn end(&self, _id: u64, outcome: &str) {
///         self.0.lock().unwrap().push(outcome.to_string());
///     }
/// }
///
/// let log = Arc::new(Log::default());
/// let scope = CallScope { sink: Some(log.clone()), ..Default::default() };
/// {
///     let _in = scope.enter();
///     let t = progress::task("fit", Some(3), "models");
///     t.set(3);
///     t.finish("done");
/// }
/// assert_eq!(*log.0.lock().unwrap(), ["fit: Some(3) models", "done"]);
/// ```
pub trait Sink: Send + Sync {
    /// A task started: `label` says what runs, `total` how much there is (in `unit`s), when known.
    fn begin(&self, id: u64, label: &str, total: Option<u64>, unit: &str);
    /// `done` of the total is done; `message` (optional) is a short status such as the
    /// current force or the case running.
    fn update(&self, id: u64, done: u64, message: Option<&str>);
    /// The task ended; `outcome` is a short word or sentence ("done", "failed: …").
    fn end(&self, id: u64, outcome: &str);
}
