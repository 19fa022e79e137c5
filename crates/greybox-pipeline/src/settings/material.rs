//! The settings of the Johnson–Cook calibrations (`greybox material fit` and `fit-c`,
//! Python's `fit_flow_curves` and `fit_rate_sensitivity`): one type each, one default per
//! field. Field names carry the units the user states them in; the options inside are SI.
//!
//! ```
//! use greybox_pipeline::settings::{from_json, material::{FlowCurveSettings, RateSensitivitySettings}};
//! let s: FlowCurveSettings = from_json("material fit", r#"{"curves": "c.csv", "room_temperature_C": 20}"#)?;
//! assert_eq!(s.options().room_temperature_k, Some(293.15));
//! let c: RateSensitivitySettings = from_json("material fit-c",
//!     r#"{"config": "cut.toml", "measured_force_N_per_mm": 250}"#)?;
//! assert_eq!(c.options()?.measured_force_n_per_m, 250e3);
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::material::{CalibrationRuns, RateSensitivityOptions};
use anyhow::Result;
use greybox_core::setting::refused;
use greybox_core::setting::{SettingError, SettingPath};
use greybox_core::units::{celsius_to_kelvin, per_mm_to_per_m};
use greybox_material::fit::FitOptions;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Melting temperature of AISI 1045, K (the article's workpiece).
pub const DEFAULT_MELT_TEMPERATURE_K: f64 = 1773.0;
/// Relative RMS misfit above which a test temperature is flagged.
pub const DEFAULT_MISFIT_THRESHOLD: f64 = 0.05;
/// The range of C searched: from …
pub const DEFAULT_C_MIN: f64 = 0.0;
/// … to.
pub const DEFAULT_C_MAX: f64 = 0.1;
/// The force match that ends the search, N/mm.
pub const DEFAULT_FORCE_TOLERANCE_N_PER_MM: f64 = 3.0;
/// Cutting simulations of one calibration at most.
pub const DEFAULT_CALIBRATION_RUNS: CalibrationRuns = CalibrationRuns::of(6);

/// A fit of Johnson–Cook A, B, n, m to compression flow curves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct FlowCurveSettings {
    /// Flow-curve CSV (strain, stress_MPa, temperature_C, strain_rate_per_s).
    #[cfg_attr(feature = "cli", arg(long))]
    pub curves: PathBuf,
    /// Strain-rate sensitivity C held fixed (find it with `material fit-c`).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = 0.0))]
    pub c: f64,
    /// Reference strain rate ε̇₀, 1/s (default: the lowest rate in the data).
    #[cfg_attr(feature = "cli", arg(long = "ref-strain-rate-per-s"))]
    pub ref_strain_rate_per_s: Option<f64>,
    /// Room temperature of the J-C T*, °C (default: the lowest test temperature).
    #[cfg_attr(feature = "cli", arg(long = "room-temperature-c"))]
    pub room_temperature_C: Option<f64>,
    /// Melting temperature, K (AISI 1045: 1773).
    #[cfg_attr(feature = "cli", arg(long = "melt-temperature-k",
        default_value_t = DEFAULT_MELT_TEMPERATURE_K))]
    pub melt_temperature_K: f64,
    /// Flag temperatures whose relative RMS misfit exceeds this.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MISFIT_THRESHOLD))]
    pub misfit_threshold: f64,
    /// Write the fit (parameters, residuals, warnings) as JSON here.
    #[cfg_attr(feature = "cli", arg(long))]
    pub out: Option<PathBuf>,
}

impl Default for FlowCurveSettings {
    fn default() -> Self {
        FlowCurveSettings {
            curves: PathBuf::new(),
            c: 0.0,
            ref_strain_rate_per_s: None,
            room_temperature_C: None,
            melt_temperature_K: DEFAULT_MELT_TEMPERATURE_K,
            misfit_threshold: DEFAULT_MISFIT_THRESHOLD,
            out: None,
        }
    }
}

impl FlowCurveSettings {
    /// The fit's options (SI).
    pub fn options(&self) -> FitOptions {
        FitOptions {
            c: self.c,
            ref_strain_rate: self.ref_strain_rate_per_s,
            room_temperature_k: self.room_temperature_C.map(celsius_to_kelvin),
            melt_temperature_k: self.melt_temperature_K,
            misfit_threshold: self.misfit_threshold,
        }
    }

    /// Fit the flow curves (and write the fit to `out`, when given).
    pub fn run(&self) -> Result<greybox_material::fit::JcFit> {
        if self.curves.as_os_str().is_empty() {
            return Err(refused("material", "curves", "give the flow-curve CSV").into());
        }
        crate::material::fit_flow_curves(&self.curves, &self.options(), self.out.as_deref())
    }
}

/// A search for Johnson–Cook C that matches a measured cutting force.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct RateSensitivitySettings {
    /// Cutting set-up TOML (its material's C is replaced in each run).
    #[cfg_attr(feature = "cli", arg(long))]
    pub config: PathBuf,
    /// Measured cutting force per unit width, N/mm (required).
    #[cfg_attr(
        feature = "cli",
        arg(long = "measured-force-n-per-mm", required = true)
    )]
    pub measured_force_N_per_mm: Option<f64>,
    /// Lower end of the C searched.
    #[cfg_attr(feature = "cli", arg(long = "c-min", default_value_t = DEFAULT_C_MIN))]
    pub c_min: f64,
    /// Upper end of the C searched.
    #[cfg_attr(feature = "cli", arg(long = "c-max", default_value_t = DEFAULT_C_MAX))]
    pub c_max: f64,
    /// Stop when the force is matched within this, N/mm.
    #[cfg_attr(feature = "cli", arg(long = "tolerance-n-per-mm",
        default_value_t = DEFAULT_FORCE_TOLERANCE_N_PER_MM))]
    pub tolerance_N_per_mm: f64,
    /// At most this many cutting simulations.
    #[cfg_attr(feature = "cli", arg(long = "max-runs", default_value_t = DEFAULT_CALIBRATION_RUNS))]
    pub max_runs: CalibrationRuns,
    /// Write the result as JSON here.
    #[cfg_attr(feature = "cli", arg(long))]
    pub out: Option<PathBuf>,
}

impl Default for RateSensitivitySettings {
    fn default() -> Self {
        RateSensitivitySettings {
            config: PathBuf::new(),
            measured_force_N_per_mm: None,
            c_min: DEFAULT_C_MIN,
            c_max: DEFAULT_C_MAX,
            tolerance_N_per_mm: DEFAULT_FORCE_TOLERANCE_N_PER_MM,
            max_runs: DEFAULT_CALIBRATION_RUNS,
            out: None,
        }
    }
}

impl RateSensitivitySettings {
    /// The search's options (SI).
    pub fn options(&self) -> Result<RateSensitivityOptions> {
        if self.config.as_os_str().is_empty() {
            return Err(refused("material", "config", "give the cutting set-up TOML").into());
        }
        let at = SettingPath::new("material", "measured_force_N_per_mm");
        let why = "give the measured cutting force per width, a positive number";
        let force = match self.measured_force_N_per_mm {
            Some(f) if f.is_finite() && f > 0.0 => f,
            Some(f) => return Err(SettingError::new(at, why).value(f).into()),
            None => return Err(SettingError::new(at, why).into()),
        };
        Ok(RateSensitivityOptions {
            config: self.config.clone(),
            measured_force_n_per_m: per_mm_to_per_m(force),
            c_range: (self.c_min, self.c_max),
            tolerance_n_per_m: per_mm_to_per_m(self.tolerance_N_per_mm),
            max_runs: self.max_runs,
            out: self.out.clone(),
        })
    }
}
