//! What one host call carries to every thread that works for it: its own stop token, its
//! own progress sink and its own command line for provenance.
//!
//! A host that runs several calls at once (the Python package, one call per Python thread)
//! must stop, watch and record each call on its own: Ctrl-C in one thread stops that
//! thread's call only. The host makes a [`CallScope`] per call and enters it
//! ([`CallScope::enter`]) on the thread that runs the call and on every thread of the call's
//! worker pool; [`crate::interrupt::check`] looks only here (a call with no stop token is
//! never interrupted), [`crate::progress::task`] and [`crate::provenance::command`] look
//! here first and fall back to the process-wide state (what the command line uses). Threads
//! the library spawns by itself outside a pool do not inherit the scope.
//!
//! ```
//! use greybox_core::call_scope::{CallScope, StopToken};
//! let stop = StopToken::new();
//! let scope = CallScope { stop: Some(stop.clone()), ..Default::default() };
//! let _in = scope.enter();
//! assert!(greybox_core::interrupt::check().is_ok());
//! stop.stop();
//! assert!(greybox_core::interrupt::check().is_err());
//! ```

use crate::progress_sink::Sink;
use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A stop request for one call: shared by the host (which sets it) and the call's threads.
#[derive(Debug, Clone, Default)]
pub struct StopToken(Arc<AtomicBool>);

impl StopToken {
    pub fn new() -> Self {
        Self::default()
    }
    /// Ask the call to stop at its next [`crate::interrupt::check`].
    pub fn stop(&self) {
        self.0.store(true, Ordering::SeqCst);
    }
    pub fn is_stopped(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// One call's stop token, progress sink and command line (each optional: without a token the
/// call is not interruptible; without a sink or command, the process-wide one applies).
#[derive(Clone, Default)]
pub struct CallScope {
    pub stop: Option<StopToken>,
    pub sink: Option<Arc<dyn Sink>>,
    /// The command recorded in provenance, program (or function) name first.
    pub command: Option<Vec<String>>,
    /// Where the call's notes go (values outside their usual range, said by the notes
    /// module), in the order they were made.
    pub notes: Option<Notes>,
}

/// One call's notes (see [`CallScope::notes`]).
pub type Notes = Arc<std::sync::Mutex<Vec<String>>>;

thread_local! {
    static CURRENT: RefCell<Option<CallScope>> = const { RefCell::new(None) };
}

/// Restores the thread's previous scope when dropped (see [`CallScope::enter`]).
pub struct Entered(Option<CallScope>);

impl Drop for Entered {
    fn drop(&mut self) {
        let previous = self.0.take();
        CURRENT.with(|c| *c.borrow_mut() = previous);
    }
}

impl CallScope {
    /// Make this the current thread's scope until the returned guard drops.
    pub fn enter(&self) -> Entered {
        Entered(CURRENT.with(|c| c.borrow_mut().replace(self.clone())))
    }

    /// Make this the current thread's scope for the thread's life (a pool thread's start).
    pub fn adopt(&self) {
        CURRENT.with(|c| *c.borrow_mut() = Some(self.clone()));
    }

    /// `f` of the current thread's scope, if it has one.
    pub(crate) fn with_current<R>(f: impl FnOnce(&CallScope) -> Option<R>) -> Option<R> {
        CURRENT.with(|c| c.borrow().as_ref().and_then(f))
    }
}
