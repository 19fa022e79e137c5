//! The training-domain check of a prediction (`greybox predict`, Python's `Model.predict`
//! and `Model.mu`): one type, one default per field, checked once.
//!
//! ```
//! use greybox_pipeline::settings::{from_json, predict::DomainCheck};
//! use greybox_model::modelfile::DomainPolicy;
//! let c: DomainCheck = from_json("predict", r#"{"outside": "refuse"}"#)?;
//! assert_eq!((c.outside, c.checked()?.margin), (DomainPolicy::Refuse, 0.05));
//! let e = from_json::<DomainCheck>("predict", r#"{"outside": "clip"}"#).unwrap_err();
//! assert!(format!("{e:#}").starts_with("predict.outside: 'clip' is not one of warn, refuse"));
//! let e = DomainCheck { margin: -0.1, ..Default::default() }.checked().unwrap_err();
//! assert!(format!("{e:#}").starts_with("predict.margin: expected a fraction ≥ 0"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use anyhow::Result;
#[cfg(feature = "cli")]
use greybox_core::choice::clap_parsers::choice;
use greybox_core::setting::refused;
use greybox_model::modelfile::DomainPolicy;
use serde::{Deserialize, Serialize};

/// The tolerated distance outside the training domain, as a fraction of each feature's range.
pub const DEFAULT_MARGIN: f64 = 0.05;

/// What a prediction does with points outside the model's training domain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct DomainCheck {
    /// Points outside the training domain (widened by the margin): warn (predict, flag and
    /// warn) or refuse (an error).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DomainPolicy::Warn, value_parser = choice::<DomainPolicy>()))]
    #[serde(with = "greybox_core::choice::name")]
    pub outside: DomainPolicy,
    /// Tolerated distance outside the training domain, as a fraction of each feature's range.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MARGIN))]
    pub margin: f64,
}

impl Default for DomainCheck {
    fn default() -> Self {
        DomainCheck {
            outside: DomainPolicy::Warn,
            margin: DEFAULT_MARGIN,
        }
    }
}

impl DomainCheck {
    /// The check, its margin refused unless a finite fraction ≥ 0.
    pub fn checked(self) -> Result<Self> {
        if !(self.margin.is_finite() && self.margin >= 0.0) {
            let why = format!("expected a fraction ≥ 0, got {}", self.margin);
            return Err(refused("predict", "margin", why).into());
        }
        Ok(self)
    }
}
