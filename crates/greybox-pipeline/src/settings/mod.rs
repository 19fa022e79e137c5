//! The settings of each stage as a user states them: one type per stage, holding the
//! documented defaults once, parsed from the command line (clap derives, feature `cli`),
//! from Python's keyword arguments and from JSON (serde), and turned into the stage's
//! options by one method whose errors name the setting (`fit.mlp_hidden`, `pin.depth_um`).
//! Names carry their units (`pin_radius_mm`, `speed_m_per_min`), as at every edge of
//! greybox; the stages' options inside are SI.
//!
//! Export has its own pair, [`crate::export::ExportOptions`] and
//! [`crate::export::ExportOverrides`], because its defaults depend on the engine.

pub mod adhesive;
pub mod couple;
pub mod fit;
pub mod hertz;
pub mod identify;
pub mod law;
pub mod material;
pub mod pin;
pub mod plan;
pub mod synth;
pub mod windows;

use anyhow::{Context, Result};
use serde::de::DeserializeOwned;
use serde::Serialize;

/// Settings of stage `stage` from JSON (an unknown or mistyped key is an error naming it;
/// a value refused by its type, such as a count beyond its cap, names its key too):
///
/// ```
/// use greybox_pipeline::settings::{from_json, fit::FitSettings, identify::IdentifySettings};
/// let e = from_json::<FitSettings>("fit", r#"{"data": "d.csv", "bootstrap": 1000000000}"#)
///     .unwrap_err();
/// assert!(format!("{e:#}").starts_with("fit settings: bootstrap: 1000000000 is above the cap"));
/// // a key of no field, also where a type gathers another's fields (identify's plan)
/// let e = from_json::<IdentifySettings>("identify", r#"{"normal_force_cout": 3}"#).unwrap_err();
/// assert!(format!("{e:#}").contains("unknown key `normal_force_cout`"));
/// ```
pub fn from_json<T: DeserializeOwned + Serialize>(stage: &str, text: &str) -> Result<T> {
    parse_keys(text).with_context(|| format!("{stage} settings"))
}

/// Settings from the keyword arguments of a call (Python's, as JSON): as [`from_json`],
/// the error starting with the key (`radius_mm: invalid type: …`), since the call names the
/// stage.
pub fn from_keywords<T: DeserializeOwned + Serialize>(text: &str) -> Result<T> {
    parse_keys(text)
}

/// A settings value or key refused: the key and why (`bootstrap: 1000000000 is above the
/// cap …`, `unknown key `x` (known: …)`). Its own type, so that a surface can tell a refused
/// setting from a failed run (Python raises `SettingsError`).
#[derive(Debug)]
pub struct SettingError(pub String);

impl std::fmt::Display for SettingError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SettingError {}

/// The key of `given` whose value alone gives the error `text` (every settings type defaults
/// its other fields).
fn blame<T: DeserializeOwned>(given: &serde_json::Value, text: &str) -> Option<String> {
    given.as_object()?.iter().find_map(|(key, value)| {
        let alone = serde_json::json!({ key: value });
        match serde_json::from_value::<T>(alone) {
            Err(e) if e.to_string().starts_with(text) => Some(key.clone()),
            _ => None,
        }
    })
}

fn parse_keys<T: DeserializeOwned + Serialize>(text: &str) -> Result<T> {
    let refused = |m: String| anyhow::Error::new(SettingError(m));
    let given: serde_json::Value =
        serde_json::from_str(text).map_err(|e| refused(format!("not JSON: {e}")))?;
    let value: T = serde_path_to_error::deserialize(&given).map_err(|e| {
        let path = e.path().to_string();
        let text = e.into_inner().to_string();
        let path = match path.as_str() {
            // a flattened field's error has no path: the key whose value alone fails
            "." | "" => blame::<T>(&given, &text).unwrap_or_default(),
            _ => path,
        };
        // a value type that names its field already (`segment: 'x' is not one of …`)
        let named = path
            .rsplit('.')
            .next()
            .is_some_and(|last| text.starts_with(&format!("{last}:")));
        match path.as_str() {
            "" => refused(text),
            _ if named => refused(text),
            _ => refused(format!("{path}: {text}")),
        }
    })?;
    // Every field serializes under its key, so a key the value does not write back is one
    // no field took (`deny_unknown_fields` cannot see through a flattened field).
    let known = serde_json::to_value(&value)?;
    if let (Some(given), Some(known)) = (given.as_object(), known.as_object()) {
        if let Some(unknown) = given.keys().find(|k| !known.contains_key(*k)) {
            let mut names: Vec<&str> = known.keys().map(String::as_str).collect();
            names.sort_unstable();
            return Err(refused(format!(
                "unknown key `{unknown}` (known: {})",
                names.join(", ")
            )));
        }
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value refused inside a flattened field (identify's plan) still names its key.
    #[test]
    fn a_refused_value_of_a_flattened_field_names_its_key() {
        let e = from_keywords::<identify::IdentifySettings>(r#"{"velocity_count": -2}"#)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("velocity_count: "), "{e}");
        let e = from_keywords::<identify::IdentifySettings>(r#"{"steady": 5}"#)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("steady: "), "{e}");
    }
}
