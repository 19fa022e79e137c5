//! The settings of one ploughing correction: the method, the pin, the measured track widths
//! and (inverse simulation) the runs.
//!
//! ```
//! use greybox_pipeline::adhesive::AdhesiveMethod;
//! use greybox_pipeline::settings::adhesive::AdhesiveSettings;
//! let s: AdhesiveSettings = greybox_pipeline::settings::from_json("adhesive",
//!     r#"{"data": "d.csv", "method": "simulation", "sim_loads": 2, "track_width": ["1777:1010"]}"#)?;
//! let o = s.options()?;
//! assert!(matches!(o.method, AdhesiveMethod::Simulation(ref m) if m.loads.get() == 2));
//! assert_eq!(o.track_widths[0].width_um, 1010.0);
//! let bad = AdhesiveSettings { track_width: vec!["1777".into()], ..Default::default() };
//! assert!(bad.options().unwrap_err().to_string().starts_with("adhesive.track_width"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::adhesive::{
    AdhesiveMethod, AdhesiveOptions, LoadStride, SimLoads, SimRuns, Simulation3dOptions,
    SimulationOptions,
};
use anyhow::Result;
use greybox_contact::hertz::ARTICLE_PIN_TIP_RADIUS_MM;
use greybox_contact::ploughing::TrackWidth;
use greybox_core::setting::{SettingError, SettingPath};
use greybox_couple::pin3d;
use greybox_couple::pin3d::Increments;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// How the ploughing share is found (the names of [`AdhesiveMethod`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Bowden–Tabor sphere ploughing with measured track widths.
    #[default]
    Analytic,
    /// Inverse pin-sliding simulation with the built-in SPH solver (plane strain).
    Simulation,
    /// The article's inverse route on a 3D model of the spherical pin (CalculiX).
    Simulation3d,
}

greybox_core::choice!(Method, "adhesive.method", [Analytic => "analytic", Simulation => "simulation", Simulation3d => "simulation-3d"]);

/// The default output dataset.
pub const DEFAULT_OUT: &str = "dataset_adhesive.csv";

const SIM: SimulationOptions = SimulationOptions::DEFAULT;

/// One ploughing correction as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct AdhesiveSettings {
    /// Friction dataset CSV from `greybox identify`.
    #[cfg_attr(feature = "cli", arg(long))]
    pub data: PathBuf,
    /// How the ploughing share is found: analytic (Bowden–Tabor sphere ploughing with the
    /// track widths), simulation (inverse pin sliding in plane strain, built-in solver) or
    /// simulation-3d (the article's inverse route on a 3D spherical pin, CalculiX).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = Method::Analytic,
        value_parser = greybox_core::choice::clap_parsers::choice::<Method>()))]
    pub method: Method,
    /// Pin tip radius, mm.
    #[cfg_attr(feature = "cli", arg(long = "pin-radius-mm", default_value_t = ARTICLE_PIN_TIP_RADIUS_MM))]
    pub pin_radius_mm: f64,
    /// Measured track width as FORCE_N:WIDTH_um (repeatable); default: the article's Table 3.
    #[cfg_attr(feature = "cli", arg(long = "track-width"))]
    pub track_width: Vec<String>,
    /// CSV of measured track widths with columns normal_force_N, track_width_um.
    #[cfg_attr(feature = "cli", arg(long = "track-widths-csv"))]
    pub track_widths_csv: Option<PathBuf>,
    /// Output dataset with the cof_adhesive column (the correction goes beside it as
    /// .correction.json).
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_OUT))]
    pub out: PathBuf,
    /// Simulation: number of highest distinct loads simulated (the share is fitted against
    /// load and applied to all loads, as in the article).
    #[cfg_attr(feature = "cli", arg(long = "sim-loads", default_value_t = SIM.loads))]
    pub sim_loads: SimLoads,
    /// Simulation: particle spacing, µm.
    #[cfg_attr(feature = "cli", arg(long = "sim-spacing-um", default_value_t = SIM.spacing_um))]
    pub sim_spacing_um: f64,
    /// Simulation: slide length, mm.
    #[cfg_attr(feature = "cli", arg(long = "sim-slide-mm", default_value_t = SIM.slide_mm))]
    pub sim_slide_mm: f64,
    /// Simulation: workpiece height, mm (the article's FE model: 1 mm).
    #[cfg_attr(feature = "cli", arg(long = "sim-height-mm", default_value_t = SIM.height_mm))]
    pub sim_height_mm: f64,
    /// Simulation: stop when |simulated F_t/F_N − μ_app| ≤ this.
    #[cfg_attr(feature = "cli", arg(long = "sim-tolerance", default_value_t = SIM.tolerance))]
    pub sim_tolerance: f64,
    /// Simulation: maximum runs per load.
    #[cfg_attr(feature = "cli", arg(long = "sim-max-runs", default_value_t = SIM.max_runs))]
    pub sim_max_runs: SimRuns,
    /// simulation-3d: number of loads simulated.
    #[cfg_attr(feature = "cli", arg(long = "sim3d-loads", default_value_t = SIM3D_LOADS))]
    pub sim3d_loads: SimLoads,
    /// simulation-3d: take every n-th distinct load from the highest (the article: 2).
    #[cfg_attr(feature = "cli", arg(long = "sim3d-load-stride", default_value_t = SIM3D_LOAD_STRIDE))]
    pub sim3d_load_stride: LoadStride,
    /// simulation-3d: elements per nominal contact radius √(2rd − d²).
    #[cfg_attr(feature = "cli", arg(long = "sim3d-elements-per-radius", default_value_t = pin3d::ELEMENTS_PER_RADIUS))]
    pub sim3d_elements_per_radius: f64,
    /// simulation-3d: slide length in nominal contact radii.
    #[cfg_attr(feature = "cli", arg(long = "sim3d-slide-per-radius", default_value_t = pin3d::SLIDE_PER_RADIUS))]
    pub sim3d_slide_per_radius: f64,
    /// simulation-3d: slide increments (the quasi-static analysis's one step size).
    #[cfg_attr(feature = "cli", arg(long = "sim3d-increments", default_value_t = SIM3D_INCREMENTS))]
    pub sim3d_increments: Increments,
    /// simulation-3d: the CalculiX executable.
    #[cfg_attr(feature = "cli", arg(long = "ccx", default_value = DEFAULT_CCX))]
    pub ccx: PathBuf,
}

/// The article's inverse plan: six loads, every second one from the highest.
pub const SIM3D_LOADS: SimLoads = SimLoads::of(6);
/// See [`SIM3D_LOADS`].
pub const SIM3D_LOAD_STRIDE: LoadStride = LoadStride::of(2);
/// The slide increments of one 3D run ([`pin3d::INCREMENTS`]).
pub const SIM3D_INCREMENTS: Increments = Increments::of(pin3d::INCREMENTS as u64);
/// The CalculiX executable looked up on the PATH.
pub const DEFAULT_CCX: &str = "ccx";

impl Default for AdhesiveSettings {
    fn default() -> Self {
        AdhesiveSettings {
            data: PathBuf::new(),
            method: Method::Analytic,
            pin_radius_mm: ARTICLE_PIN_TIP_RADIUS_MM,
            track_width: Vec::new(),
            track_widths_csv: None,
            out: DEFAULT_OUT.into(),
            sim_loads: SIM.loads,
            sim_spacing_um: SIM.spacing_um,
            sim_slide_mm: SIM.slide_mm,
            sim_height_mm: SIM.height_mm,
            sim_tolerance: SIM.tolerance,
            sim_max_runs: SIM.max_runs,
            sim3d_loads: SIM3D_LOADS,
            sim3d_load_stride: SIM3D_LOAD_STRIDE,
            sim3d_elements_per_radius: pin3d::ELEMENTS_PER_RADIUS,
            sim3d_slide_per_radius: pin3d::SLIDE_PER_RADIUS,
            sim3d_increments: SIM3D_INCREMENTS,
            ccx: DEFAULT_CCX.into(),
        }
    }
}

/// `FORCE_N:WIDTH_um` as a track width.
fn track_width(text: &str) -> Result<TrackWidth> {
    let refused = |why: String| {
        SettingError::new(SettingPath::new("adhesive", "track_width"), why)
            .value(format!("'{text}'"))
    };
    let (f, w) = text
        .split_once(':')
        .ok_or_else(|| anyhow::Error::from(refused("expected FORCE_N:WIDTH_um".into())))?;
    let number = |s: &str| match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(refused(format!("'{s}' is not a number"))),
    };
    Ok(TrackWidth {
        normal_force_n: number(f)?,
        width_um: number(w)?,
    })
}

impl AdhesiveSettings {
    /// The stage's options.
    pub fn options(&self) -> Result<AdhesiveOptions> {
        if !(self.pin_radius_mm.is_finite() && self.pin_radius_mm > 0.0) {
            let why = format!("expected a positive radius, mm, got {}", self.pin_radius_mm);
            return Err(greybox_core::setting::refused("adhesive", "pin_radius_mm", why).into());
        }
        Ok(AdhesiveOptions {
            data: self.data.clone(),
            method: match self.method {
                Method::Analytic => AdhesiveMethod::Analytic,
                Method::Simulation => AdhesiveMethod::Simulation(SimulationOptions {
                    loads: self.sim_loads,
                    spacing_um: self.sim_spacing_um,
                    slide_mm: self.sim_slide_mm,
                    height_mm: self.sim_height_mm,
                    tolerance: self.sim_tolerance,
                    max_runs: self.sim_max_runs,
                }),
                Method::Simulation3d => AdhesiveMethod::Simulation3d(Simulation3dOptions {
                    loads: self.sim3d_loads,
                    load_stride: self.sim3d_load_stride,
                    elements_per_radius: self.sim3d_elements_per_radius,
                    slide_per_radius: self.sim3d_slide_per_radius,
                    increments: self.sim3d_increments,
                    tolerance: self.sim_tolerance,
                    max_runs: self.sim_max_runs,
                    ccx: self.ccx.clone(),
                }),
            },
            pin_radius_mm: self.pin_radius_mm,
            track_widths: self
                .track_width
                .iter()
                .map(|t| track_width(t))
                .collect::<Result<_>>()?,
            track_widths_csv: self.track_widths_csv.clone(),
            out: self.out.clone(),
        })
    }
}
