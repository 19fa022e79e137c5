//! Hertzian contact of a sphere or a cylinder on a flat: contact size, maximum and mean
//! pressure, approach, and the pressure of a chosen convention.

use anyhow::Result;
use greybox_contact::hertz::{cylinder_on_flat, effective_modulus, Elastic};
use greybox_contact::PinContact;
use greybox_core::dataset::PressureConvention;
use greybox_core::units::{M_PER_MM, PA_PER_GPA, PA_PER_MPA};
use serde::Serialize;

/// The contact geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Geometry {
    /// Sphere (pin tip) on a flat: circular contact.
    Sphere,
    /// Cylinder of this length, mm, on a flat: line contact.
    Cylinder { length_mm: f64 },
}

/// The bodies: body 1 the disk (flat), body 2 the pin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzOptions {
    pub geometry: Geometry,
    /// Sphere or cylinder radius, mm.
    pub radius_mm: f64,
    /// Young's modulus of body 1, GPa (infinite: rigid).
    pub e1_gpa: f64,
    pub nu1: f64,
    /// Young's modulus of body 2, GPa (infinite: rigid).
    pub e2_gpa: f64,
    pub nu2: f64,
    /// The convention of `convention_pressure_mpa`.
    pub convention: PressureConvention,
}

/// The contact at one normal force.
#[derive(Debug, Clone, Serialize)]
pub struct HertzRow {
    pub force_n: f64,
    pub contact_half_width_mm: f64,
    pub max_pressure_mpa: f64,
    pub mean_pressure_mpa: f64,
    pub approach_um: Option<f64>,
    pub convention: String,
    pub convention_pressure_mpa: f64,
}

/// The effective modulus E*, Pa, and the contact at each of `forces_n`.
///
/// Against the textbook sphere-on-flat formulas (Johnson, *Contact Mechanics*, §4.2):
/// E* = 1 / ((1 − ν₁²)/E₁ + (1 − ν₂²)/E₂), a = (3FR / 4E*)^⅓, p₀ = 3F / (2πa²).
///
/// ```
/// use greybox_pipeline::hertz::{hertz, Geometry, HertzOptions};
/// use greybox_core::dataset::PressureConvention;
/// let o = HertzOptions {
///     geometry: Geometry::Sphere,
///     radius_mm: 17.0,
///     e1_gpa: 210.0,
///     nu1: 0.3,
///     e2_gpa: 650.0,
///     nu2: 0.3,
///     convention: PressureConvention::TextbookMax,
/// };
/// let (e_star, rows) = hertz(&o, &[1000.0]).unwrap();
/// let e: f64 = 1.0 / ((1.0 - 0.09) / 210e9 + (1.0 - 0.09) / 650e9);
/// let a: f64 = (3.0 * 1000.0 * 17e-3 / (4.0 * e)).cbrt();
/// let p0 = 3.0 * 1000.0 / (2.0 * std::f64::consts::PI * a * a);
/// assert!((e_star / e - 1.0).abs() < 1e-12);
/// assert!((rows[0].contact_half_width_mm / (a * 1e3) - 1.0).abs() < 1e-9);
/// assert!((rows[0].max_pressure_mpa / (p0 * 1e-6) - 1.0).abs() < 1e-9);
/// ```
pub fn hertz(o: &HertzOptions, forces_n: &[f64]) -> Result<(f64, Vec<HertzRow>)> {
    let e_star = effective_modulus(
        Elastic::new(o.e1_gpa * PA_PER_GPA, o.nu1),
        Elastic::new(o.e2_gpa * PA_PER_GPA, o.nu2),
    )?;
    let conv = o.convention;
    let mut rows = Vec::new();
    for &f in forces_n {
        let (h, pc) = match o.geometry {
            Geometry::Sphere => {
                let contact = PinContact {
                    pin_tip_radius_mm: o.radius_mm,
                    disk_youngs_modulus_gpa: o.e1_gpa,
                    disk_poisson_ratio: o.nu1,
                    pin_youngs_modulus_gpa: o.e2_gpa,
                    pin_poisson_ratio: o.nu2,
                    convention: conv,
                };
                (contact.solve(f)?, contact.pressure_pa(f)?)
            }
            Geometry::Cylinder { length_mm } => {
                if conv == PressureConvention::ArticleEq7 {
                    anyhow::bail!("the article's convention is defined for a sphere only");
                }
                let h = cylinder_on_flat(f, length_mm * M_PER_MM, o.radius_mm * M_PER_MM, e_star)?;
                let pc = if conv == PressureConvention::TextbookMean {
                    h.mean_pressure_pa
                } else {
                    h.max_pressure_pa
                };
                (h, pc)
            }
        };
        rows.push(HertzRow {
            force_n: f,
            contact_half_width_mm: h.contact_half_width_m / M_PER_MM,
            max_pressure_mpa: h.max_pressure_pa / PA_PER_MPA,
            mean_pressure_mpa: h.mean_pressure_pa / PA_PER_MPA,
            approach_um: h.approach_m.map(|d| d * 1e6),
            convention: conv.name().into(),
            convention_pressure_mpa: pc / PA_PER_MPA,
        });
    }
    Ok((e_star, rows))
}
