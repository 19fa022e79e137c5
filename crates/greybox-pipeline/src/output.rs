//! What every stage does with its outputs: a provenance record, and output directories that
//! are staged and swapped in whole ([`greybox_core::outputs`]).

use anyhow::Result;
use greybox_core::outputs::{check_dir_output, Existing, StagedDir};
use greybox_core::provenance::Provenance;
use std::path::Path;

/// The provenance record of this run: greybox's version, the command (the process's command
/// line, or the host call's: [`greybox_core::provenance::command`]) and
/// `inputs` (role, path; hashed now).
pub fn provenance(inputs: &[(&str, &Path)]) -> Result<Provenance> {
    Ok(Provenance::new(
        "greybox",
        env!("CARGO_PKG_VERSION"),
        greybox_core::provenance::command(),
    )
    .inputs(inputs)?)
}

/// Begin the output directory `out`: refused if it holds one of `inputs` or (unless
/// `force`) already holds files; written into a staging directory that
/// [`StagedDir::commit`] swaps in whole.
pub fn stage_out_dir(out: &Path, force: bool, inputs: &[(&str, &Path)]) -> Result<StagedDir> {
    check_dir_output(out, "out", inputs)?;
    Ok(StagedDir::begin(out, "out", Existing::from_force(force))?)
}

/// On SIGINT, SIGTERM or SIGHUP: delete the temporary files and staging directories being
/// written ([`greybox_core::cleanup`]), then die of the signal as if unhandled (exit status
/// 128 + signal). A thread that only waits for signals; it never touches rayon's pool.
/// For programs (the command line); a library call never installs it by itself.
pub fn remove_temporaries_on_interrupt() {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("warning: cannot watch for interrupts ({e}); an interrupted run may leave temporary files");
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            let removed = greybox_core::cleanup::remove_registered();
            if !removed.is_empty() {
                eprintln!(
                    "interrupted: removed {} unfinished output(s)",
                    removed.len()
                );
            }
            let _ = signal_hook::low_level::emulate_default_handler(sig);
            std::process::exit(128 + sig);
        }
    });
}
