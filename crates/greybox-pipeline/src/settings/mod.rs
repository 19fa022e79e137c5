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
pub mod identify;
pub mod pin;
pub mod plan;

use anyhow::{Context, Result};
use serde::de::DeserializeOwned;

/// Settings of stage `stage` from JSON (an unknown or mistyped key is an error naming it;
/// a value refused by its type, such as a count beyond its cap, names its key too):
///
/// ```
/// let e = greybox_pipeline::settings::from_json::<greybox_pipeline::settings::fit::FitSettings>(
///     "fit", r#"{"data": "d.csv", "bootstrap": 1000000000}"#).unwrap_err();
/// assert!(format!("{e:#}").starts_with("fit settings: bootstrap: 1000000000 is above the cap"));
/// ```
pub fn from_json<T: DeserializeOwned>(stage: &str, text: &str) -> Result<T> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        match path.as_str() {
            "." | "" => anyhow::Error::new(inner),
            _ => anyhow::anyhow!("{path}: {inner}"),
        }
    });
    value.with_context(|| format!("{stage} settings"))
}
