//! The flow-stress models a workpiece can have, chosen by `model` in the material's
//! `plasticity` table:
//! * `johnson_cook` (the default when `model` is absent, so older set-ups read unchanged):
//!   [`JohnsonCook`];
//! * `tanh`: the TANH-type Johnson–Cook of Calamaz 2008 / Sima & Özel 2010 ([`TanhJohnsonCook`]);
//! * `table`: measured flow curves σ(ε_p, ε̇_p, T) read from a CSV file ([`FlowTable`]).

use crate::tanh::TanhAt;
use crate::{FlowTable, JohnsonCook, TanhJohnsonCook};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "model", rename_all = "snake_case")]
pub enum FlowStress {
    JohnsonCook(JohnsonCook),
    Tanh(TanhJohnsonCook),
    Table(FlowTable),
}

impl<'de> Deserialize<'de> for FlowStress {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let mut v = serde_json::Value::deserialize(d)?;
        let model = match v.as_object_mut() {
            Some(o) => match o.remove("model") {
                None => "johnson_cook".to_string(),
                Some(serde_json::Value::String(s)) => s,
                Some(other) => {
                    return Err(D::Error::custom(format!(
                        "plasticity.model: expected \"johnson_cook\", \"tanh\" or \"table\", got {other}"
                    )))
                }
            },
            None => return Err(D::Error::custom("plasticity: expected a table of parameters")),
        };
        let err = |e: serde_json::Error| D::Error::custom(format!("plasticity ({model}): {e}"));
        match model.as_str() {
            "johnson_cook" => serde_json::from_value(v).map(FlowStress::JohnsonCook).map_err(err),
            "tanh" => serde_json::from_value(v).map(FlowStress::Tanh).map_err(err),
            "table" => serde_json::from_value(v).map(FlowStress::Table).map_err(err),
            other => Err(D::Error::custom(format!(
                "plasticity.model: expected \"johnson_cook\", \"tanh\" or \"table\", got \"{other}\""
            ))),
        }
    }
}

impl From<JohnsonCook> for FlowStress {
    fn from(jc: JohnsonCook) -> Self {
        FlowStress::JohnsonCook(jc)
    }
}

impl FlowStress {
    /// Flow stress σ_y(ε_p, ε̇_p, T), Pa.
    pub fn flow_stress(&self, eps_p: f64, strain_rate: f64, temperature_k: f64) -> f64 {
        match self {
            FlowStress::JohnsonCook(m) => m.flow_stress(eps_p, strain_rate, temperature_k),
            FlowStress::Tanh(m) => m.flow_stress(eps_p, strain_rate, temperature_k),
            FlowStress::Table(m) => m.flow_stress(eps_p, strain_rate, temperature_k),
        }
    }

    /// σ_y, ∂σ_y/∂ε_p and ∂σ_y/∂ln ε̇_p, Pa (the table's by central differences over a
    /// 10⁻⁶ relative step: its curves are piecewise linear).
    pub fn flow_stress_slopes(&self, eps_p: f64, strain_rate: f64, t: f64) -> (f64, f64, f64) {
        match self {
            FlowStress::JohnsonCook(m) => {
                let e = eps_p.max(0.0);
                let h = m.hardening(e);
                let dh = if e > 0.0 {
                    m.b_pa * m.n * e.powf(m.n - 1.0)
                } else {
                    0.0
                };
                let (rf, drf) = m.rate_factor_and_slope(strain_rate);
                let soft = m.thermal_factor(t);
                (h * rf * soft, dh * rf * soft, h * drf * soft)
            }
            FlowStress::Tanh(m) => m.flow_stress_slopes(eps_p, strain_rate, t),
            FlowStress::Table(m) => {
                let s = m.flow_stress(eps_p, strain_rate, t);
                let de = 1e-6 * eps_p.max(1e-3);
                let e0 = (eps_p - de).max(0.0);
                let ds_de = (m.flow_stress(eps_p + de, strain_rate, t)
                    - m.flow_stress(e0, strain_rate, t))
                    / (eps_p + de - e0);
                let f = 1.0 + 1e-6;
                let ds_dlnr = (m.flow_stress(eps_p, strain_rate * f, t)
                    - m.flow_stress(eps_p, strain_rate / f, t))
                    / (2.0 * f.ln());
                (s, ds_de, ds_dlnr)
            }
        }
    }

    /// The model at temperature `t` (K), for evaluating it at many (ε_p, ε̇_p) with the
    /// temperature's factors computed once (the radial return's iterations).
    #[inline]
    pub fn at_temperature(&self, t: f64) -> FlowAt<'_> {
        match self {
            FlowStress::Tanh(m) => FlowAt::Tanh(m.at_temperature(t)),
            other => FlowAt::Any(other, t),
        }
    }

    /// The largest strain hardening over every ε_p, Pa, where the model has one worth a
    /// quick test ([`FlowAt::quasi_static_ceiling`]; TANH: [`TanhJohnsonCook::hardening_peak_pa`]);
    /// `None` otherwise. Computed once per pass by the radial return's caller.
    pub fn hardening_peak_pa(&self) -> Option<f64> {
        match self {
            FlowStress::Tanh(m) => Some(m.hardening_peak_pa()),
            _ => None,
        }
    }

    /// Whether σ_y never falls as ε_p grows (J-C): the radial return may then bound the
    /// increment by the perfectly plastic one.
    #[inline]
    pub fn hardens_monotonically(&self) -> bool {
        matches!(self, FlowStress::JohnsonCook(_))
    }

    /// The melting temperature, K (flow stress 0 at and above it).
    pub fn melt_temperature_k(&self) -> f64 {
        match self {
            FlowStress::JohnsonCook(m) => m.melt_temperature_k,
            FlowStress::Tanh(m) => m.melt_temperature_k,
            FlowStress::Table(m) => m.melt_temperature_k,
        }
    }

    /// The initial yield stress at room conditions (ε_p = 0, quasi-static, the model's
    /// lowest temperature), Pa: the pressure scale of a cut before any contact is measured.
    pub fn initial_yield_pa(&self) -> f64 {
        match self {
            FlowStress::JohnsonCook(m) => m.a_pa,
            FlowStress::Tanh(m) => m.a_pa,
            FlowStress::Table(m) => m.flow_stress(0.0, 0.0, 0.0),
        }
    }

    /// Sets the strain-rate sensitivity C (the table's above its highest rate): what the
    /// cutting-force inverse calibrates.
    pub fn set_rate_sensitivity(&mut self, c: f64) {
        match self {
            FlowStress::JohnsonCook(m) => m.c = c,
            FlowStress::Tanh(m) => m.c = c,
            FlowStress::Table(m) => m.rate_sensitivity_c = c,
        }
    }

    /// The Johnson–Cook parameters, where the model is J-C.
    pub fn johnson_cook(&self) -> Option<&JohnsonCook> {
        match self {
            FlowStress::JohnsonCook(m) => Some(m),
            _ => None,
        }
    }

    pub fn validate(&self) -> greybox_core::Result<()> {
        match self {
            FlowStress::JohnsonCook(m) => m.validate(),
            FlowStress::Tanh(m) => m.validate(),
            FlowStress::Table(m) => m.validate(),
        }
    }

    /// A model's short name for reports.
    pub fn model_name(&self) -> &'static str {
        match self {
            FlowStress::JohnsonCook(_) => "Johnson-Cook",
            FlowStress::Tanh(_) => "TANH Johnson-Cook (Calamaz / Sima-Özel)",
            FlowStress::Table(_) => "tabulated flow curves",
        }
    }
}
/// A [`FlowStress`] at one temperature ([`FlowStress::at_temperature`]).
#[derive(Debug, Clone, Copy)]
pub enum FlowAt<'a> {
    Tanh(TanhAt<'a>),
    /// A model with nothing worth precomputing, and the temperature, K.
    Any(&'a FlowStress, f64),
}

impl FlowAt<'_> {
    /// σ_y, ∂σ_y/∂ε_p and ∂σ_y/∂ln ε̇_p, Pa ([`FlowStress::flow_stress_slopes`]).
    #[inline]
    pub fn flow_stress_slopes(&self, eps_p: f64, strain_rate: f64) -> (f64, f64, f64) {
        match self {
            FlowAt::Tanh(m) => m.flow_stress_slopes(eps_p, strain_rate),
            FlowAt::Any(m, t) => m.flow_stress_slopes(eps_p, strain_rate, *t),
        }
    }

    /// A lower bound of σ_y at this temperature over every ε_p ≥ 0 and ε̇_p ≥ 0, Pa (0 where
    /// none is kept: J-C has its own specialised return with the same test, A·(1 − T*^m)).
    #[inline]
    pub fn floor(&self) -> f64 {
        match self {
            FlowAt::Tanh(m) => m.floor(),
            FlowAt::Any(..) => 0.0,
        }
    }

    /// An upper bound of σ_y at this temperature over every ε_p ≥ 0 at ε̇_p ≤ ε̇₀, Pa, given
    /// the model's [`FlowStress::hardening_peak_pa`]; infinite where none is kept.
    #[inline]
    pub fn quasi_static_ceiling(&self, hardening_peak_pa: Option<f64>) -> f64 {
        match (self, hardening_peak_pa) {
            (FlowAt::Tanh(m), Some(peak)) => m.quasi_static_ceiling(peak),
            _ => f64::INFINITY,
        }
    }

    /// σ_y, Pa ([`FlowStress::flow_stress`]).
    #[inline]
    pub fn flow_stress(&self, eps_p: f64, strain_rate: f64) -> f64 {
        match self {
            FlowAt::Tanh(m) => m.flow_stress_slopes(eps_p, strain_rate).0,
            FlowAt::Any(m, t) => m.flow_stress(eps_p, strain_rate, *t),
        }
    }
}
