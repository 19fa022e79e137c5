//! The settings of a Hertz contact calculation: one type for the command line and Python,
//! with the article's pin (17 mm WC-Co sphere) on a steel disk as defaults.
//!
//! ```
//! use greybox_pipeline::settings::{from_json, hertz::HertzSettings};
//! let s: HertzSettings = from_json("hertz", r#"{"force_N": [60]}"#)?;
//! let (_, rows) = s.run()?;
//! assert!((rows[0].max_pressure_mpa - 1068.7).abs() < 2.0);
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::hertz::{hertz, Geometry, HertzOptions, HertzRow};
use anyhow::Result;
use greybox_core::dataset::PressureConvention;
use greybox_core::setting::refused;
use serde::{Deserialize, Serialize};

/// Radius of the article's pin, mm.
pub const DEFAULT_RADIUS_MM: f64 = greybox_contact::hertz::ARTICLE_PIN_TIP_RADIUS_MM;
/// Young's modulus of the disk (steel), GPa.
pub const DEFAULT_E1_GPA: f64 = 210.0;
/// Young's modulus of the pin (WC-Co), GPa.
pub const DEFAULT_E2_GPA: f64 = 650.0;
/// Poisson's ratio of both bodies.
pub const DEFAULT_POISSON: f64 = 0.3;

/// The contact's shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum HertzShape {
    /// Sphere (pin tip) on a flat: circular contact.
    #[default]
    Sphere,
    /// Cylinder on a flat: line contact (needs `length_mm`).
    Cylinder,
}
greybox_core::choice!(HertzShape, "geometry", [Sphere => "sphere", Cylinder => "cylinder"]);

/// One Hertz calculation as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct HertzSettings {
    /// Normal force(s), N.
    #[cfg_attr(feature = "cli", arg(long = "force-N", num_args = 1.., required = true))]
    pub force_N: Vec<f64>,
    /// Sphere or cylinder radius, mm (article pin: 17).
    #[cfg_attr(feature = "cli", arg(long = "radius-mm", default_value_t = DEFAULT_RADIUS_MM))]
    pub radius_mm: f64,
    /// Sphere or cylinder.
    #[cfg_attr(feature = "cli", arg(long, default_value = "sphere",
        value_parser = greybox_core::choice::clap_parsers::choice::<HertzShape>()))]
    pub geometry: HertzShape,
    /// Cylinder length, mm.
    #[cfg_attr(feature = "cli", arg(long = "length-mm"))]
    pub length_mm: Option<f64>,
    /// Young's modulus of body 1 (disk), GPa; inf for rigid.
    #[cfg_attr(feature = "cli", arg(long = "e1-GPa", default_value_t = DEFAULT_E1_GPA))]
    pub e1_GPa: f64,
    /// Poisson's ratio of body 1.
    #[cfg_attr(feature = "cli", arg(long = "nu1", default_value_t = DEFAULT_POISSON))]
    pub nu1: f64,
    /// Young's modulus of body 2 (pin), GPa; inf for rigid.
    #[cfg_attr(feature = "cli", arg(long = "e2-GPa", default_value_t = DEFAULT_E2_GPA))]
    pub e2_GPa: f64,
    /// Poisson's ratio of body 2.
    #[cfg_attr(feature = "cli", arg(long = "nu2", default_value_t = DEFAULT_POISSON))]
    pub nu2: f64,
    /// Also report this convention's pressure (sphere only).
    #[cfg_attr(feature = "cli", arg(long, default_value = "textbook-max",
        value_parser = greybox_core::choice::clap_parsers::choice::<PressureConvention>()))]
    pub convention: PressureConvention,
}

impl Default for HertzSettings {
    fn default() -> Self {
        HertzSettings {
            force_N: Vec::new(),
            radius_mm: DEFAULT_RADIUS_MM,
            geometry: HertzShape::Sphere,
            length_mm: None,
            e1_GPa: DEFAULT_E1_GPA,
            nu1: DEFAULT_POISSON,
            e2_GPa: DEFAULT_E2_GPA,
            nu2: DEFAULT_POISSON,
            convention: PressureConvention::default(),
        }
    }
}

impl HertzSettings {
    /// The calculation's options.
    pub fn options(&self) -> Result<HertzOptions> {
        use greybox_core::physics::{admit_setting, Quantity};
        use greybox_core::setting::SettingPath;
        admit_setting(
            Quantity::ContactRadius,
            greybox_core::units::mm_to_m(self.radius_mm),
            &SettingPath::new("hertz", "radius_mm"),
        )?;
        for (k, &f) in self.force_N.iter().enumerate() {
            admit_setting(
                Quantity::NormalForce,
                f,
                &SettingPath::new("hertz", "force_N").at(k),
            )?;
        }
        let geometry = match (self.geometry, self.length_mm) {
            (HertzShape::Sphere, _) => Geometry::Sphere,
            (HertzShape::Cylinder, Some(length_mm)) => Geometry::Cylinder { length_mm },
            (HertzShape::Cylinder, None) => {
                return Err(refused("hertz", "length_mm", "a cylinder needs its length").into())
            }
        };
        Ok(HertzOptions {
            geometry,
            radius_mm: self.radius_mm,
            e1_gpa: self.e1_GPa,
            nu1: self.nu1,
            e2_gpa: self.e2_GPa,
            nu2: self.nu2,
            convention: self.convention,
        })
    }

    /// The effective modulus E*, Pa, and the contact at each force.
    pub fn run(&self) -> Result<(f64, Vec<HertzRow>)> {
        if self.force_N.is_empty() {
            return Err(refused("hertz", "force_N", "give at least one normal force").into());
        }
        hertz(&self.options()?, &self.force_N)
    }
}
