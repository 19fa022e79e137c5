//! The settings of one pin-sliding simulation (plane strain): the indentation, the pin, the
//! workpiece and the time scaling, in the units a user measures them in.
//!
//! ```
//! use greybox_pipeline::settings::pin::PinSettings;
//! let s: PinSettings = greybox_pipeline::settings::from_json("pin",
//!     r#"{"track_width_um": 1010, "mu": 0.2, "spacing_um": 5}"#)?;
//! let setup = s.setup()?;
//! assert!((setup.depth_m - (17e-3 - (17e-3f64.powi(2) - 505e-6f64.powi(2)).sqrt())).abs() < 1e-15);
//! let both = PinSettings { depth_um: Some(5.0), ..s };
//! assert!(both.setup().unwrap_err().to_string().starts_with("pin.depth_um"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::simulate::Indentation;
use anyhow::Result;
use greybox_contact::hertz::ARTICLE_PIN_TIP_RADIUS_MM;
use greybox_core::setting::refused_together;
use greybox_core::units::{m_per_min_to_m_per_s, mm_to_m, um_to_m};
use greybox_sim::pin::PinSetup;
use serde::{Deserialize, Serialize};

/// Defaults of a pin slide: the article's sliding speed and FE workpiece, a 1.5 mm slide of
/// 10 µm particles at μ 0.3, time scaled to 1 % of the elastic wave speed, no mass scaling.
pub const DEFAULT_MU: f64 = 0.3;
pub const DEFAULT_SPACING_UM: f64 = 10.0;
pub const DEFAULT_SLIDE_MM: f64 = 1.5;
pub const DEFAULT_HEIGHT_MM: f64 = 1.0;
pub const DEFAULT_SPEED_M_PER_MIN: f64 = 150.0;
pub const DEFAULT_MACH: f64 = 0.01;

/// One pin slide as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct PinSettings {
    /// Indentation depth, µm (or give the track width).
    #[cfg_attr(feature = "cli", arg(long = "depth-um"))]
    pub depth_um: Option<f64>,
    /// Measured track width, µm: depth d = r − √(r² − (w/2)²).
    #[cfg_attr(feature = "cli", arg(long = "track-width-um"))]
    pub track_width_um: Option<f64>,
    /// Pin tip radius, mm.
    #[cfg_attr(feature = "cli", arg(long = "pin-radius-mm", default_value_t = ARTICLE_PIN_TIP_RADIUS_MM))]
    pub pin_radius_mm: f64,
    /// Coulomb μ on the pin.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MU))]
    pub mu: f64,
    /// Particle spacing, µm.
    #[cfg_attr(feature = "cli", arg(long = "spacing-um", default_value_t = DEFAULT_SPACING_UM))]
    pub spacing_um: f64,
    /// Slide length after pressing, mm.
    #[cfg_attr(feature = "cli", arg(long = "slide-mm", default_value_t = DEFAULT_SLIDE_MM))]
    pub slide_mm: f64,
    /// Workpiece height, mm (the article's FE model: 1 mm).
    #[cfg_attr(feature = "cli", arg(long = "height-mm", default_value_t = DEFAULT_HEIGHT_MM))]
    pub height_mm: f64,
    /// Physical sliding speed (sets the J-C strain rate), m/min.
    #[cfg_attr(feature = "cli", arg(long = "speed-m-per-min", default_value_t = DEFAULT_SPEED_M_PER_MIN))]
    pub speed_m_per_min: f64,
    /// Simulated sliding speed / elastic wave speed (time scaling of the quasi-static slide).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_MACH))]
    pub mach: f64,
    /// Mass scaling factor (≥ 1).
    #[cfg_attr(feature = "cli", arg(long = "mass-scaling", default_value_t = 1.0))]
    pub mass_scaling: f64,
    /// Most particles the workpiece may have (numerics.max_particles; default 5 million,
    /// about 20 GB): a finer spacing is refused before anything is allocated.
    #[cfg_attr(feature = "cli", arg(long = "max-particles"))]
    pub max_particles: Option<greybox_sim::model::ParticleCap>,
}

impl Default for PinSettings {
    fn default() -> Self {
        PinSettings {
            depth_um: None,
            track_width_um: None,
            pin_radius_mm: ARTICLE_PIN_TIP_RADIUS_MM,
            mu: DEFAULT_MU,
            spacing_um: DEFAULT_SPACING_UM,
            slide_mm: DEFAULT_SLIDE_MM,
            height_mm: DEFAULT_HEIGHT_MM,
            speed_m_per_min: DEFAULT_SPEED_M_PER_MIN,
            mach: DEFAULT_MACH,
            mass_scaling: 1.0,
            max_particles: None,
        }
    }
}

impl PinSettings {
    /// The solver's set-up (SI), validated.
    pub fn setup(&self) -> Result<PinSetup> {
        let r = mm_to_m(self.pin_radius_mm);
        let depth = match (self.depth_um, self.track_width_um) {
            (Some(d), None) => Indentation::Depth(um_to_m(d)),
            (None, Some(w)) => Indentation::TrackWidth(um_to_m(w)),
            _ => {
                let one_of = ["depth_um", "track_width_um"];
                return Err(refused_together("pin", &one_of, "give exactly one of them").into());
            }
        }
        .depth_m(r)?;
        let mut s = PinSetup::article(depth, self.mu, um_to_m(self.spacing_um));
        s.pin_radius_m = r;
        s.slide_length_m = mm_to_m(self.slide_mm);
        s.workpiece_height_m = mm_to_m(self.height_mm);
        s.sliding_speed_m_s = m_per_min_to_m_per_s(self.speed_m_per_min);
        s.mach = self.mach;
        s.numerics.mass_scaling = self.mass_scaling;
        s.numerics.max_particles = self.max_particles;
        s.validate()?;
        Ok(s)
    }
}
