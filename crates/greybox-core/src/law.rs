//! The friction-law seam.
//!
//! It lives in `greybox-core` (not in the friction crate) so that every producer and
//! consumer of friction — the virtual tribometer, the simulator, the coupling loop,
//! the exporters — can share it without depending on the learning stack.

use crate::ContactState;

/// Closed interval of a contact variable in SI units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Range {
    pub min: f64,
    pub max: f64,
}

impl Range {
    pub fn contains(&self, x: f64) -> bool {
        x >= self.min && x <= self.max
    }
}

/// The contact states a law is valid for (fitted or calibrated on).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ValidityDomain {
    /// Pressure, Pa.
    pub pressure_pa: Range,
    /// Sliding velocity, m/s.
    pub sliding_velocity_m_s: Range,
    /// Temperature, K (`None`: the law does not depend on temperature).
    pub temperature_k: Option<Range>,
}

impl ValidityDomain {
    pub fn contains(&self, s: &ContactState) -> bool {
        self.pressure_pa.contains(s.pressure_pa)
            && self.sliding_velocity_m_s.contains(s.sliding_velocity_m_s)
            && self
                .temperature_k
                .is_none_or(|t| t.contains(s.temperature_k))
    }
}

/// A friction law: Coulomb coefficient μ as a function of the local contact state.
pub trait FrictionLaw: Send + Sync {
    /// Short human-readable name (for reports and file headers).
    fn name(&self) -> String;

    /// Friction coefficient μ (dimensionless) at a contact state.
    fn mu(&self, state: &ContactState) -> f64;

    /// Batch form: writes μ for every state into `out` (same length).
    fn mu_batch(&self, states: &[ContactState], out: &mut [f64]) {
        for (s, o) in states.iter().zip(out.iter_mut()) {
            *o = self.mu(s);
        }
    }

    /// Frictional shear stress τ (Pa) for a workpiece shear flow stress `k_pa`.
    /// Default: Coulomb τ = μ p capped by sticking, τ ≤ k (Zorev).
    fn shear_stress(&self, state: &ContactState, k_pa: f64) -> f64 {
        (self.mu(state) * state.pressure_pa).min(k_pa)
    }

    /// The domain the law was fitted/calibrated on, if it has one.
    fn domain(&self) -> Option<ValidityDomain> {
        None
    }
}
