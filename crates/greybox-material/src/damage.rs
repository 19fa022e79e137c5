//! Ductile damage of the workpiece: Johnson–Cook damage initiation with Hillerborg's
//! fracture-energy softening, the criterion published Ti6Al4V cutting models add to the
//! flow stress to form a segmented chip (e.g. Ducobu, Rivière-Lorphèvre & Filippi, Int J
//! Mech Sci 107 (2016) 136, TANH and J-C laws with this criterion).
//!
//! **Initiation** (Johnson & Cook, Eng Fract Mech 21 (1985) 31): the strain at fracture
//!
//! ε_f = [D1 + D2 exp(D3 η)] · [1 + D4 ln ε̇*] · [1 + D5 T*],
//!
//! with the stress triaxiality η = σ_m/σ_vm (σ_m = −p, the mean stress), ε̇* = ε̇_p/ε̇_0
//! (the rate factor is 1 below ε̇_0, as in the flow stress) and T* = (T − T_room)/(T_m −
//! T_room) clamped to [0, 1]. The damage indicator ω = Σ Δε_p/ε_f grows with every plastic
//! increment; damage starts at ω = 1. Where the first bracket is not positive (D1 < 0 at high
//! triaxiality) the strain at fracture is [`MIN_FAILURE_STRAIN`]: such a state starts
//! damage at once.
//!
//! **Softening** (Hillerborg, Modéer & Petersson, Cem Concr Res 6 (1976) 773): after
//! initiation the flow stress falls linearly with the plastic displacement ū = L Δε_p across
//! a particle of spacing L, to zero at ū_f = 2 G_f/σ_y, so that the energy the softening
//! dissipates per unit of crack area is the fracture energy G_f whatever the spacing:
//!
//! Δd = L Δε_p σ_y / (2 G_f),  σ_y,damaged = (1 − d) σ_y,  d ≤ d_max,
//!
//! with σ_y the undamaged flow stress of the step (the linear law's σ_y0, taken at each step).
//! A tensile mean stress is degraded alike (a compressive one never is): a damaged particle
//! still carries pressure but no longer holds the chip together in tension.
//!
//! Both phases live in one state per particle, `damage` = ω in [0, 1) before initiation and
//! 1 + d in [1, 1 + d_max] after it ([`JohnsonCookDamage::degradation`]).

use serde::{Deserialize, Serialize};

/// The smallest strain at fracture, used where the first bracket of ε_f is not positive.
pub const MIN_FAILURE_STRAIN: f64 = 1e-6;

/// Johnson–Cook damage initiation and Hillerborg softening (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JohnsonCookDamage {
    pub d1: f64,
    pub d2: f64,
    pub d3: f64,
    pub d4: f64,
    pub d5: f64,
    /// Reference plastic strain rate ε̇_0, 1/s.
    pub ref_strain_rate: f64,
    /// Room (reference) temperature, K.
    pub room_temperature_k: f64,
    /// Melting temperature, K.
    pub melt_temperature_k: f64,
    /// Fracture energy G_f per unit of crack area, J/m².
    pub fracture_energy_j_m2: f64,
    /// Largest degradation d_max in [0, 1): a particle keeps at least (1 − d_max) of its
    /// flow stress, so its return stays well posed.
    #[serde(default = "default_max_degradation")]
    pub max_degradation: f64,
}

fn default_max_degradation() -> f64 {
    0.99
}

/// Whether the state `damage` has initiated (ω reached 1).
#[inline]
pub fn initiated(damage: f64) -> bool {
    damage >= 1.0
}

/// The degradation d ≥ 0 the state `damage` holds (0 before initiation), before any
/// model's cap d_max: the one decoding of the state's two phases.
#[inline]
pub fn degradation_of(damage: f64) -> f64 {
    (damage - 1.0).max(0.0)
}

/// Plane-strain fracture energy G = K_IC² (1 − ν²)/E, J/m², of a material with fracture
/// toughness `k_ic` (Pa·√m), Young's modulus `e` (Pa) and Poisson's ratio `nu`
/// (Irwin's relation, e.g. Anderson, *Fracture Mechanics*, 3rd ed., 2005, eq. 2.54).
pub fn plane_strain_fracture_energy(k_ic: f64, e: f64, nu: f64) -> f64 {
    k_ic * k_ic * (1.0 - nu * nu) / e
}

impl JohnsonCookDamage {
    /// Ti6Al4V after Lesuer (LLNL report UCRL-ID-134691, 2000; the set Ti6Al4V cutting
    /// models use): D1 −0.09, D2 0.25, D3 −0.5, D4 0.014, D5 3.87, ε̇_0 = 1 s⁻¹, with the
    /// room and melting temperatures of the flow stress it goes with, and the plane-strain
    /// fracture energy of K_IC = 75 MPa√m (annealed Ti6Al4V, e.g. the ASM Handbook vol. 2)
    /// with E = 113.8 GPa, ν = 0.342: G_f = 43.6 kJ/m².
    pub fn ti6al4v_lesuer(room_temperature_k: f64, melt_temperature_k: f64) -> Self {
        JohnsonCookDamage {
            d1: -0.09,
            d2: 0.25,
            d3: -0.5,
            d4: 0.014,
            d5: 3.87,
            ref_strain_rate: 1.0,
            room_temperature_k,
            melt_temperature_k,
            fracture_energy_j_m2: plane_strain_fracture_energy(75e6, 113.8e9, 0.342),
            max_degradation: default_max_degradation(),
        }
    }

    /// The strain at fracture ε_f(η, ε̇_p, T) (module docs), at least [`MIN_FAILURE_STRAIN`].
    pub fn failure_strain(&self, triaxiality: f64, strain_rate: f64, temperature_k: f64) -> f64 {
        let stress = self.d1 + self.d2 * (self.d3 * triaxiality).exp();
        let r = strain_rate / self.ref_strain_rate;
        let rate = if r > 1.0 { 1.0 + self.d4 * r.ln() } else { 1.0 };
        let t = ((temperature_k - self.room_temperature_k)
            / (self.melt_temperature_k - self.room_temperature_k))
            .clamp(0.0, 1.0);
        let eps_f = stress * rate * (1.0 + self.d5 * t);
        if eps_f.is_finite() {
            eps_f.max(MIN_FAILURE_STRAIN)
        } else if stress > 0.0 {
            // exp(D3 η) overflowed: a state so compressive that it never fails.
            f64::MAX
        } else {
            MIN_FAILURE_STRAIN
        }
    }

    /// The degradation d in [0, d_max] of a particle with state `damage` (0 before initiation).
    #[inline]
    pub fn degradation(&self, damage: f64) -> f64 {
        degradation_of(damage).min(self.max_degradation)
    }

    /// The share of its mean stress a particle with state `damage` keeps: 1 in compression,
    /// 1 − d in tension (`tension`: the mean stress is tensile, p < 0).
    #[inline]
    pub fn mean_stress_share(&self, damage: f64, tension: bool) -> f64 {
        if tension {
            self.strength(damage)
        } else {
            1.0
        }
    }

    /// The share 1 − d of the undamaged flow stress a particle with state `damage` keeps.
    #[inline]
    pub fn strength(&self, damage: f64) -> f64 {
        1.0 - self.degradation(damage)
    }

    /// The state after a plastic increment `d_eps` at the given triaxiality, plastic strain
    /// rate (1/s, as the flow stress sees it), temperature (K) and undamaged flow stress
    /// `flow_stress` (Pa), of a particle of spacing `spacing` (m). An increment that crosses
    /// initiation spends the rest of its strain on softening.
    #[allow(clippy::too_many_arguments)] // one particle's state and its step
    pub fn advance(
        &self,
        damage: f64,
        d_eps: f64,
        triaxiality: f64,
        strain_rate: f64,
        temperature_k: f64,
        flow_stress: f64,
        spacing: f64,
    ) -> f64 {
        if d_eps <= 0.0 {
            return damage;
        }
        let mut damage = damage;
        let mut left = d_eps;
        if damage < 1.0 {
            let eps_f = self.failure_strain(triaxiality, strain_rate, temperature_k);
            let to_initiation = (1.0 - damage) * eps_f;
            if left < to_initiation {
                return damage + left / eps_f;
            }
            left -= to_initiation;
            damage = 1.0;
        }
        let softening = spacing * left * flow_stress.max(0.0) / (2.0 * self.fracture_energy_j_m2);
        (damage + softening).min(1.0 + self.max_degradation)
    }

    /// Checks the parameters: D2 ≥ 0 and D1 + D2 > 0 (a strain at fracture at zero
    /// triaxiality), D3 ≤ 0, D4 ≥ 0, D5 finite, ε̇_0 > 0, T_m > T_room > 0, G_f > 0,
    /// 0 ≤ d_max < 1.
    pub fn validate(&self) -> greybox_core::Result<()> {
        let mut rules = greybox_core::rules::Rules::new("damage (Johnson-Cook)");
        crate::johnson_cook::add_reference_rules(
            &mut rules,
            self.ref_strain_rate,
            self.room_temperature_k,
            self.melt_temperature_k,
        )
        .finite("d1", self.d1)
        .non_negative("d2", self.d2)
        .relation(
            self.d1 + self.d2 > 0.0,
            format!(
                "d1 + d2 = {} must be > 0 (the strain at fracture at zero triaxiality)",
                self.d1 + self.d2
            ),
        )
        .within("d3", self.d3, f64::MIN, 0.0)
        .non_negative("d4", self.d4)
        .finite("d5", self.d5)
        .positive("fracture_energy_j_m2", self.fracture_energy_j_m2)
        .within("max_degradation", self.max_degradation, 0.0, 0.999_999)
        .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lesuer() -> JohnsonCookDamage {
        JohnsonCookDamage::ti6al4v_lesuer(298.0, 1878.0)
    }

    /// Hand values of Lesuer's set: at η = 0, ε̇ ≤ ε̇_0 and room temperature ε_f = D1 + D2
    /// = 0.16; at η = −1/3, ε̇ = 10⁴ s⁻¹ and T* = 0.25:
    /// (−0.09 + 0.25 e^{1/6}) (1 + 0.014 ln 10⁴) (1 + 3.87/4) = 0.205 34 · 1.128 94 · 1.967 5 = 0.456 1.
    #[test]
    fn failure_strain_matches_hand_values() {
        let d = lesuer();
        assert!((d.failure_strain(0.0, 0.5, 298.0) - 0.16).abs() < 1e-15);
        let t = 298.0 + 0.25 * (1878.0 - 298.0);
        let want = (-0.09 + 0.25 * (1.0f64 / 6.0).exp())
            * (1.0 + 0.014 * 1e4f64.ln())
            * (1.0 + 3.87 * 0.25);
        let got = d.failure_strain(-1.0 / 3.0, 1e4, t);
        assert!((got / want - 1.0).abs() < 1e-14, "{got} vs {want}");
        assert!((want - 0.456_3).abs() < 1e-3, "{want}");
        // High triaxiality: the first bracket is negative, damage starts at once.
        assert_eq!(d.failure_strain(3.0, 1.0, 298.0), MIN_FAILURE_STRAIN);
        // Deep compression: finite, never NaN.
        assert!(d.failure_strain(-1e4, 1.0, 298.0) > 1e10);
        assert!(d.failure_strain(f64::NEG_INFINITY, 1.0, 298.0).is_finite());
    }

    /// The K_IC relation: 75 MPa√m, 113.8 GPa, ν 0.342 → 43.6 kJ/m².
    #[test]
    fn fracture_energy_of_ti6al4v() {
        let g = lesuer().fracture_energy_j_m2;
        assert!((g - 75e6f64.powi(2) * (1.0 - 0.342f64.powi(2)) / 113.8e9).abs() < 1e-9);
        assert!((g / 43_630.0 - 1.0).abs() < 1e-3, "{g}");
    }

    /// Initiation after ε_f of plastic strain, whatever the increments; then the softening
    /// dissipates G_f per unit crack area: d reaches 1 after ū = L Δε_p = 2 G_f/σ_y, the
    /// same plastic displacement at any spacing.
    #[test]
    fn initiation_then_softening_regularised_by_the_spacing() {
        let d = lesuer();
        let (eta, rate, t, sy) = (0.0, 0.5, 298.0, 1e9);
        for steps in [1usize, 7, 1000] {
            let mut s = 0.0;
            for _ in 0..steps {
                s = d.advance(s, 0.16 / steps as f64, eta, rate, t, sy, 1e-5);
            }
            assert!((s - 1.0).abs() < 1e-12, "{steps} steps: {s}");
        }
        let u_f = 2.0 * d.fracture_energy_j_m2 / sy;
        for spacing in [5e-6, 1e-5, 2e-5] {
            let half = d.advance(1.0, 0.5 * u_f / spacing, eta, rate, t, sy, spacing);
            assert!((d.degradation(half) - 0.5).abs() < 1e-12);
            assert!((d.strength(half) - 0.5).abs() < 1e-12);
        }
        // An increment across initiation spends the rest on softening.
        let s = d.advance(0.5, 0.08 + 0.1 * u_f / 1e-5, eta, rate, t, sy, 1e-5);
        assert!((d.degradation(s) - 0.1).abs() < 1e-9, "{s}");
        // Tension keeps (1 − d) of its mean stress, compression all of it.
        assert!((d.mean_stress_share(half_state(&d), true) - 0.5).abs() < 1e-12);
        assert_eq!(d.mean_stress_share(half_state(&d), false), 1.0);
        assert!(!initiated(0.999) && initiated(1.0));
        // Capped at d_max; no increment, no change.
        let full = d.advance(1.0, 1e3, eta, rate, t, sy, 1e-5);
        assert_eq!(full, 1.0 + d.max_degradation);
        assert_eq!(d.advance(0.3, 0.0, eta, rate, t, sy, 1e-5), 0.3);
    }

    /// A state halfway through the softening (d = 0.5).
    fn half_state(d: &JohnsonCookDamage) -> f64 {
        let u_f = 2.0 * d.fracture_energy_j_m2 / 1e9;
        d.advance(1.0, 0.5 * u_f / 1e-5, 0.0, 0.5, 298.0, 1e9, 1e-5)
    }

    #[test]
    fn validation_names_the_field() {
        let mut d = lesuer();
        d.validate().unwrap();
        d.max_degradation = 1.0;
        let e = d.validate().unwrap_err().to_string();
        assert!(e.contains("max_degradation"), "{e}");
        let mut d = lesuer();
        d.d1 = -0.3;
        let e = d.validate().unwrap_err().to_string();
        assert!(e.contains("d1 + d2"), "{e}");
        let mut d = lesuer();
        d.fracture_energy_j_m2 = 0.0;
        assert!(d
            .validate()
            .unwrap_err()
            .to_string()
            .contains("fracture_energy_j_m2"));
    }
}
