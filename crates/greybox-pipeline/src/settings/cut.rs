//! The settings of one orthogonal cut: the set-up, the friction law it runs with and the
//! share of its cut length, the same for `greybox simulate cutting` and Python's
//! `simulate_cut` (where the outputs, [`crate::simulate::RunOutput`], are their own settings).
//!
//! ```no_run
//! use greybox_pipeline::settings::cut::CutSettings;
//! let s: CutSettings = greybox_pipeline::settings::from_json("cut",
//!     r#"{"config": "examples/iwf-ti64-cut.toml", "law": "law.json", "fraction": 0.5}"#)?;
//! let case = s.case()?; // the set-up read, its law swapped for law.json
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::simulate::{read_cutting_setup, run_cut, CutCase, CutSummary, RunOutput};
use anyhow::Result;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::sync::Arc;

/// The whole configured cut length.
pub const DEFAULT_FRACTION: f64 = 1.0;

/// One cut as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields)]
pub struct CutSettings {
    /// Set-up TOML (a serialised cutting set-up; examples/iwf-ti64-cut.toml).
    #[cfg_attr(feature = "cli", arg(long))]
    pub config: PathBuf,
    /// A friction law (law, model or table file) in place of the set-up's own.
    #[cfg_attr(feature = "cli", arg(long))]
    #[serde(default)]
    pub law: Option<PathBuf>,
    /// Simulate this fraction of the configured cut length, in (0, 1].
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_FRACTION))]
    #[serde(default = "default_fraction")]
    pub fraction: f64,
}

fn default_fraction() -> f64 {
    DEFAULT_FRACTION
}

impl CutSettings {
    /// The settings with their defaults, the set-up (required) as an empty path.
    pub fn shown_defaults() -> Self {
        CutSettings {
            config: PathBuf::new(),
            law: None,
            fraction: DEFAULT_FRACTION,
        }
    }

    /// The cut these settings describe: the set-up read (its law relative to it), the law
    /// given here in its place.
    pub fn case(&self) -> Result<CutCase> {
        let mut case = read_cutting_setup(&self.config)?;
        if let Some(l) = &self.law {
            case.law = Arc::from(greybox_friction::spec::load_law(l)?);
            case.law_source = l.display().to_string();
            case.inputs.push(("law", l.clone()));
        }
        Ok(case)
    }

    /// Run the cut into `output`.
    pub fn run(&self, output: &RunOutput) -> Result<CutSummary> {
        run_cut(&self.case()?, self.fraction, output)
    }
}
