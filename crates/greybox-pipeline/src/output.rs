//! What every stage does with its outputs: a provenance record, and output directories that
//! are staged and swapped in whole ([`greybox_core::outputs`]).

use anyhow::Result;
use greybox_core::outputs::{check_dir_output, Existing, StagedDir};
use greybox_core::provenance::Provenance;
use std::path::Path;

/// The provenance record of this run: greybox's version, the process's command line and
/// `inputs` (role, path; hashed now).
pub fn provenance(inputs: &[(&str, &Path)]) -> Result<Provenance> {
    Ok(Provenance::new(
        "greybox",
        env!("CARGO_PKG_VERSION"),
        std::env::args().collect(),
    )
    .inputs(inputs)?)
}

/// Begin the output directory `out`: refused if it holds one of `inputs` or (unless
/// `force`) already holds files; written into a staging directory that
/// [`StagedDir::commit`] swaps in whole.
pub fn stage_out_dir(out: &Path, force: bool, inputs: &[(&str, &Path)]) -> Result<StagedDir> {
    check_dir_output(out, "--out", inputs)?;
    Ok(StagedDir::begin(out, "--out", Existing::from_force(force))?)
}
