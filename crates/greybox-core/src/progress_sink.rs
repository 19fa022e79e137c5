//! The seam between progress reports and their display ([`Sink`]), in its own module so
//! that both [`crate::progress`] (which reports) and [`crate::call_scope`] (which holds a
//! call's own sink) name it without naming each other.

/// What a progress display implements. Every call names the task by the id [`task`] gave it.
pub trait Sink: Send + Sync {
    /// A task started: `label` says what runs, `total` how much there is (in `unit`s), when known.
    fn begin(&self, id: u64, label: &str, total: Option<u64>, unit: &str);
    /// `done` of the total is done; `message` (optional) is a short status such as the
    /// current force or the case running.
    fn update(&self, id: u64, done: u64, message: Option<&str>);
    /// The task ended; `outcome` is a short word or sentence ("done", "failed: …").
    fn end(&self, id: u64, outcome: &str);
}
