//! The settings of one restart loop with an external FE engine.
//!
//! ```
//! use greybox_pipeline::settings::couple::CoupleSettings;
//! let s: CoupleSettings = greybox_pipeline::settings::from_json("couple",
//!     r#"{"engine": "command", "command": "./seg.sh {dir}", "windows": ["W1"], "law": "law.json"}"#)?;
//! assert_eq!(s.options()?.max_cycles, 20);
//! let e = CoupleSettings { law: Some("law.json".into()), ..Default::default() }.options().unwrap_err();
//! assert_eq!(e.to_string(), "couple.deck: the CalculiX deck is required for engine calculix");
//! let e = CoupleSettings { tol: f64::NAN, ..s }.options().unwrap_err();
//! assert_eq!(e.to_string(), "couple.tol: expected a positive number, got NaN");
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::couple::{CoupleOptions, EngineOptions};
use anyhow::Result;
use greybox_core::setting::refused;
use greybox_friction::grid::UnitSystem;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The engine run per segment (the names of [`EngineOptions`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EngineName {
    /// CalculiX (ccx) with *RESTART and *CHANGE FRICTION.
    #[default]
    Calculix,
    /// A user command per segment (friction.csv in, states.csv out).
    Command,
}

greybox_core::choice!(EngineName, "couple.engine", [Calculix => "calculix", Command => "command"]);

/// Defaults: the loop's work directory, cycle limit and tolerance, one segment's duration.
pub const DEFAULT_WORK: &str = "couple-out";
pub const DEFAULT_MAX_CYCLES: Cycles = Cycles::of(20);
/// Segments of one restart loop after the first: each is a run of the FE engine.
pub type Cycles = greybox_core::count::Count<1, 10_000>;
pub const DEFAULT_TOL: f64 = 1e-3;
pub const DEFAULT_SEGMENT_S: f64 = 1e-3;

/// One restart loop as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct CoupleSettings {
    /// The engine run per segment: calculix (ccx with *RESTART and *CHANGE FRICTION) or
    /// command (a user command per segment: friction.csv in, states.csv out).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = EngineName::Calculix,
        value_parser = greybox_core::choice::clap_parsers::choice::<EngineName>()))]
    pub engine: EngineName,
    /// CalculiX deck: model, contact pairs per window, first segment (with *RESTART,WRITE).
    #[cfg_attr(feature = "cli", arg(long))]
    pub deck: Option<PathBuf>,
    /// CalculiX segment-step template containing {{FRICTION}}.
    #[cfg_attr(feature = "cli", arg(long))]
    pub segment: Option<PathBuf>,
    /// The ccx binary.
    #[cfg_attr(feature = "cli", arg(long, default_value = "ccx"))]
    pub ccx: PathBuf,
    /// Command template of the command engine ({cycle}, {dir}, {prev_dir}).
    #[cfg_attr(feature = "cli", arg(long))]
    pub command: Option<String>,
    /// Window names of the command engine, comma-separated.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub windows: Vec<String>,
    /// Friction law (law file, model file or table).
    #[cfg_attr(feature = "cli", arg(long))]
    pub law: Option<PathBuf>,
    /// Work directory (one sub-directory per cycle).
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_WORK))]
    pub work: PathBuf,
    /// Most restart cycles.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MAX_CYCLES))]
    pub max_cycles: Cycles,
    /// Converged when every window's μ changes less than this.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_TOL))]
    pub tol: f64,
    /// The CalculiX deck's unit system: MPa-mm-s, Pa-m-s or MPa-mm-ms (stresses and lengths
    /// of its contact output).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = UnitSystem::MpaMmS,
        value_parser = greybox_core::choice::clap_parsers::choice::<UnitSystem>()))]
    pub units: UnitSystem,
    /// Physical duration of one segment, s (slip per segment / duration = sliding velocity).
    #[cfg_attr(feature = "cli", arg(long = "segment-s", default_value_t = DEFAULT_SEGMENT_S))]
    pub segment_s: f64,
}

impl Default for CoupleSettings {
    fn default() -> Self {
        CoupleSettings {
            engine: EngineName::Calculix,
            deck: None,
            segment: None,
            ccx: "ccx".into(),
            command: None,
            windows: Vec::new(),
            law: None,
            work: DEFAULT_WORK.into(),
            max_cycles: DEFAULT_MAX_CYCLES,
            tol: DEFAULT_TOL,
            units: UnitSystem::MpaMmS,
            segment_s: DEFAULT_SEGMENT_S,
        }
    }
}

/// `value`, or an error naming the setting the engine needs.
fn needed<T: Clone>(value: &Option<T>, field: &str, what: &str, engine: &str) -> Result<T> {
    value.clone().ok_or_else(|| -> anyhow::Error {
        refused(
            "couple",
            field,
            format!("{what} is required for engine {engine}"),
        )
        .into()
    })
}

impl CoupleSettings {
    /// The loop's options.
    pub fn options(&self) -> Result<CoupleOptions> {
        greybox_core::setting::positive("couple", "tol", self.tol)?;
        if !(self.segment_s.is_finite() && self.segment_s > 0.0) {
            let why = format!("expected a positive duration, s, got {}", self.segment_s);
            return Err(refused("couple", "segment_s", why).into());
        }
        let engine = match self.engine {
            EngineName::Calculix => EngineOptions::Calculix {
                ccx: self.ccx.clone(),
                deck: needed(&self.deck, "deck", "the CalculiX deck", "calculix")?,
                segment: needed(&self.segment, "segment", "the segment template", "calculix")?,
                pressure_pa_per_unit: self.units.pa_per_stress_unit(),
                length_m_per_unit: self.units.m_per_length_unit(),
                segment_s: self.segment_s,
            },
            EngineName::Command => EngineOptions::Command {
                command: needed(&self.command, "command", "the command template", "command")?,
                windows: self.windows.clone(),
            },
        };
        Ok(CoupleOptions {
            engine,
            law: self.law.clone().ok_or_else(|| {
                anyhow::Error::from(refused("couple", "law", "a friction law is required"))
            })?,
            work: self.work.clone(),
            max_cycles: self.max_cycles.get(),
            tol: self.tol,
        })
    }
}
