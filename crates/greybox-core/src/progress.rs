//! Progress of long work (a cut, a fit, a sweep) reported to whoever is watching.
//!
//! Library code opens a [`Task`] with [`task`] and advances it; what the user sees is decided
//! by the process's installed [`Sink`] (the command line installs a progress bar on a
//! terminal, periodic status lines otherwise, nothing with `--quiet`). With no sink installed
//! — the default for library users and the Python package — tasks cost one relaxed atomic
//! load per update and print nothing.
//!
//! Updates are throttled in the [`Task`] (at most one sink call per [`MIN_INTERVAL`]), so
//! a solver may report after every step.
//!
//! ```
//! use greybox_core::progress;
//! let t = progress::task("fit", Some(10), "models");
//! for i in 0..10 { t.set(i + 1); }
//! t.finish("done");
//! ```

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, RwLock};
use std::time::{Duration, Instant};

/// The shortest time between two updates a task hands to the sink.
pub const MIN_INTERVAL: Duration = Duration::from_millis(100);

pub use crate::progress_sink::Sink;

static INSTALLED: AtomicBool = AtomicBool::new(false);
static SINK: RwLock<Option<Arc<dyn Sink>>> = RwLock::new(None);
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

/// Makes `sink` receive every task started from now on (replacing any installed sink).
pub fn install(sink: Arc<dyn Sink>) {
    *SINK.write().unwrap_or_else(|e| e.into_inner()) = Some(sink);
    INSTALLED.store(true, Ordering::Release);
}

/// Removes the installed sink: later tasks are silent.
pub fn uninstall() {
    INSTALLED.store(false, Ordering::Release);
    *SINK.write().unwrap_or_else(|e| e.into_inner()) = None;
}

/// The sink of the call the current thread works for ([`crate::call_scope`]), else the
/// process's installed one.
fn installed() -> Option<Arc<dyn Sink>> {
    if let Some(s) = crate::call_scope::CallScope::with_current(|s| s.sink.clone()) {
        return Some(s);
    }
    if !INSTALLED.load(Ordering::Acquire) {
        return None;
    }
    SINK.read().unwrap_or_else(|e| e.into_inner()).clone()
}

/// Starts a task: `total` units of work if known (`None`: a spinner).
pub fn task(label: &str, total: Option<u64>, unit: &str) -> Task {
    let sink = installed();
    let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
    if let Some(s) = &sink {
        s.begin(id, label, total, unit);
    }
    Task {
        id,
        sink,
        done: AtomicU64::new(0),
        last: Mutex::new(None),
        ended: AtomicBool::new(false),
    }
}

/// One piece of long work being reported. Ends with [`Task::finish`]; a task dropped
/// without finishing (an error unwound past it) ends as "stopped".
pub struct Task {
    id: u64,
    sink: Option<Arc<dyn Sink>>,
    done: AtomicU64,
    last: Mutex<Option<Instant>>,
    ended: AtomicBool,
}

impl Task {
    /// Whether anyone watches (callers may skip building status messages when not).
    pub fn watched(&self) -> bool {
        self.sink.is_some()
    }
    /// Sets the amount done.
    pub fn set(&self, done: u64) {
        self.done.store(done, Ordering::Relaxed);
        self.report(None, false);
    }
    /// Adds `n` to the amount done.
    pub fn inc(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
        self.report(None, false);
    }
    /// Sets the amount done with a short status message (throttled like [`Task::set`]).
    pub fn set_with(&self, done: u64, message: impl FnOnce() -> String) {
        self.done.store(done, Ordering::Relaxed);
        if self.sink.is_some() && self.due() {
            self.send(Some(&message()));
        }
    }
    /// Ends the task with `outcome`.
    pub fn finish(self, outcome: &str) {
        self.end(outcome);
    }
    fn report(&self, message: Option<&str>, force: bool) {
        if self.sink.is_some() && (force || self.due()) {
            self.send(message);
        }
    }
    fn send(&self, message: Option<&str>) {
        if let Some(s) = &self.sink {
            s.update(self.id, self.done.load(Ordering::Relaxed), message);
        }
    }
    /// Whether enough time has passed since the last update handed to the sink.
    fn due(&self) -> bool {
        let now = Instant::now();
        let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
        match *last {
            Some(t) if now.duration_since(t) < MIN_INTERVAL => false,
            _ => {
                *last = Some(now);
                true
            }
        }
    }
    fn end(&self, outcome: &str) {
        if self.ended.swap(true, Ordering::AcqRel) {
            return;
        }
        if let Some(s) = &self.sink {
            s.update(self.id, self.done.load(Ordering::Relaxed), None);
            s.end(self.id, outcome);
        }
    }
}

impl Drop for Task {
    fn drop(&mut self) {
        self.end("stopped");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Default)]
    struct Recorder(Mutex<Vec<String>>);
    impl Sink for Recorder {
        fn begin(&self, _: u64, label: &str, total: Option<u64>, unit: &str) {
            self.0
                .lock()
                .unwrap()
                .push(format!("begin {label} {total:?} {unit}"));
        }
        fn update(&self, _: u64, done: u64, _: Option<&str>) {
            self.0.lock().unwrap().push(format!("update {done}"));
        }
        fn end(&self, _: u64, outcome: &str) {
            self.0.lock().unwrap().push(format!("end {outcome}"));
        }
    }

    #[test]
    fn tasks_report_to_the_installed_sink_throttled_and_end_once() {
        let r = Arc::new(Recorder::default());
        install(r.clone());
        let t = task("cut", Some(1000), "steps");
        for i in 0..1000 {
            t.set(i + 1);
        }
        t.finish("done");
        {
            let _dropped = task("fit", None, "models");
        }
        uninstall();
        let silent = task("quiet", Some(3), "x");
        silent.set(3);
        assert!(!silent.watched());
        drop(silent);
        let log = r.0.lock().unwrap().clone();
        assert_eq!(log[0], "begin cut Some(1000) steps");
        // the first update passes, the rest of the burst is throttled, the end reports the total
        let updates = log.iter().filter(|l| l.starts_with("update")).count();
        assert!(updates <= 4, "{log:?}");
        assert!(log.contains(&"update 1000".to_string()), "{log:?}");
        assert_eq!(log.iter().filter(|l| *l == "end done").count(), 1);
        assert!(log.contains(&"begin fit None models".to_string()));
        assert!(log.contains(&"end stopped".to_string()));
        assert!(!log.iter().any(|l| l.contains("quiet")));
    }
}
