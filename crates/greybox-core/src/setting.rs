//! A setting refused, typed: which setting — its stage, field and, for a list, the index —
//! and the value given, so that each surface names it in its own words. The command line
//! shows a field as its flag (`--track-radii-mm`) where the flag was given, and as the
//! study's key (`[identify] track_radii_mm`) where the value came from a file; Python as the
//! keyword argument (`track_radii_mm=`). The library's own wording ([`SettingError`]'s
//! `Display`) is the neutral `identify.track_radii_mm[1]`.
//!
//! ```
//! use greybox_core::setting::{SettingError, SettingPath};
//! let e = SettingError::new(SettingPath::new("identify", "track_radii_mm").at(1), "must be > 0")
//!     .value("-5");
//! assert_eq!(e.to_string(), "identify.track_radii_mm[1]: must be > 0, got -5");
//! // a surface names the field its own way
//! assert_eq!(
//!     e.render(|p| format!("{}=", p.field)),
//!     "track_radii_mm=: must be > 0, got -5"
//! );
//! ```

use std::fmt;

/// One setting: the stage whose settings hold it, the field (its key and, where a surface
/// has one, its argument's name) and the element of a list field.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SettingPath {
    /// The stage (`identify`, `fit`, `export`, …; `budget` for the readers' caps).
    pub stage: String,
    /// The field as its settings type names it (`track_radii_mm`).
    pub field: String,
    /// The element of a list field (0-based), where one element is refused.
    pub index: Option<usize>,
}

impl SettingPath {
    pub fn new(stage: impl Into<String>, field: impl Into<String>) -> Self {
        SettingPath {
            stage: stage.into(),
            field: field.into(),
            index: None,
        }
    }

    /// A setting as serde names the place of a refused value inside a settings type
    /// (`track_radii_mm[1]`, `plan.normal_force_count`: the first key is the field, a list
    /// index right after it the element).
    pub fn parse(stage: &str, path: &str) -> Self {
        let field_end = path.find(['.', '[']).unwrap_or(path.len());
        let index = path[field_end..]
            .strip_prefix('[')
            .and_then(|rest| rest.split(']').next())
            .and_then(|i| i.parse().ok());
        SettingPath {
            stage: stage.to_string(),
            field: path[..field_end].to_string(),
            index,
        }
    }

    /// The element `index` of this list field.
    pub fn at(mut self, index: usize) -> Self {
        self.index = Some(index);
        self
    }

    /// `[index]` where an element is named, else nothing: for a surface's own wording.
    pub fn index_suffix(&self) -> String {
        self.index.map(|i| format!("[{i}]")).unwrap_or_default()
    }
}

impl fmt::Display for SettingPath {
    /// `stage.field[index]`; `field[index]` where the stage is not known (`""`: keyword
    /// arguments of a call, which names its stage).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.stage.is_empty() {
            write!(f, "{}.", self.stage)?;
        }
        write!(f, "{}{}", self.field, self.index_suffix())
    }
}

/// A setting (or a combination of settings) refused: the settings named, the value given
/// where one value is at fault, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SettingError {
    /// The settings at fault (several for a rule between them; none for the settings as a
    /// whole, e.g. text that is not JSON).
    pub paths: Vec<SettingPath>,
    /// The value given, as the user wrote it or as greybox reads it.
    pub value: Option<String>,
    /// Why it is refused, and what to do.
    pub message: String,
}

impl SettingError {
    /// `path` refused for `message`.
    pub fn new(path: SettingPath, message: impl Into<String>) -> Self {
        SettingError {
            paths: vec![path],
            value: None,
            message: message.into(),
        }
    }

    /// A rule between several settings (`mu_min` and `mu_max`, one of `depth_um` and
    /// `track_width_um`), or none (`paths` empty) for the settings as a whole.
    pub fn between(paths: Vec<SettingPath>, message: impl Into<String>) -> Self {
        SettingError {
            paths,
            value: None,
            message: message.into(),
        }
    }

    /// The value given.
    pub fn value(mut self, value: impl fmt::Display) -> Self {
        self.value = Some(value.to_string());
        self
    }

    /// The message with each setting named by `name` (a surface's wording).
    pub fn render(&self, name: impl Fn(&SettingPath) -> String) -> String {
        let names: Vec<String> = self.paths.iter().map(name).collect();
        let mut out = if names.is_empty() {
            self.message.clone()
        } else {
            format!("{}: {}", names.join(", "), self.message)
        };
        if let Some(v) = &self.value {
            out.push_str(&format!(", got {v}"));
        }
        out
    }
}

impl fmt::Display for SettingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render(SettingPath::to_string))
    }
}

impl std::error::Error for SettingError {}

/// The setting `stage.field` refused for `message`.
pub fn refused(stage: &str, field: &str, message: impl Into<String>) -> SettingError {
    SettingError::new(SettingPath::new(stage, field), message)
}

/// A rule between several settings of one stage refused for `message` (one of
/// `depth_um` and `track_width_um`, `mu_min` below `mu_max`).
pub fn refused_together(stage: &str, fields: &[&str], message: impl Into<String>) -> SettingError {
    let paths = fields.iter().map(|f| SettingPath::new(stage, *f)).collect();
    SettingError::between(paths, message)
}

/// `value` where it is absent or a positive, finite number; else the setting `stage.field`
/// refused ([`positive`]).
pub fn positive_if_given(
    stage: &str,
    field: &str,
    value: Option<f64>,
) -> Result<Option<f64>, SettingError> {
    if let Some(x) = value {
        positive(stage, field, x)?;
    }
    Ok(value)
}

/// `Ok` where `value` is a positive, finite number; else the setting `stage.field` refused.
pub fn positive(stage: &str, field: &str, value: f64) -> Result<(), SettingError> {
    match value.is_finite() && value > 0.0 {
        true => Ok(()),
        false => Err(refused(
            stage,
            field,
            format!("expected a positive number, got {value}"),
        )),
    }
}
