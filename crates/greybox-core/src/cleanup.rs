//! Temporary paths to remove when the process is interrupted.
//!
//! A temporary file or staging directory registers itself here while it exists
//! ([`register`]); the guard unregisters it when dropped. A program that wants interrupted
//! runs to leave nothing behind (the `greybox` binary does) calls [`remove_registered`] from
//! its SIGINT/SIGTERM/SIGHUP handler before exiting. A library never installs signal handlers
//! itself; without a handler, the guards still clean up on every normal or error exit.
//!
//! The move of a registered path into its final place runs under [`CleanupGuard::complete`],
//! so a handler never removes a file that has just become an output.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

struct Entry {
    id: u64,
    path: PathBuf,
    dir: bool,
}

static REGISTRY: Mutex<Vec<Entry>> = Mutex::new(Vec::new());
static NEXT_ID: AtomicU64 = AtomicU64::new(1);

fn lock() -> MutexGuard<'static, Vec<Entry>> {
    // a panic while holding the lock leaves a valid Vec: keep going
    REGISTRY.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes `path` from the registry when dropped (it does not delete the path).
#[derive(Debug)]
#[must_use = "the path is unregistered when the guard is dropped"]
pub struct CleanupGuard {
    id: u64,
}

impl CleanupGuard {
    /// Run `f` (the rename that turns the temporary into an output) and unregister the path,
    /// with no interrupt handler able to remove it in between.
    pub fn complete<T>(self, f: impl FnOnce() -> T) -> T {
        let mut reg = lock();
        let out = f();
        reg.retain(|e| e.id != self.id);
        drop(reg);
        std::mem::forget(self);
        out
    }
}

impl Drop for CleanupGuard {
    fn drop(&mut self) {
        lock().retain(|e| e.id != self.id);
    }
}

/// Register a temporary file (`dir = false`) or directory tree (`dir = true`).
pub fn register(path: &Path, dir: bool) -> CleanupGuard {
    let id = NEXT_ID.fetch_add(1, Ordering::Relaxed);
    lock().push(Entry {
        id,
        path: path.to_path_buf(),
        dir,
    });
    CleanupGuard { id }
}

/// Delete every registered path (best effort) and empty the registry; the paths removed.
/// For signal handlers: the registry stays locked until the process exits, so no rename
/// into place can follow.
pub fn remove_registered() -> Vec<PathBuf> {
    let mut reg = lock();
    let mut removed = Vec::new();
    for e in reg.drain(..) {
        let r = if e.dir {
            std::fs::remove_dir_all(&e.path)
        } else {
            std::fs::remove_file(&e.path)
        };
        if r.is_ok() {
            removed.push(e.path);
        }
    }
    // keep the lock: the caller is about to exit
    std::mem::forget(reg);
    removed
}

/// Paths registered now (for tests and diagnostics).
pub fn registered() -> Vec<PathBuf> {
    lock().iter().map(|e| e.path.clone()).collect()
}
