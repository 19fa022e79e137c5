//! The settings of an import (`greybox import`, Python's `import_model`, `from_sklearn`,
//! `from_xgboost`, `from_onnx`): what a model trained elsewhere does not say — its features'
//! names and units, the target, the training domain, the calibration rows, the interval's
//! coverage and the tribometer's pin contact — in one type, with one default per field,
//! checked once. The rows a Python caller hands over (training and calibration arrays) are
//! data, not settings: [`ImportSettings::options`] takes them beside the settings.
//!
//! ```
//! use greybox_pipeline::settings::{from_json, import::{ImportRows, ImportSettings}};
//! let s: ImportSettings = from_json("import", r#"{"domain": [[150, 2000], [20, 250]]}"#)?;
//! let o = s.options(ImportRows::default())?;
//! assert_eq!((o.target.as_str(), o.coverage), ("cof_adhesive", greybox_import::DEFAULT_COVERAGE));
//! // the domain is stated one way only, and each range is a range
//! let e = from_json::<ImportSettings>("import", r#"{"domain": [[5, 1]]}"#).unwrap_err();
//! assert!(format!("{e:#}").starts_with("import.domain[0]: 5..1 is not a range"), "{e:#}");
//! let both: ImportSettings = from_json("import",
//!     r#"{"domain": [[0, 1]], "training_data": "train.csv"}"#)?;
//! let e = both.options(ImportRows::default()).unwrap_err();
//! assert!(format!("{e:#}").contains("state the training domain one way"), "{e:#}");
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::import::ContactSpec;
use anyhow::Result;
use greybox_core::setting::refused_together;
use greybox_import::{Calibration, Domain, ImportOptions, DEFAULT_COVERAGE, DEFAULT_TARGET};
use greybox_model::modelfile::{FeatureRange, ForcePressure};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// One import as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct ImportSettings {
    /// Feature names with unit suffixes in the model's input order, comma-separated
    /// (e.g. normal_force_N,sliding_velocity_m_per_min); default: the names the model records.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub features: Option<Vec<String>>,
    /// Target name.
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_TARGET))]
    pub target: String,
    /// Training data (CSV with the feature columns): the training domain is taken from it
    /// (a greybox friction dataset also gives the model its contact).
    #[cfg_attr(feature = "cli", arg(long, conflicts_with = "domain"))]
    pub training_data: Option<PathBuf>,
    /// The training domain per feature, MIN:MAX comma-separated in feature order
    /// (e.g. 150:2000,20:250; Python: [(min, max), …]).
    #[cfg_attr(
        feature = "cli",
        arg(long, value_delimiter = ',', allow_hyphen_values = true)
    )]
    pub domain: Option<Vec<Span>>,
    /// Rows the model was not trained on (CSV with features and target): a split-conformal
    /// prediction interval and a held-out R².
    #[cfg_attr(feature = "cli", arg(long))]
    pub calibration: Option<PathBuf>,
    /// Nominal coverage of the prediction interval, in (0, 1).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_COVERAGE))]
    pub coverage: f64,
    /// The tribometer's pin contact (a study's `[contact]` table and/or its keys); on the
    /// command line its own flags (`--contact`, `--convention`, `--pin-tip-radius-mm`, …).
    #[cfg_attr(feature = "cli", arg(skip))]
    pub contact: ContactSpec,
}

impl Default for ImportSettings {
    fn default() -> Self {
        ImportSettings {
            features: None,
            target: DEFAULT_TARGET.into(),
            training_data: None,
            domain: None,
            calibration: None,
            coverage: DEFAULT_COVERAGE,
            contact: ContactSpec::default(),
        }
    }
}

/// The rows a caller hands over beside the settings (Python's arrays): the training rows
/// (with their contact where their table records one) and calibration rows with targets.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ImportRows {
    /// Training rows, feature units, one per sample.
    pub training: Option<Vec<Vec<f64>>>,
    /// The training table's force-to-pressure map (a friction dataset's columns).
    pub training_contact: Option<ForcePressure>,
    /// Calibration rows and their targets.
    pub calibration: Option<(Vec<Vec<f64>>, Vec<f64>)>,
}

impl ImportSettings {
    /// The import's options: the domain from exactly one of `domain`, `training_data` and
    /// the training rows; the calibration from the file or the rows, not both; the contact
    /// resolved (its study read). Errors name the settings at fault.
    pub fn options(&self, rows: ImportRows) -> Result<ImportOptions> {
        let domain = match (&self.domain, &self.training_data, rows.training) {
            (Some(d), None, None) => Domain::Stated(d.iter().map(|s| s.0).collect()),
            (None, Some(path), None) => Domain::Data(path.clone()),
            (None, None, Some(x)) => Domain::Rows {
                x,
                force_to_pressure: rows.training_contact,
            },
            _ => {
                let why = "state the training domain one way: its ranges, the training data CSV, or (from Python) the training rows";
                return Err(refused_together("import", &["domain", "training_data"], why).into());
            }
        };
        let calibration = match (&self.calibration, rows.calibration) {
            (Some(path), None) => Some(Calibration::File(path.clone())),
            (None, Some((x, y))) => Some(Calibration::Rows(x, y)),
            (None, None) => None,
            (Some(_), Some(_)) => {
                let why = "give the calibration rows as a CSV or (from Python) as rows, not both";
                return Err(greybox_core::setting::refused("import", "calibration", why).into());
            }
        };
        Ok(ImportOptions {
            features: self.features.clone(),
            target: self.target.clone(),
            domain,
            calibration,
            coverage: self.coverage,
            contact: self.contact.resolve()?,
        })
    }
}

/// One feature's training range, `MIN:MAX` on the command line and `[min, max]` in JSON,
/// refused unless both ends are finite and min ≤ max.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Span(pub FeatureRange);

impl Span {
    fn new(min: f64, max: f64) -> Result<Self, String> {
        if min.is_finite() && max.is_finite() && min <= max {
            Ok(Span(FeatureRange { min, max }))
        } else {
            Err(format!("{min}..{max} is not a range"))
        }
    }
}

impl std::str::FromStr for Span {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        let (a, b) = text
            .split_once(':')
            .ok_or_else(|| format!("'{text}': expected MIN:MAX"))?;
        let number = |s: &str| {
            s.trim()
                .parse::<f64>()
                .map_err(|_| format!("'{text}': '{s}' is not a number"))
        };
        Span::new(number(a)?, number(b)?)
    }
}

impl Serialize for Span {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        [self.0.min, self.0.max].serialize(s)
    }
}

impl<'de> Deserialize<'de> for Span {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let (min, max) = <(f64, f64)>::deserialize(d)?;
        Span::new(min, max).map_err(serde::de::Error::custom)
    }
}
