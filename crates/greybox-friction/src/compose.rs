//! Laws built from other laws: a constant factor on μ ([`Scaled`]) and the Zorev shear cap
//! τ ≤ k on any law ([`ShearCapped`]).
//!
//! A scaled law is how a law measured on a tribometer is carried to a cut with one
//! calibrated correction (the contact conditions of a pin and of a chip differ); a capped law
//! is the pressure-dependent form of the article's grey-box composition, μ(p, v) =
//! min(μ_inner(p, v), k/p), with a white-box inner law.

use greybox_core::law::ValidityDomain;
use greybox_core::{Breaks, ContactState, FrictionLaw};
use std::sync::Arc;

/// μ = `factor` · μ_inner; the inner law's domain and breaks are kept. The inner law is
/// shared, so that a calibration trying many factors loads it once.
pub struct Scaled {
    pub factor: f64,
    pub inner: Arc<dyn FrictionLaw>,
}

impl FrictionLaw for Scaled {
    fn name(&self) -> String {
        format!("{} × {}", self.factor, self.inner.name())
    }
    fn mu(&self, s: &ContactState) -> f64 {
        self.factor * self.inner.mu(s)
    }
    fn domain(&self) -> Option<ValidityDomain> {
        self.inner.domain()
    }
    fn breaks(&self) -> Option<Breaks> {
        self.inner.breaks()
    }
}

/// The Zorev cap on a law: μ = min(μ_inner, k/p), so that τ = μ p ≤ k (k in Pa).
pub struct ShearCapped {
    pub k_pa: f64,
    pub inner: Box<dyn FrictionLaw>,
}

impl FrictionLaw for ShearCapped {
    fn name(&self) -> String {
        format!(
            "{}, capped at τ ≤ {} MPa",
            self.inner.name(),
            self.k_pa / greybox_core::units::PA_PER_MPA
        )
    }
    fn mu(&self, s: &ContactState) -> f64 {
        let mu = self.inner.mu(s);
        if mu * s.pressure_pa > self.k_pa {
            self.k_pa / s.pressure_pa
        } else {
            mu
        }
    }
    fn shear_stress(&self, s: &ContactState, k_pa: f64) -> f64 {
        (self.mu(s) * s.pressure_pa).min(self.k_pa.min(k_pa))
    }
    fn domain(&self) -> Option<ValidityDomain> {
        self.inner.domain()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classical::Coulomb;

    #[test]
    fn a_factor_scales_mu_and_a_cap_bounds_the_shear_stress() {
        let s = ContactState::new(1e9, 1.0);
        let scaled = Scaled {
            factor: 1.5,
            inner: Arc::new(Coulomb { mu: 0.4 }),
        };
        assert!((scaled.mu(&s) - 0.6).abs() < 1e-15);
        // 0.6 · 1 GPa = 600 MPa > k = 450 MPa: μ = 450/1000
        let capped = ShearCapped {
            k_pa: 450e6,
            inner: Box::new(scaled),
        };
        assert!((capped.mu(&s) - 0.45).abs() < 1e-15);
        assert!((capped.shear_stress(&s, 1e12) - 450e6).abs() < 1e-3);
        // below the cap the inner law holds: 0.6 · 500 MPa = 300 MPa
        assert!((capped.mu(&ContactState::new(5e8, 1.0)) - 0.6).abs() < 1e-15);
    }
}
