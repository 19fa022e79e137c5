//! Hertzian elastic contact (Johnson, *Contact Mechanics*, CUP 1985, ch. 4).
//!
//! Effective modulus: 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2 (a rigid body has E = ∞).
//!
//! Sphere (radius R) on flat, load F:
//! a = (3 F R / (4 E*))^(1/3), p0 = 3F/(2π a²) = (6 F E*² / (π³ R²))^(1/3),
//! p_m = F/(π a²) = (2/3) p0, approach δ = a²/R.
//!
//! Cylinder (radius R, length L) on flat, load per length P' = F/L:
//! b = (4 P' R / (π E*))^(1/2), p0 = 2P'/(π b), p_m = P'/(2b) = (π/4) p0.
//! The approach of a 2D contact depends on where the reference points sit and is not reported.
//!
//! The seed article's eq. 7 (its own convention, digest §3):
//! σ_H = (1/π)·cbrt(3 F E*² / (2 r²)) = p0 / 4^(1/3); it reproduces the article's
//! 914.7 MPa at 150 N and 2170 MPa at 2000 N with E1 = 210 GPa, E2 = 650 GPa, ν = 0.3, r = 17 mm.

use greybox_core::dataset::PressureConvention;
use greybox_core::{units, Error, Result};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Isotropic linear-elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    /// Young's modulus E, Pa (`f64::INFINITY` for a rigid body).
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
}

impl Elastic {
    pub fn new(youngs_modulus_pa: f64, poisson_ratio: f64) -> Self {
        Elastic {
            youngs_modulus_pa,
            poisson_ratio,
        }
    }
    pub const RIGID: Elastic = Elastic {
        youngs_modulus_pa: f64::INFINITY,
        poisson_ratio: 0.0,
    };
    fn validate(&self, name: &str) -> Result<()> {
        if !(self.youngs_modulus_pa > 0.0) {
            return Err(Error::invalid(
                name,
                format!(
                    "Young's modulus must be > 0, got {} Pa",
                    self.youngs_modulus_pa
                ),
            ));
        }
        if self.youngs_modulus_pa.is_finite() {
            greybox_core::physics::admit(
                greybox_core::physics::Quantity::YoungsModulus,
                self.youngs_modulus_pa,
                "youngs_modulus",
            )
            .map_err(|e| Error::invalid(name, e))?;
        }
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(Error::invalid(
                name,
                format!(
                    "Poisson's ratio must be in (-1, 0.5), got {}",
                    self.poisson_ratio
                ),
            ));
        }
        Ok(())
    }
}

/// Effective contact modulus E*, Pa: 1/E* = (1−ν1²)/E1 + (1−ν2²)/E2.
pub fn effective_modulus(body1: Elastic, body2: Elastic) -> Result<f64> {
    body1.validate("body 1")?;
    body2.validate("body 2")?;
    let c = |m: Elastic| {
        if m.youngs_modulus_pa.is_infinite() {
            0.0
        } else {
            (1.0 - m.poisson_ratio.powi(2)) / m.youngs_modulus_pa
        }
    };
    let inv = c(body1) + c(body2);
    if inv <= 0.0 {
        return Err(Error::invalid(
            "materials",
            "both bodies are rigid: E* is infinite",
        ));
    }
    Ok(1.0 / inv)
}

/// Result of a Hertz calculation, SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HertzContact {
    /// Contact radius a (sphere) or half-width b (cylinder), m.
    pub contact_half_width_m: f64,
    /// Maximum (central) pressure p0, Pa.
    pub max_pressure_pa: f64,
    /// Mean pressure p_m, Pa.
    pub mean_pressure_pa: f64,
    /// Mutual approach δ, m (sphere only).
    pub approach_m: Option<f64>,
}

fn positive(name: &str, v: f64, unit: &str) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            name,
            format!("must be a positive finite number, got {v} {unit}"),
        ))
    }
}

/// Sphere of radius `radius_m` on a flat, normal load `force_n`.
pub fn sphere_on_flat(force_n: f64, radius_m: f64, e_star_pa: f64) -> Result<HertzContact> {
    positive("normal force", force_n, "N")?;
    positive("sphere radius", radius_m, "m")?;
    positive("effective modulus", e_star_pa, "Pa")?;
    let a = (3.0 * force_n * radius_m / (4.0 * e_star_pa)).cbrt();
    let p0 = 3.0 * force_n / (2.0 * PI * a * a);
    Ok(HertzContact {
        contact_half_width_m: a,
        max_pressure_pa: p0,
        mean_pressure_pa: force_n / (PI * a * a),
        approach_m: Some(a * a / radius_m),
    })
}

/// Cylinder of radius `radius_m` and length `length_m` on a flat (line contact), load `force_n`.
pub fn cylinder_on_flat(
    force_n: f64,
    length_m: f64,
    radius_m: f64,
    e_star_pa: f64,
) -> Result<HertzContact> {
    positive("normal force", force_n, "N")?;
    positive("cylinder length", length_m, "m")?;
    positive("cylinder radius", radius_m, "m")?;
    positive("effective modulus", e_star_pa, "Pa")?;
    let p_line = force_n / length_m;
    let b = (4.0 * p_line * radius_m / (PI * e_star_pa)).sqrt();
    let p0 = 2.0 * p_line / (PI * b);
    Ok(HertzContact {
        contact_half_width_m: b,
        max_pressure_pa: p0,
        mean_pressure_pa: p_line / (2.0 * b),
        approach_m: None,
    })
}

/// The seed article's eq. 7 value, Pa: (1/π)·cbrt(3 F E*² / (2 r²)).
pub fn article_eq7_pressure(force_n: f64, radius_m: f64, e_star_pa: f64) -> Result<f64> {
    positive("normal force", force_n, "N")?;
    positive("sphere radius", radius_m, "m")?;
    positive("effective modulus", e_star_pa, "Pa")?;
    Ok((3.0 * force_n * e_star_pa * e_star_pa / (2.0 * radius_m * radius_m)).cbrt() / PI)
}

/// The article's pin tip radius, mm (a 17 mm carbide pin; digest §3): the default of every
/// setting that states a pin's radius.
pub const ARTICLE_PIN_TIP_RADIUS_MM: f64 = 17.0;

/// Pin-on-disk contact: pin tip sphere on the flat disk, with the pressure convention to report.
/// Field names carry their units (this is read from study TOML files).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PinContact {
    /// Pin tip radius, mm (article: 17 mm).
    pub pin_tip_radius_mm: f64,
    /// Disk (workpiece) Young's modulus, GPa (AISI 1045: 210 GPa).
    pub disk_youngs_modulus_gpa: f64,
    pub disk_poisson_ratio: f64,
    /// Pin Young's modulus, GPa (cemented carbide ≈ 650 GPa).
    pub pin_youngs_modulus_gpa: f64,
    pub pin_poisson_ratio: f64,
    /// Which pressure the dataset reports.
    pub convention: PressureConvention,
}

impl Default for PinContact {
    /// The article's pin and disk (digest §3), textbook maximum pressure.
    fn default() -> Self {
        PinContact {
            pin_tip_radius_mm: ARTICLE_PIN_TIP_RADIUS_MM,
            disk_youngs_modulus_gpa: 210.0,
            disk_poisson_ratio: 0.3,
            pin_youngs_modulus_gpa: 650.0,
            pin_poisson_ratio: 0.3,
            convention: PressureConvention::TextbookMax,
        }
    }
}

impl PinContact {
    pub fn radius_m(&self) -> f64 {
        self.pin_tip_radius_mm * units::M_PER_MM
    }
    pub fn effective_modulus_pa(&self) -> Result<f64> {
        effective_modulus(
            Elastic::new(
                self.disk_youngs_modulus_gpa * units::PA_PER_GPA,
                self.disk_poisson_ratio,
            ),
            Elastic::new(
                self.pin_youngs_modulus_gpa * units::PA_PER_GPA,
                self.pin_poisson_ratio,
            ),
        )
    }
    /// Full Hertz solution for a normal force.
    pub fn solve(&self, force_n: f64) -> Result<HertzContact> {
        sphere_on_flat(force_n, self.radius_m(), self.effective_modulus_pa()?)
    }
    /// The pressure under this contact's convention, Pa.
    pub fn pressure_pa(&self, force_n: f64) -> Result<f64> {
        self.pressure_pa_as(force_n, self.convention)
    }
    /// The pressure under any convention, Pa.
    pub fn pressure_pa_as(&self, force_n: f64, convention: PressureConvention) -> Result<f64> {
        Ok(match convention {
            PressureConvention::TextbookMax => self.solve(force_n)?.max_pressure_pa,
            PressureConvention::TextbookMean => self.solve(force_n)?.mean_pressure_pa,
            PressureConvention::ArticleEq7 => {
                article_eq7_pressure(force_n, self.radius_m(), self.effective_modulus_pa()?)?
            }
        })
    }
    /// Validate (also used after deserializing).
    pub fn validate(&self) -> Result<()> {
        positive("pin_tip_radius_mm", self.pin_tip_radius_mm, "mm")?;
        greybox_core::physics::admit(
            greybox_core::physics::Quantity::ContactRadius,
            self.radius_m(),
            "pin_tip_radius_mm (as m)",
        )
        .map_err(|e| Error::invalid("contact", e))?;
        self.effective_modulus_pa().map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    const MPA: f64 = 1e6;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// H1 (reference-values.md): steel ball R = 6.35 mm on steel flat, 210 GPa, ν = 0.3, 10 N
    /// → p_mean 574 MPa, p_max 861 MPa (moritzploss/tribology test suite, rounded to integer MPa).
    #[test]
    fn steel_ball_on_steel_flat() {
        let steel = Elastic::new(210e9, 0.3);
        let e = effective_modulus(steel, steel).unwrap();
        let h = sphere_on_flat(10.0, 6.35e-3, e).unwrap();
        assert!(
            (h.mean_pressure_pa / MPA - 574.0).abs() < 0.5,
            "{}",
            h.mean_pressure_pa / MPA
        );
        assert!(
            (h.max_pressure_pa / MPA - 861.0).abs() < 0.5,
            "{}",
            h.max_pressure_pa / MPA
        );
    }

    /// H2: elastic sphere R = 8 mm, E = 1000 MPa, ν = 0.3 on a rigid flat, F = 188.5 N → a = 1.010 mm.
    #[test]
    fn soft_sphere_on_rigid_flat() {
        let e = effective_modulus(Elastic::new(1000.0 * MPA, 0.3), Elastic::RIGID).unwrap();
        let h = sphere_on_flat(30.0 * 2.0 * PI, 8e-3, e).unwrap();
        assert!(
            (h.contact_half_width_m * 1e3 - 1.010).abs() < 0.0006,
            "{}",
            h.contact_half_width_m * 1e3
        );
    }

    /// The article's convention reproduces its 914.7 MPa (150 N) and 2170 MPa (2000 N) within 0.5 %.
    #[test]
    fn article_convention() {
        let c = PinContact {
            convention: PressureConvention::ArticleEq7,
            ..Default::default()
        };
        assert!(rel(c.pressure_pa(150.0).unwrap() / MPA, 914.7) < 0.005);
        assert!(rel(c.pressure_pa(2000.0).unwrap() / MPA, 2170.0) < 0.005);
        // and it is p0 / 4^(1/3) of the textbook maximum
        let p0 = c
            .pressure_pa_as(150.0, PressureConvention::TextbookMax)
            .unwrap();
        assert!(rel(p0 / 4f64.cbrt(), c.pressure_pa(150.0).unwrap()) < 1e-12);
    }

    /// Line contact: equilibrium ∫p = P' and b from the textbook form (H4: R = 10 mm steel/steel,
    /// P' = 100 N/mm → b = 0.10505 mm, p0 = 606.0 MPa, computed values in reference-values.md).
    #[test]
    fn cylinder_on_flat_values() {
        let steel = Elastic::new(210e9, 0.3);
        let e = effective_modulus(steel, steel).unwrap();
        let h = cylinder_on_flat(1000.0, 0.01, 0.01, e).unwrap();
        assert!(rel(h.contact_half_width_m * 1e3, 0.10505) < 1e-3);
        assert!(rel(h.max_pressure_pa / MPA, 606.0) < 1e-3);
        // equilibrium: (π/2) p0 b = P'
        assert!(rel(PI / 2.0 * h.max_pressure_pa * h.contact_half_width_m, 1.0e5) < 1e-12);
    }

    #[test]
    fn rejects_bad_parameters() {
        assert!(sphere_on_flat(-1.0, 0.01, 1e11).is_err());
        assert!(sphere_on_flat(f64::NAN, 0.01, 1e11).is_err());
        assert!(effective_modulus(Elastic::new(1e9, 0.6), Elastic::RIGID).is_err());
        assert!(effective_modulus(Elastic::RIGID, Elastic::RIGID).is_err());
    }
}
