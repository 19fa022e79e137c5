//! Cooperative cancellation of long work (a fit, a cut, an identification).
//!
//! A host that wants to stop a running call (the Python package on Ctrl-C, while the call
//! runs with the GIL released) hands the call a [`StopToken`](crate::call_scope::StopToken)
//! in its [`CallScope`](crate::call_scope::CallScope) and stops the token; the long loops of
//! the library call [`check`] between their steps (grid points and folds, time steps,
//! recordings, refinement rounds) and return [`Interrupted`] at the next one. Outputs are
//! staged, so an interrupted call leaves no half-written file behind.
//!
//! The stop request is a value the host owns, not process-wide state: only the threads
//! working for that call (those that entered its scope) stop, so a host running several
//! calls at once (the Python package) stops one with Ctrl-C and leaves the others running.
//! Passing the token through the thread's scope instead of every workflow, solver and
//! learner signature keeps it off the design's seams. A call outside any scope, or whose
//! scope has no token, is never interrupted. Nothing here installs signal handlers.
//!
//! ```
//! use greybox_core::call_scope::{CallScope, StopToken};
//! use greybox_core::interrupt;
//! let stop = StopToken::new();
//! let scope = CallScope { stop: Some(stop.clone()), ..Default::default() };
//! let _in = scope.enter();
//! assert!(interrupt::check().is_ok());
//! stop.stop();
//! assert_eq!(interrupt::check().unwrap_err().to_string(), "interrupted");
//! ```

/// The error of a call stopped on request: "interrupted".
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("interrupted")]
pub struct Interrupted;

/// Whether a stop has been requested for the call the current thread works for.
pub fn stop_requested() -> bool {
    crate::call_scope::CallScope::with_current(|s| s.stop.as_ref().map(|t| t.is_stopped()))
        .unwrap_or(false)
}

/// `Err(Interrupted)` once a stop has been requested; for long loops to call between steps
/// (a thread-local look-up).
pub fn check() -> Result<(), Interrupted> {
    if stop_requested() {
        Err(Interrupted)
    } else {
        Ok(())
    }
}
