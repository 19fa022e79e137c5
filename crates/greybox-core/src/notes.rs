//! Notes a run must not keep to itself: a value outside its usual range (a flag of the
//! physics table, [`crate::physics::check`]) that a stage's settings validation accepted.
//!
//! A note goes to the current call's list when the host made one ([`CallScope::notes`]:
//! the Python package turns each into a `greybox.UnusualValueWarning` when the call
//! returns), else to the process-wide hook ([`install`]: the command line prints
//! "warning: …" on stderr, with `--quiet` too), else to stderr. The same text is said once
//! per call (or once per process through the hook): a set-up validated twice says it once.
//!
//! [`CallScope::notes`]: crate::call_scope::CallScope::notes

use crate::call_scope::CallScope;
pub use crate::call_scope::Notes;
use std::collections::HashSet;
use std::sync::{Mutex, RwLock};

static HOOK: RwLock<Option<fn(&str)>> = RwLock::new(None);
static SAID: Mutex<Option<HashSet<String>>> = Mutex::new(None);

/// Where notes go for the rest of the process when no call collects them.
pub fn install(hook: fn(&str)) {
    *HOOK.write().unwrap_or_else(|e| e.into_inner()) = Some(hook);
}

/// Says `text` (see the module): to the call's notes, the hook, or stderr; once.
pub fn note(text: impl Into<String>) {
    let text = text.into();
    let collected = CallScope::with_current(|s| s.notes.clone());
    if let Some(notes) = collected {
        let mut n = notes.lock().unwrap_or_else(|e| e.into_inner());
        if !n.contains(&text) {
            n.push(text);
        }
        return;
    }
    let first = SAID
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .get_or_insert_with(HashSet::new)
        .insert(text.clone());
    if !first {
        return;
    }
    match *HOOK.read().unwrap_or_else(|e| e.into_inner()) {
        Some(hook) => hook(&text),
        None => eprintln!("warning: {text}"),
    }
}

/// Run `f` in a call of its own and return what it said, in order (a library caller that
/// shows notes its own way; tests).
pub fn collected<R>(f: impl FnOnce() -> R) -> (R, Vec<String>) {
    let notes = Notes::default();
    let scope = CallScope {
        notes: Some(notes.clone()),
        ..Default::default()
    };
    let r = {
        let _in = scope.enter();
        f()
    };
    let said = std::mem::take(&mut *notes.lock().unwrap_or_else(|e| e.into_inner()));
    (r, said)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_call_collects_its_notes_once_each() {
        let notes = Notes::default();
        let scope = CallScope {
            notes: Some(notes.clone()),
            ..Default::default()
        };
        {
            let _in = scope.enter();
            note("density 7.85 kg/m³ is outside the usual range");
            note("density 7.85 kg/m³ is outside the usual range");
            note("μ 1.5 is outside the usual range");
        }
        assert_eq!(notes.lock().unwrap().len(), 2);
    }
}
