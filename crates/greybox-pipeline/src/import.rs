//! Models trained elsewhere as greybox model files ([`greybox_import`]): an XGBoost booster
//! (JSON/UBJSON) or a scikit-learn export, with the names, units and training domain the
//! source does not know, written the safe way with provenance.

use crate::output::provenance;
use anyhow::{bail, Context, Result};
use greybox_contact::PinContact;
use greybox_core::outputs::check_file_output;
use greybox_import::{Calibration, Domain, ImportOptions};
use greybox_model::modelfile::ModelFile;
use std::path::{Path, PathBuf};

/// The keys of a study's `[contact]` table: the pin contact stated at import
/// (`greybox import --pin-tip-radius-mm …`, Python `contact={"pin_tip_radius_mm": …}`).
pub const CONTACT_KEYS: [&str; 6] = [
    "pin_tip_radius_mm",
    "pin_youngs_modulus_gpa",
    "pin_poisson_ratio",
    "disk_youngs_modulus_gpa",
    "disk_poisson_ratio",
    "convention",
];

/// The tribometer's pin contact as a user states it at import: a study TOML's `[contact]`
/// table, and/or that table's keys ([`CONTACT_KEYS`]) with values, which override the
/// study's. The pressure convention must be stated (in the table or as a key): a model
/// trained on a normal force is never given a default convention. Keys not stated take the
/// `[contact]` table's defaults (the article's 17 mm carbide pin, 650 GPa / 0.3, on AISI
/// 1045, 210 GPa / 0.3).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactSpec {
    /// A study TOML whose `[contact]` table states the contact.
    pub study: Option<PathBuf>,
    /// `[contact]` keys and their values (numbers; the convention as its name).
    pub fields: serde_json::Map<String, serde_json::Value>,
}

/// A contact in settings JSON: a study TOML's path (`"study.toml"`), or an object of
/// `[contact]` keys, where a `study` key names the study whose table the others override.
impl serde::Serialize for ContactSpec {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut all = self.fields.clone();
        if let Some(p) = &self.study {
            all.insert("study".into(), p.display().to_string().into());
        }
        all.serialize(s)
    }
}

impl<'de> serde::Deserialize<'de> for ContactSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error as _;
        match serde_json::Value::deserialize(d)? {
            serde_json::Value::Null => Ok(ContactSpec::default()),
            serde_json::Value::String(path) => Ok(ContactSpec {
                study: Some(path.into()),
                fields: serde_json::Map::new(),
            }),
            serde_json::Value::Object(mut fields) => {
                let study = match fields.remove("study") {
                    None | Some(serde_json::Value::Null) => None,
                    Some(serde_json::Value::String(p)) => Some(PathBuf::from(p)),
                    Some(other) => {
                        return Err(D::Error::custom(format!(
                            "study: expected a study TOML's path, got {other}"
                        )))
                    }
                };
                Ok(ContactSpec { study, fields })
            }
            other => Err(D::Error::custom(format!(
                "expected a study TOML's path or an object of the [contact] keys ({}), got {other}",
                CONTACT_KEYS.join(", ")
            ))),
        }
    }
}

impl ContactSpec {
    /// Whether anything states a contact.
    pub fn is_stated(&self) -> bool {
        self.study.is_some() || !self.fields.is_empty()
    }

    /// The pin contact, or `None` when nothing states one; errors name the study file, the
    /// key, or the missing convention.
    pub fn resolve(&self) -> Result<Option<PinContact>> {
        if !self.is_stated() {
            return Ok(None);
        }
        let mut table = match &self.study {
            Some(path) => study_contact_table(path)?,
            None => serde_json::Map::new(),
        };
        table.extend(self.fields.clone());
        if !table.contains_key("convention") {
            bail!(
                "the contact states no pressure convention: give convention (textbook-max, textbook-mean or article-eq7) — the one the training data's pressures were computed with{}",
                self.study.as_ref().map(|p| format!(" (the [contact] table of {} has none)", p.display())).unwrap_or_default()
            );
        }
        let contact: PinContact = serde_json::from_value(serde_json::Value::Object(table))
            .with_context(|| {
                format!(
                    "invalid contact (keys: {}; the study's [contact] table)",
                    CONTACT_KEYS.join(", ")
                )
            })?;
        contact.validate().context("invalid contact")?;
        Ok(Some(contact))
    }
}

/// The `[contact]` table of a study TOML, as JSON values.
fn study_contact_table(path: &Path) -> Result<serde_json::Map<String, serde_json::Value>> {
    let value: toml::Value = crate::config_toml::read(path, "study file")?;
    let Some(contact) = value.get("contact") else {
        bail!(
            "{}: no [contact] table: the study must state the tribometer's pin contact",
            path.display()
        );
    };
    match serde_json::to_value(contact)? {
        serde_json::Value::Object(m) => Ok(m),
        _ => bail!("{}: [contact] is not a table", path.display()),
    }
}

/// The files an import reads, by role: the model file (`None` when it came as text, a
/// scikit-learn export from Python), the training and calibration data, and the study TOML
/// that stated the contact.
pub fn import_inputs<'a>(
    source: Option<&'a Path>,
    opts: &'a ImportOptions,
    contact_study: Option<&'a Path>,
) -> Vec<(&'static str, &'a Path)> {
    let mut inputs: Vec<(&'static str, &'a Path)> =
        source.map(|s| ("model", s)).into_iter().collect();
    if let Domain::Data(p) = &opts.domain {
        inputs.push(("training data", p.as_path()));
    }
    if let Some(Calibration::File(p)) = &opts.calibration {
        inputs.push(("calibration", p.as_path()));
    }
    if let Some(p) = contact_study {
        inputs.push(("contact", p));
    }
    inputs
}

/// `model` with the provenance of the import that made it (greybox's version, the command
/// or host call, `inputs` hashed), sealed again: the same record from the command line and
/// from Python.
pub fn with_import_provenance(mut model: ModelFile, inputs: &[(&str, &Path)]) -> Result<ModelFile> {
    model.provenance = Some(provenance(inputs)?);
    Ok(model.seal()?)
}

/// Import `source` into the model file `out` (written atomically, provenance beside it);
/// `contact_study` is the study TOML that stated the contact, recorded among the inputs.
pub fn import(
    source: &Path,
    opts: &ImportOptions,
    contact_study: Option<&Path>,
    out: &Path,
) -> Result<ModelFile> {
    let inputs = import_inputs(Some(source), opts, contact_study);
    check_file_output(out, "out", &inputs)?;
    let model = with_import_provenance(greybox_import::import_file(source, opts)?, &inputs)?;
    model.save(out)?;
    model
        .provenance
        .as_ref()
        .expect("set above")
        .write_beside(out)?;
    Ok(model)
}
