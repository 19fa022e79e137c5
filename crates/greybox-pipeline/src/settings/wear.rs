//! The settings of a wear evaluation (`greybox wear`): a wear-tests CSV, or one test's load,
//! speed and duration with exactly one way to its volume (measured, a height map of the worn
//! pin, or the scar's diameter) — one type, one default per field, checked once.
//!
//! ```
//! use greybox_pipeline::settings::{from_json, wear::{WearRun, WearSettings}};
//! let s: WearSettings = from_json("wear",
//!     r#"{"force_N": 500, "velocity_m_per_min": 60, "duration_s": 100, "volume_mm3": 0.3}"#)?;
//! let WearRun::One(r) = s.run()? else { panic!("one test") };
//! assert!((r.sliding_distance_m - 100.0).abs() < 1e-9);
//! let two: WearSettings = from_json("wear", r#"{"force_N": 500, "velocity_m_per_min": 60,
//!     "duration_s": 100, "volume_mm3": 0.3, "scar_diameter_mm": 1}"#)?;
//! let e = two.run().unwrap_err();
//! assert!(format!("{e:#}").contains("give exactly one way to the wear volume"), "{e:#}");
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::wear::{wear_rate, wear_tests, WearInput, WearResult, WearTestRow, WearVolume};
use anyhow::Result;
use greybox_contact::hertz::ARTICLE_PIN_TIP_RADIUS_MM;
use greybox_contact::wear::Reference;
#[cfg(feature = "cli")]
use greybox_core::choice::clap_parsers::choice;
use greybox_core::setting::{positive_if_given, refused_together};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The unworn form a height map is measured against.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReferenceForm {
    /// The pin's spherical tip (radius `pin_radius_mm`).
    #[default]
    Sphere,
    /// A plane.
    Plane,
}

greybox_core::choice!(ReferenceForm, "reference", [Sphere => "sphere", Plane => "plane"]);

/// One wear evaluation as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct WearSettings {
    /// Wear tests CSV (pin, normal_force_N, velocity_m_per_min, duration_s, k_1e-7_mm3_per_Nm,
    /// mean_depth_um): implied volumes V = k F s and k back from V (examples/wear-tests.csv
    /// holds the article's five tests).
    #[cfg_attr(feature = "cli", arg(long))]
    pub tests: Option<PathBuf>,
    /// Normal load of one test, N.
    #[cfg_attr(feature = "cli", arg(long = "force-N"))]
    pub force_N: Option<f64>,
    /// Sliding velocity of one test, m/min.
    #[cfg_attr(feature = "cli", arg(long = "velocity-m-per-min"))]
    pub velocity_m_per_min: Option<f64>,
    /// Duration of one test, s.
    #[cfg_attr(feature = "cli", arg(long = "duration-s"))]
    pub duration_s: Option<f64>,
    /// Measured wear volume, mm³.
    #[cfg_attr(feature = "cli", arg(long = "volume-mm3"))]
    pub volume_mm3: Option<f64>,
    /// Height map of the worn pin: CSV x_mm,y_mm,z_um on a regular grid.
    #[cfg_attr(feature = "cli", arg(long))]
    pub height_map: Option<PathBuf>,
    /// The unworn form the height map is measured against.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ReferenceForm::Sphere, value_parser = choice::<ReferenceForm>()))]
    pub reference: ReferenceForm,
    /// Pin tip radius for the sphere reference and the scar formula, mm.
    #[cfg_attr(feature = "cli", arg(long = "pin-radius-mm", default_value_t = ARTICLE_PIN_TIP_RADIUS_MM))]
    pub pin_radius_mm: f64,
    /// Diameter of a flat wear scar on the spherical tip, mm.
    #[cfg_attr(feature = "cli", arg(long = "scar-diameter-mm"))]
    pub scar_diameter_mm: Option<f64>,
    /// Hardness for the dimensionless K = k H, GPa.
    #[cfg_attr(feature = "cli", arg(long = "hardness-GPa"))]
    pub hardness_GPa: Option<f64>,
}

impl Default for WearSettings {
    fn default() -> Self {
        WearSettings {
            tests: None,
            force_N: None,
            velocity_m_per_min: None,
            duration_s: None,
            volume_mm3: None,
            height_map: None,
            reference: ReferenceForm::Sphere,
            pin_radius_mm: ARTICLE_PIN_TIP_RADIUS_MM,
            scar_diameter_mm: None,
            hardness_GPa: None,
        }
    }
}

/// What a wear evaluation gives: the rows of a tests file, or one test's rate.
#[derive(Debug, Clone)]
pub enum WearRun {
    Tests(Vec<WearTestRow>),
    One(WearResult),
}

impl WearSettings {
    /// Evaluate the tests file, or the one test these settings state.
    pub fn run(&self) -> Result<WearRun> {
        if let Some(t) = &self.tests {
            let one_test = [
                ("force_N", self.force_N.is_some()),
                ("velocity_m_per_min", self.velocity_m_per_min.is_some()),
                ("duration_s", self.duration_s.is_some()),
                ("volume_mm3", self.volume_mm3.is_some()),
                ("height_map", self.height_map.is_some()),
                ("scar_diameter_mm", self.scar_diameter_mm.is_some()),
            ];
            if let Some((field, _)) = one_test.iter().find(|(_, given)| *given) {
                let why = "give a tests file or one test's settings, not both";
                return Err(refused_together("wear", &["tests", field], why).into());
            }
            return Ok(WearRun::Tests(wear_tests(t)?));
        }
        Ok(WearRun::One(wear_rate(&self.input()?)?))
    }

    /// The one test these settings state, every number checked and the volume given one way.
    pub fn input(&self) -> Result<WearInput> {
        let (Some(f), Some(v), Some(t)) = (self.force_N, self.velocity_m_per_min, self.duration_s)
        else {
            let fields = ["force_N", "velocity_m_per_min", "duration_s"];
            let why = "give one test's load, velocity and duration (or a tests file, `tests`)";
            return Err(refused_together("wear", &fields, why).into());
        };
        let numbers = [
            ("force_N", Some(f)),
            ("velocity_m_per_min", Some(v)),
            ("duration_s", Some(t)),
            ("volume_mm3", self.volume_mm3),
            ("pin_radius_mm", Some(self.pin_radius_mm)),
            ("scar_diameter_mm", self.scar_diameter_mm),
            ("hardness_GPa", self.hardness_GPa),
        ];
        for (field, value) in numbers {
            positive_if_given("wear", field, value)?;
        }
        let reference = match self.reference {
            ReferenceForm::Sphere => Reference::Sphere {
                radius_mm: self.pin_radius_mm,
            },
            ReferenceForm::Plane => Reference::Plane,
        };
        let volume = match (self.volume_mm3, &self.height_map, self.scar_diameter_mm) {
            (Some(v), None, None) => WearVolume::Measured(v),
            (None, Some(path), None) => WearVolume::HeightMap {
                path: path.clone(),
                reference,
            },
            (None, None, Some(d)) => WearVolume::ScarDiameter(d),
            _ => {
                let fields = ["volume_mm3", "height_map", "scar_diameter_mm"];
                let why = "give exactly one way to the wear volume";
                return Err(refused_together("wear", &fields, why).into());
            }
        };
        Ok(WearInput {
            normal_force_n: f,
            velocity_m_per_min: v,
            duration_s: t,
            volume,
            pin_radius_mm: self.pin_radius_mm,
            hardness_gpa: self.hardness_GPa,
        })
    }
}
