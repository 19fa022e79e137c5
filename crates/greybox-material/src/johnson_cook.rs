//! Johnson–Cook flow stress (Johnson & Cook, 7th Int. Symp. Ballistics, 1983; the article's eq. 9):
//!
//! σ_y = (A + B ε_p^n) · (1 + C ln(ε̇_p/ε̇_0)) · (1 − T*^m),  T* = (T − T_room)/(T_melt − T_room).
//!
//! Guards (no NaN for any finite input): ε_p is clamped at 0; the rate factor is 1 for
//! ε̇_p ≤ ε̇_0 (the logarithm would otherwise go negative and to −∞ as ε̇ → 0; the same choice as
//! the ETH IWF SPH codes); T* is clamped to [0, 1], so the flow stress is 0 at and above melting.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JohnsonCook {
    /// Initial yield stress A, Pa.
    pub a_pa: f64,
    /// Hardening modulus B, Pa.
    pub b_pa: f64,
    /// Hardening exponent n.
    pub n: f64,
    /// Strain-rate sensitivity C.
    pub c: f64,
    /// Thermal-softening exponent m.
    pub m: f64,
    /// Reference plastic strain rate ε̇_0, 1/s.
    pub ref_strain_rate: f64,
    /// Room (reference) temperature, K.
    pub room_temperature_k: f64,
    /// Melting temperature, K.
    pub melt_temperature_k: f64,
}

impl JohnsonCook {
    /// AISI 1045, the article's Table 4 (A 331 MPa, B 614 MPa, n 0.26, C 0.045, m 1.19,
    /// T_m 1773 K; ε̇_0 = 4·10⁻³ s⁻¹, the compression-test rate the parameters were fitted at).
    pub fn aisi1045_article() -> Self {
        JohnsonCook {
            a_pa: 331e6,
            b_pa: 614e6,
            n: 0.26,
            c: 0.045,
            m: 1.19,
            ref_strain_rate: 4e-3,
            room_temperature_k: 293.15,
            melt_temperature_k: 1773.0,
        }
    }

    /// AISI 1045 after Jaspers & Dautzenberg (J. Mater. Process. Technol. 122, 2002), the NIST
    /// extended-Oxley condition: A 553.1 MPa, B 600.8 MPa, n 0.234, C 0.0134, m 1, T_m 1460 °C,
    /// ε̇_0 = 1 s⁻¹.
    pub fn aisi1045_jaspers() -> Self {
        JohnsonCook {
            a_pa: 553.1e6,
            b_pa: 600.8e6,
            n: 0.234,
            c: 0.0134,
            m: 1.0,
            ref_strain_rate: 1.0,
            room_temperature_k: 293.15,
            melt_temperature_k: 1460.0 + 273.15,
        }
    }

    /// Ti6Al4V, standard Johnson–Cook set (Lee & Lin 1998 as used by the ETH IWF SPH cutting
    /// benchmark): A 862 MPa, B 331 MPa, n 0.34, C 0.01, m 0.8, ε̇_0 = 1 s⁻¹, T_m 1836 K.
    pub fn ti6al4v() -> Self {
        JohnsonCook {
            a_pa: 862e6,
            b_pa: 331e6,
            n: 0.34,
            c: 0.01,
            m: 0.8,
            ref_strain_rate: 1.0,
            room_temperature_k: 300.0,
            melt_temperature_k: 1836.0,
        }
    }

    /// Strain-hardening factor A + B ε^n, Pa.
    #[inline]
    pub fn hardening(&self, eps_p: f64) -> f64 {
        self.a_pa + self.b_pa * eps_p.max(0.0).powf(self.n)
    }

    /// Strain-rate factor 1 + C ln(ε̇/ε̇_0), equal to 1 below ε̇_0.
    #[inline]
    pub fn rate_factor(&self, strain_rate: f64) -> f64 {
        let r = strain_rate / self.ref_strain_rate;
        if r > 1.0 {
            1.0 + self.c * r.ln()
        } else {
            1.0
        }
    }

    /// The strain-rate factor and its slope by ln ε̇ (C above ε̇_0, 0 below).
    #[inline]
    pub fn rate_factor_and_slope(&self, strain_rate: f64) -> (f64, f64) {
        let slope = if strain_rate > self.ref_strain_rate {
            self.c
        } else {
            0.0
        };
        (self.rate_factor(strain_rate), slope)
    }

    /// Thermal-softening factor 1 − T*^m with T* clamped to [0, 1].
    #[inline]
    pub fn thermal_factor(&self, temperature_k: f64) -> f64 {
        let t = ((temperature_k - self.room_temperature_k)
            / (self.melt_temperature_k - self.room_temperature_k))
            .clamp(0.0, 1.0);
        if t == 0.0 {
            1.0
        } else {
            1.0 - crate::powf(t, self.m)
        }
    }

    /// Flow stress σ_y(ε_p, ε̇_p, T), Pa.
    #[inline]
    pub fn flow_stress(&self, eps_p: f64, strain_rate: f64, temperature_k: f64) -> f64 {
        self.hardening(eps_p) * self.rate_factor(strain_rate) * self.thermal_factor(temperature_k)
    }

    /// Checks the parameters (positive A, B ≥ 0, 0 < n ≤ 1, C ≥ 0, m > 0, T_m > T_room).
    pub fn validate(&self) -> greybox_core::Result<()> {
        self.add_rules(&mut greybox_core::rules::Rules::new(
            "Johnson-Cook parameters",
        ))
        .finish()
    }

    /// Adds the J-C parameter rules to `rules` (also those of the J-C part of the TANH model).
    pub fn add_rules<'r>(
        &self,
        rules: &'r mut greybox_core::rules::Rules,
    ) -> &'r mut greybox_core::rules::Rules {
        rules
            .positive("a_pa", self.a_pa)
            .non_negative("b_pa", self.b_pa)
            .above_up_to("n", self.n, 0.0, 1.0)
            .non_negative("c", self.c)
            .positive("m", self.m);
        add_reference_rules(
            rules,
            self.ref_strain_rate,
            self.room_temperature_k,
            self.melt_temperature_k,
        )
    }
}

/// The rules on a Johnson–Cook-type law's reference strain rate ε̇_0 > 0 and temperatures
/// T_m > T_room > 0 (the flow stress's and the damage's).
pub(crate) fn add_reference_rules(
    rules: &mut greybox_core::rules::Rules,
    ref_strain_rate: f64,
    room_temperature_k: f64,
    melt_temperature_k: f64,
) -> &mut greybox_core::rules::Rules {
    rules
        .positive("ref_strain_rate", ref_strain_rate)
        .positive("room_temperature_k", room_temperature_k)
        .relation(
            melt_temperature_k > room_temperature_k && melt_temperature_k.is_finite(),
            format!(
                "melt_temperature_k ({melt_temperature_k}) must exceed room_temperature_k ({room_temperature_k})"
            ),
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed values: at ε = 0.5, ε̇ = ε̇0·e, T = T_room + 0.5 (T_m − T_room):
    /// (331 + 614·0.5^0.26)(1 + 0.045)(1 − 0.5^1.19) MPa.
    #[test]
    fn article_values() {
        let jc = JohnsonCook::aisi1045_article();
        let t = 293.15 + 0.5 * (1773.0 - 293.15);
        let want = (331e6 + 614e6 * 0.5f64.powf(0.26)) * 1.045 * (1.0 - 0.5f64.powf(1.19));
        let got = jc.flow_stress(0.5, 4e-3 * std::f64::consts::E, t);
        assert!((got / want - 1.0).abs() < 1e-12);
        assert_eq!(jc.flow_stress(0.0, 0.0, 293.15), 331e6);
        assert_eq!(jc.flow_stress(0.3, 1e3, 5000.0), 0.0);
        assert!(jc.flow_stress(-1.0, -5.0, 0.0).is_finite());
    }
}
