//! Cooperative cancellation of long work (a fit, a cut, an identification).
//!
//! A host that wants to stop a running call (the Python package on Ctrl-C, while the call
//! runs with the GIL released) calls [`request_stop`]; the long loops of the library call
//! [`check`] between their steps (grid points and folds, time steps, recordings, refinement
//! rounds) and return [`Interrupted`] at the next one. Outputs are staged, so an interrupted
//! call leaves no half-written file behind.
//!
//! The flag is the one piece of process-wide state in the library, on purpose: an interrupt
//! (SIGINT) is itself process-wide, and threading a cancellation token through every
//! workflow, solver and learner signature for it would touch every seam of the design. A
//! host clears it ([`clear`]) before starting a call. Nothing here installs signal handlers.
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

/// Whether a stop has been requested (and not cleared since).
pub fn stop_requested() -> bool {
    STOP.load(Ordering::Relaxed)
}

/// `Err(Interrupted)` once a stop has been requested; for long loops to call between steps
/// (one relaxed atomic load).
pub fn check() -> Result<(), Interrupted> {
    if stop_requested() {
        Err(Interrupted)
    } else {
        Ok(())
    }
}
