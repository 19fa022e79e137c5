//! Models trained elsewhere as greybox model files ([`greybox_import`]): an XGBoost booster
//! (JSON/UBJSON) or a scikit-learn export, with the names, units and training domain the
//! source does not know, written the safe way with provenance.

use crate::output::provenance;
use anyhow::Result;
use greybox_core::outputs::check_file_output;
pub use greybox_import::{Calibration, Domain, ImportOptions, Imported};
use greybox_model::modelfile::ModelFile;
use std::path::Path;

/// Import `source` into the model file `out` (written atomically, provenance beside it).
pub fn import(source: &Path, opts: &ImportOptions, out: &Path) -> Result<ModelFile> {
    let mut inputs = vec![("model", source)];
    if let Domain::Data(p) = &opts.domain {
        inputs.push(("training data", p.as_path()));
    }
    if let Some(Calibration::File(p)) = &opts.calibration {
        inputs.push(("calibration", p.as_path()));
    }
    check_file_output(out, "--out", &inputs)?;
    let mut model = greybox_import::import_file(source, opts)?;
    let record = provenance(&inputs)?;
    model.provenance = Some(record.clone());
    let model = model.seal()?;
    model.save(out)?;
    record.write_beside(out)?;
    Ok(model)
}
