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
pub mod characterize;
pub mod couple;
pub mod cut;
pub mod fit;
pub mod hertz;
pub mod identify;
pub mod import;
pub mod law;
pub mod material;
pub mod pin;
pub mod plan;
pub mod predict;
pub mod synth;
pub mod wear;
pub mod windows;

use anyhow::Result;
use greybox_core::setting::{SettingError, SettingPath};
use serde::de::DeserializeOwned;
use serde::Serialize;

/// A stage with one settings type: the name its errors and Python's `settings_defaults`
/// use (the CLI subcommand's, where it has one), and its settings with their defaults. A
/// new stage's settings type is added here once (a test checks that each entry's defaults
/// parse back as its type).
#[derive(Debug)]
pub struct StageSettings {
    /// The stage's name (`fit`, `cut`, …).
    pub name: &'static str,
    /// Its settings with their defaults, as JSON (a required path as `""`).
    pub defaults: fn() -> serde_json::Value,
    /// Parse settings JSON as the stage's type ([`from_json`]), for checks.
    pub parse: fn(&str) -> Result<()>,
}

/// The entry of `T`, whose defaults are `defaults()`.
const fn stage<T: DeserializeOwned + Serialize>(
    name: &'static str,
    defaults: fn() -> serde_json::Value,
) -> StageSettings {
    StageSettings {
        name,
        defaults,
        parse: parse_as::<T>,
    }
}

/// Whether `text` is settings JSON of `T` (every key one of its fields: [`from_keywords`]).
fn parse_as<T: DeserializeOwned + Serialize>(text: &str) -> Result<()> {
    from_keywords::<T>(text).map(|_| ())
}

/// `T::default()` as JSON.
fn defaults_of<T: Default + Serialize>() -> serde_json::Value {
    serde_json::to_value(T::default()).expect("settings serialize")
}

/// Every stage with one settings type (Python's `settings_defaults` adds the run output,
/// the validation suite and the report, whose types live elsewhere).
pub const STAGES: &[StageSettings] = &[
    stage::<identify::IdentifySettings>("identify", defaults_of::<identify::IdentifySettings>),
    stage::<synth::SynthSettings>("synth", defaults_of::<synth::SynthSettings>),
    stage::<hertz::HertzSettings>("hertz", defaults_of::<hertz::HertzSettings>),
    stage::<plan::PlanSettings>("plan", defaults_of::<plan::PlanSettings>),
    stage::<fit::FitSettings>("fit", || {
        serde_json::to_value(fit::FitSettings::shown_defaults()).expect("settings serialize")
    }),
    stage::<adhesive::AdhesiveSettings>("adhesive", defaults_of::<adhesive::AdhesiveSettings>),
    stage::<pin::PinSettings>("pin", defaults_of::<pin::PinSettings>),
    stage::<couple::CoupleSettings>("couple", defaults_of::<couple::CoupleSettings>),
    stage::<law::GreyBoxSettings>("law", defaults_of::<law::GreyBoxSettings>),
    stage::<windows::WindowsSettings>("windows", defaults_of::<windows::WindowsSettings>),
    stage::<material::FlowCurveSettings>("flow_curves", defaults_of::<material::FlowCurveSettings>),
    stage::<material::RateSensitivitySettings>(
        "rate_sensitivity",
        defaults_of::<material::RateSensitivitySettings>,
    ),
    stage::<cut::CutSettings>("cut", || {
        serde_json::to_value(cut::CutSettings::shown_defaults()).expect("settings serialize")
    }),
    stage::<predict::DomainCheck>("predict", defaults_of::<predict::DomainCheck>),
    stage::<import::ImportSettings>("import", defaults_of::<import::ImportSettings>),
    stage::<characterize::CharacterizeSettings>(
        "characterize",
        defaults_of::<characterize::CharacterizeSettings>,
    ),
    stage::<wear::WearSettings>("wear", defaults_of::<wear::WearSettings>),
];

/// The registry's entry of `name`, or an error listing the stages.
pub fn stage_settings(name: &str) -> Result<&'static StageSettings> {
    STAGES.iter().find(|s| s.name == name).ok_or_else(|| {
        let names: Vec<&str> = STAGES.iter().map(|s| s.name).collect();
        anyhow::anyhow!("stage '{name}': expected one of {}", names.join(", "))
    })
}

/// Settings of stage `stage` from JSON (an unknown or mistyped key is an error naming it;
/// a value refused by its type, such as a count beyond its cap, names its key too):
///
/// ```
/// use greybox_pipeline::settings::{from_json, fit::FitSettings, identify::IdentifySettings};
/// let e = from_json::<FitSettings>("fit", r#"{"data": "d.csv", "bootstrap": 1000000000}"#)
///     .unwrap_err();
/// assert!(format!("{e:#}").starts_with("fit.bootstrap: 1000000000 is above the cap"));
/// // a key of no field, also where a type gathers another's fields (identify's plan)
/// let e = from_json::<IdentifySettings>("identify", r#"{"normal_force_cout": 3}"#).unwrap_err();
/// assert!(format!("{e:#}").contains("identify.normal_force_cout: unknown key"));
/// ```
pub fn from_json<T: DeserializeOwned + Serialize>(stage: &str, text: &str) -> Result<T> {
    parse_keys(stage, text)
}

/// Settings from the keyword arguments of a call (Python's, as JSON): as [`from_json`],
/// the error starting with the key (`radius_mm: invalid type: …`), since the call names the
/// stage.
pub fn from_keywords<T: DeserializeOwned + Serialize>(text: &str) -> Result<T> {
    parse_keys("", text)
}

/// An error and its causes joined as `{:#}` joins them (`outer: inner: …`), each
/// [`SettingError`] worded by `name` (a surface's name of a setting: a flag, a keyword
/// argument) and every other cause's text passed through `text`.
pub fn render_error(
    e: &anyhow::Error,
    name: &dyn Fn(&SettingPath) -> String,
    text: &dyn Fn(&str) -> String,
) -> String {
    e.chain()
        .map(|cause| match greybox_core::error::as_setting(cause) {
            Some(s) => s.render(name),
            None => text(&cause.to_string()),
        })
        .collect::<Vec<_>>()
        .join(": ")
}

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

/// Settings of `stage` (`""`: unnamed) from JSON; a refusal is a [`SettingError`] naming the
/// key (and element) at fault.
fn parse_keys<T: DeserializeOwned + Serialize>(stage: &str, text: &str) -> Result<T> {
    let whole = |m: String| {
        let m = if stage.is_empty() {
            m
        } else {
            format!("{stage} settings: {m}")
        };
        anyhow::Error::new(SettingError::between(Vec::new(), m))
    };
    let given: serde_json::Value =
        serde_json::from_str(text).map_err(|e| whole(format!("not JSON: {e}")))?;
    let value: T = serde_path_to_error::deserialize(&given).map_err(|e| {
        let path = e.path().to_string();
        let text = e.into_inner().to_string();
        let path = match path.as_str() {
            // a flattened field's error has no path: the key whose value alone fails
            "." | "" => blame::<T>(&given, &text).unwrap_or_default(),
            _ => path,
        };
        if path.is_empty() {
            return whole(text);
        }
        let at = SettingPath::parse(stage, &path);
        // a value type that names its field already (`segment: 'x' is not one of …`,
        // `adhesive.method: …`): named once, by the path
        let text = match text.split_once(": ") {
            Some((name, rest)) if name == at.field || name.ends_with(&format!(".{}", at.field)) => {
                rest.to_string()
            }
            _ => text,
        };
        anyhow::Error::new(SettingError::new(at, text))
    })?;
    // Every field serializes under its key, so a key the value does not write back is one
    // no field took (`deny_unknown_fields` cannot see through a flattened field).
    let known = serde_json::to_value(&value)?;
    if let (Some(given), Some(known)) = (given.as_object(), known.as_object()) {
        if let Some(unknown) = given.keys().find(|k| !known.contains_key(*k)) {
            let mut names: Vec<&str> = known.keys().map(String::as_str).collect();
            names.sort_unstable();
            return Err(anyhow::Error::new(SettingError::new(
                SettingPath::new(stage, unknown.as_str()),
                format!("unknown key (known: {})", names.join(", ")),
            )));
        }
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each stage's defaults are settings of its type (the registry cannot pair a name with
    /// another stage's defaults), and the names are unique.
    #[test]
    fn every_stage_defaults_parse_back_as_its_settings() {
        for s in STAGES {
            let text = (s.defaults)().to_string();
            (s.parse)(&text).unwrap_or_else(|e| panic!("{}: {e:#}: {text}", s.name));
            let same_name = STAGES.iter().filter(|t| t.name == s.name).count();
            assert_eq!(same_name, 1, "{} is registered {same_name} times", s.name);
        }
        let e = stage_settings("fitt").unwrap_err().to_string();
        assert!(e.contains("expected one of identify, synth"), "{e}");
    }

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
