//! A workpiece material: density, isotropic elasticity, a flow stress, optional ductile damage and
//! temperature-dependent thermal properties.

use crate::{FlowStress, JohnsonCook, JohnsonCookDamage, Table1d};
use serde::{Deserialize, Serialize};

/// Isotropic linear elasticity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Elastic {
    /// Young's modulus E, Pa.
    pub youngs_modulus_pa: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
}

impl Elastic {
    /// Shear modulus G = E / (2(1 + ν)), Pa.
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus_pa / (2.0 * (1.0 + self.poisson_ratio))
    }
    /// Bulk modulus K = E / (3(1 − 2ν)), Pa.
    pub fn bulk_modulus(&self) -> f64 {
        self.youngs_modulus_pa / (3.0 * (1.0 - 2.0 * self.poisson_ratio))
    }
    /// P-wave modulus K + 4G/3, Pa (sets the longitudinal wave speed √(M/ρ)).
    pub fn p_wave_modulus(&self) -> f64 {
        self.bulk_modulus() + 4.0 / 3.0 * self.shear_modulus()
    }
}

/// Thermal properties as functions of temperature (K).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Thermal {
    /// Conductivity λ(T), W/(m·K).
    pub conductivity: Table1d,
    /// Specific heat c_p(T), J/(kg·K).
    pub specific_heat: Table1d,
    /// Taylor–Quinney coefficient: share of plastic work turned into heat.
    pub taylor_quinney: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Material {
    pub name: String,
    /// Density ρ_0, kg/m³.
    pub density_kg_m3: f64,
    pub elastic: Elastic,
    /// Flow-stress model; `None`: purely elastic.
    pub plasticity: Option<FlowStress>,
    /// Ductile damage softening the flow stress (`[material.damage]`); `None`: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damage: Option<JohnsonCookDamage>,
    pub thermal: Thermal,
    /// Sources of the numbers, for reports.
    pub source: String,
}

impl Material {
    /// AISI 1045 as in the article (Table 4 J-C, ρ 7850 kg/m³, ν 0.3). The article gives E, λ
    /// and c_p only as temperature-dependent without values; the tables here are typical
    /// plain-carbon-steel values (E after the ASM Handbook vol. 1 trend for carbon steels;
    /// λ and c_p for AISI 1045 from the MatWeb/ASM data as tabulated in Jaspers 2002 and the
    /// NIST extended-Oxley inputs: λ = 52.61 − 0.0281 ΔT W/(m·K), c_p = 420 + 0.504 ΔT J/(kg·K)).
    pub fn aisi1045_article() -> Self {
        Material {
            name: "AISI 1045 (article Table 4)".into(),
            density_kg_m3: 7850.0,
            elastic: Elastic {
                youngs_modulus_pa: 205e9,
                poisson_ratio: 0.3,
            },
            plasticity: Some(JohnsonCook::aisi1045_article().into()),
            damage: None,
            thermal: Self::aisi1045_thermal(),
            source: "J-C: article Table 4; thermal: NIST extended-Oxley AISI 1045 inputs".into(),
        }
    }

    /// AISI 1045 with the Jaspers J-C set (NIST extended-Oxley condition), ρ = 8000 kg/m³.
    pub fn aisi1045_jaspers() -> Self {
        Material {
            name: "AISI 1045 (Jaspers J-C)".into(),
            density_kg_m3: 8000.0,
            elastic: Elastic {
                youngs_modulus_pa: 205e9,
                poisson_ratio: 0.3,
            },
            plasticity: Some(JohnsonCook::aisi1045_jaspers().into()),
            damage: None,
            thermal: Self::aisi1045_thermal(),
            source: "Jaspers & Dautzenberg 2002 via the NIST extended-Oxley inputs".into(),
        }
    }

    /// λ = 52.61 − 0.0281 ΔT, c_p = 420 + 0.504 ΔT (ΔT above 20 °C), tabulated to 1200 °C.
    fn aisi1045_thermal() -> Thermal {
        let t: Vec<f64> = (0..=12).map(|k| 293.15 + 100.0 * k as f64).collect();
        let dt = |x: &f64| x - 293.15;
        Thermal {
            conductivity: Table1d {
                x: t.clone(),
                y: t.iter().map(|x| 52.61 - 0.0281 * dt(x)).collect(),
            },
            specific_heat: Table1d {
                x: t.clone(),
                y: t.iter().map(|x| 420.0 + 0.504 * dt(x)).collect(),
            },
            taylor_quinney: 0.9,
        }
    }

    /// Ti6Al4V (the ETH IWF SPH cutting benchmark): ρ 4430 kg/m³, E 113.8 GPa, ν 0.342,
    /// λ 7.3 W/(m·K), c_p 560 J/(kg·K), standard J-C set.
    pub fn ti6al4v() -> Self {
        Material {
            name: "Ti6Al4V".into(),
            density_kg_m3: 4430.0,
            elastic: Elastic {
                youngs_modulus_pa: 113.8e9,
                poisson_ratio: 0.342,
            },
            plasticity: Some(JohnsonCook::ti6al4v().into()),
            damage: None,
            thermal: Thermal {
                conductivity: Table1d::constant(7.3),
                specific_heat: Table1d::constant(560.0),
                taylor_quinney: 0.9,
            },
            source: "standard Ti6Al4V J-C set (A 862, B 331 MPa, n 0.34, C 0.01, m 0.8)".into(),
        }
    }

    /// Ti6Al4V with the TANH Johnson–Cook of Sima & Özel 2010 (model 3; see
    /// [`crate::TanhJohnsonCook::ti6al4v_sima_ozel_2010`]) and the elastic and thermal data of
    /// [`Material::ti6al4v`] (c_p 580 J/(kg·K) as in the ETH IWF refinement code's set).
    pub fn ti6al4v_sima_ozel() -> Self {
        let mut m = Self::ti6al4v();
        m.name = "Ti6Al4V (Sima-Özel TANH)".into();
        m.plasticity = Some(FlowStress::Tanh(
            crate::TanhJohnsonCook::ti6al4v_sima_ozel_2010(),
        ));
        m.thermal.specific_heat = Table1d::constant(580.0);
        m.source = "TANH J-C: Sima & Özel, Int J Mach Tools Manuf 50 (2010) 943, model 3".into();
        m
    }

    /// Purely elastic steel (for wave and Hertz checks).
    pub fn elastic_steel() -> Self {
        Material {
            name: "elastic steel".into(),
            density_kg_m3: 7850.0,
            elastic: Elastic {
                youngs_modulus_pa: 200e9,
                poisson_ratio: 0.3,
            },
            plasticity: None,
            damage: None,
            thermal: Thermal {
                conductivity: Table1d::constant(50.0),
                specific_heat: Table1d::constant(470.0),
                taylor_quinney: 0.9,
            },
            source: "generic".into(),
        }
    }

    pub fn validate(&self) -> greybox_core::Result<()> {
        let e = &self.elastic;
        greybox_core::rules::Rules::new(format!("material '{}'", self.name))
            .positive("density_kg_m3", self.density_kg_m3)
            .physics(
                "density_kg_m3",
                greybox_core::physics::Quantity::Density,
                self.density_kg_m3,
            )
            .section("elastic", |r| {
                r.positive("youngs_modulus_pa", e.youngs_modulus_pa)
                    .physics(
                        "youngs_modulus_pa",
                        greybox_core::physics::Quantity::YoungsModulus,
                        e.youngs_modulus_pa,
                    )
                    .between("poisson_ratio", e.poisson_ratio, -1.0, 0.5);
            })
            .section("thermal", |r| {
                r.within("taylor_quinney", self.thermal.taylor_quinney, 0.0, 1.0);
            })
            .finish()?;
        if let Some(f) = &self.plasticity {
            f.validate()?;
        }
        if let Some(d) = &self.damage {
            if self.plasticity.is_none() {
                return Err(greybox_core::Error::invalid(
                    format!("material '{}'", self.name),
                    "damage needs a flow stress: [material.damage] softens [material.plasticity], which is absent",
                ));
            }
            d.validate()?;
        }
        self.thermal.conductivity.validate()?;
        self.thermal.specific_heat.validate()?;
        if self.thermal.conductivity.y.iter().any(|&v| v < 0.0)
            || self.thermal.specific_heat.y.iter().any(|&v| v <= 0.0)
        {
            return Err(greybox_core::Error::invalid(
                format!("material '{}'", self.name),
                "expected conductivity ≥ 0 and specific heat > 0",
            ));
        }
        Ok(())
    }
}
