//! Cooperative cancellation of long work (a fit, a cut, an identification).
//!
//! A host that wants to stop a running call (the Python package on Ctrl-C, while the call
//! runs with the GIL released) stops its token, or calls [`request_stop`] to stop every
//! call; the long loops of the library call
//! [`check`] between their steps (grid points and folds, time steps, recordings, refinement
//! rounds) and return [`Interrupted`] at the next one. Outputs are staged, so an interrupted
//! call leaves no half-written file behind.
//!
//! Two kinds of request: the process-wide flag ([`request_stop`], every call stops), and
//! one call's [`StopToken`](crate::call_scope::StopToken) carried by its
//! [`CallScope`](crate::call_scope::CallScope) (only the threads working for that call
//! stop). A host running several calls at once (the Python package) uses the token, so
//! Ctrl-C in one thread leaves the others' calls running; passing the token through the
//! thread's scope instead of every workflow, solver and learner signature keeps it off the
//! design's seams. Nothing here installs signal handlers.
//!
//! ```
//! use greybox_core::interrupt;
//! interrupt::clear();
//! assert!(interrupt::check().is_ok());
//! interrupt::request_stop();
//! assert_eq!(interrupt::check().unwrap_err().to_string(), "interrupted");
//! interrupt::clear();
//! ```

use std::sync::atomic::{AtomicBool, Ordering};

static STOP: AtomicBool = AtomicBool::new(false);

/// The error of a call stopped by [`request_stop`]: "interrupted".
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("interrupted")]
pub struct Interrupted;

/// Ask every running call to stop at its next [`check`].
pub fn request_stop() {
    STOP.store(true, Ordering::SeqCst);
}

/// Forget an earlier stop request (before starting a new call).
pub fn clear() {
    STOP.store(false, Ordering::SeqCst);
}

/// Whether a stop has been requested (and not cleared since), process-wide or for the call
/// the current thread works for.
pub fn stop_requested() -> bool {
    STOP.load(Ordering::Relaxed)
        || crate::call_scope::CallScope::with_current(|s| s.stop.as_ref().map(|t| t.is_stopped()))
            .unwrap_or(false)
}

/// `Err(Interrupted)` once a stop has been requested; for long loops to call between steps
/// (an atomic load and a thread-local look-up).
pub fn check() -> Result<(), Interrupted> {
    if stop_requested() {
        Err(Interrupted)
    } else {
        Ok(())
    }
}
