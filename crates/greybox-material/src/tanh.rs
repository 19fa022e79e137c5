//! TANH-type Johnson–Cook flow stress for titanium alloys: strain softening at large strains
//! (the adiabatic shear that makes Ti6Al4V chips serrated).
//!
//! Calamaz, Coupard & Girot, "A new material model for 2D numerical simulation of serrated
//! chip formation when machining titanium alloy Ti–6Al–4V", Int. J. Mach. Tools Manuf. 48
//! (2008) 275–288; Sima & Özel, "Modified material constitutive models for serrated chip
//! formation simulations and experimental validation in machining of titanium alloy
//! Ti–6Al–4V", Int. J. Mach. Tools Manuf. 50 (2010) 943–960:
//!
//! σ_y = [A + B ε^n exp(−ε^a)] · [1 + C ln(ε̇/ε̇₀)] · [1 − T*^m] · [D + (1 − D) tanh(1/(ε + p)^c)^s],
//!
//! with T* = (T − T_room)/(T_m − T_room) clamped to [0, 1], D = 1 − (T/T_m)^d and
//! p = (T/T_m)^b (temperatures in kelvin, as in the ETH IWF implementation of the Sima–Özel
//! set). Calamaz's model is s = 1; Sima & Özel added the exponent s. The strain-rate and
//! ε, T* guards are those of [`crate::JohnsonCook`].

use crate::{powf, JohnsonCook};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TanhJohnsonCook {
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
    /// Reference plastic strain rate ε̇₀, 1/s.
    pub ref_strain_rate: f64,
    /// Room (reference) temperature, K.
    pub room_temperature_k: f64,
    /// Melting temperature, K.
    pub melt_temperature_k: f64,
    /// Exponent a of the hardening damping exp(−ε^a).
    pub tanh_a: f64,
    /// Exponent b of p = (T/T_m)^b.
    pub tanh_b: f64,
    /// Exponent c (Sima & Özel's r) of 1/(ε + p)^c.
    pub tanh_c: f64,
    /// Exponent d of D = 1 − (T/T_m)^d.
    pub tanh_d: f64,
    /// Exponent s of the tanh (1 in Calamaz's model).
    #[serde(default = "one")]
    pub tanh_s: f64,
}

fn one() -> f64 {
    1.0
}

impl TanhJohnsonCook {
    /// Sima & Özel 2010, model 3 (their Table 3 exponents a = 2, b = 5, c = r = 2, d = 1,
    /// s = 0.05 on the Lee–Lin J-C set of their Table 1: A 724.7 MPa, B 683.1 MPa, n 0.47,
    /// C 0.035, m 1), T_room 298 K, T_m 1878 K, ε̇₀ 1 s⁻¹: the set the ETH IWF refinement
    /// code (mfree_iwf-ul-cut-refine, `matlib_tial6v4_Sima_tanh2010_SI`) cuts Ti6Al4V with.
    pub fn ti6al4v_sima_ozel_2010() -> Self {
        TanhJohnsonCook {
            a_pa: 724.7e6,
            b_pa: 683.1e6,
            n: 0.47,
            c: 0.035,
            m: 1.0,
            ref_strain_rate: 1.0,
            room_temperature_k: 298.0,
            melt_temperature_k: 1878.0,
            tanh_a: 2.0,
            tanh_b: 5.0,
            tanh_c: 2.0,
            tanh_d: 1.0,
            tanh_s: 0.05,
        }
    }

    /// The Johnson–Cook part of the model (A, B, n, C, m, ε̇₀, T_room, T_m): its rate and
    /// thermal factors and its parameter rules are those of [`JohnsonCook`].
    pub fn johnson_cook_part(&self) -> JohnsonCook {
        JohnsonCook {
            a_pa: self.a_pa,
            b_pa: self.b_pa,
            n: self.n,
            c: self.c,
            m: self.m,
            ref_strain_rate: self.ref_strain_rate,
            room_temperature_k: self.room_temperature_k,
            melt_temperature_k: self.melt_temperature_k,
        }
    }

    /// Flow stress σ_y(ε_p, ε̇_p, T), Pa.
    pub fn flow_stress(&self, eps_p: f64, strain_rate: f64, temperature_k: f64) -> f64 {
        self.flow_stress_slopes(eps_p, strain_rate, temperature_k).0
    }

    /// σ_y, ∂σ_y/∂ε_p and ∂σ_y/∂ln ε̇_p (Pa each).
    pub fn flow_stress_slopes(&self, eps_p: f64, strain_rate: f64, t: f64) -> (f64, f64, f64) {
        self.at_temperature(t)
            .flow_stress_slopes(eps_p, strain_rate)
    }

    /// The model at temperature `t` (K): its factors that depend on the temperature alone,
    /// 1 − T*^m, D and p, evaluated once for the many (ε_p, ε̇_p) a radial return tries.
    #[inline]
    pub fn at_temperature(&self, t: f64) -> TanhAt<'_> {
        let tr = (t / self.melt_temperature_k).clamp(0.0, 1.0);
        TanhAt {
            model: self,
            soft: self.johnson_cook_part().thermal_factor(t),
            d: 1.0 - powf(tr, self.tanh_d),
            p: powf(tr, self.tanh_b),
        }
    }

    /// The largest hardening H = A + B ε^n exp(−ε^a) over every ε ≥ 0, Pa: with t = ε^a and
    /// k = n/a, ε^n exp(−ε^a) = t^k e^(−t) peaks at t = k, so H_max = A + B k^k e^(−k).
    pub fn hardening_peak_pa(&self) -> f64 {
        let k = self.n / self.tanh_a;
        self.a_pa + self.b_pa * k.powf(k) * (-k).exp()
    }

    /// Checks the parameters (as J-C, plus a, c > 0 and b, d, s > 0).
    pub fn validate(&self) -> greybox_core::Result<()> {
        let mut rules = greybox_core::rules::Rules::new("TANH Johnson-Cook parameters");
        self.johnson_cook_part()
            .add_rules(&mut rules)
            .positive("tanh_a", self.tanh_a)
            .positive("tanh_b", self.tanh_b)
            .positive("tanh_c", self.tanh_c)
            .positive("tanh_d", self.tanh_d)
            .positive("tanh_s", self.tanh_s)
            .finish()
    }
}

/// A [`TanhJohnsonCook`] at one temperature ([`TanhJohnsonCook::at_temperature`]).
#[derive(Debug, Clone, Copy)]
pub struct TanhAt<'a> {
    model: &'a TanhJohnsonCook,
    /// The thermal factor 1 − T*^m.
    soft: f64,
    /// D = 1 − (T/T_m)^d.
    d: f64,
    /// p = (T/T_m)^b.
    p: f64,
}

impl TanhAt<'_> {
    /// A lower bound of σ_y at this temperature over every ε_p ≥ 0 and ε̇_p, Pa: A·(1 − T*^m)·D
    /// (H ≥ A, the rate factor ≥ 1, G ≥ D), so that a trial stress below it is elastic
    /// without evaluating the model.
    #[inline]
    pub fn floor(&self) -> f64 {
        self.model.a_pa * self.soft * self.d
    }

    /// An upper bound of σ_y at this temperature over every ε_p ≥ 0 at ε̇_p ≤ ε̇₀, Pa, from
    /// the model's [`TanhJohnsonCook::hardening_peak_pa`] (computed once by the caller):
    /// H_max·(1 − T*^m), since G ≤ 1 and the rate factor is 1 there. A trial stress above it
    /// is plastic without evaluating the model. Raised by 10⁻¹² of itself so that the
    /// round-off of evaluating σ_y near the peak (a few ulps) cannot cross it.
    #[inline]
    pub fn quasi_static_ceiling(&self, hardening_peak_pa: f64) -> f64 {
        hardening_peak_pa * self.soft * (1.0 + 1e-12)
    }

    /// σ_y, ∂σ_y/∂ε_p and ∂σ_y/∂ln ε̇_p (Pa each) at this temperature.
    #[inline]
    pub fn flow_stress_slopes(&self, eps_p: f64, strain_rate: f64) -> (f64, f64, f64) {
        let m = self.model;
        let e = eps_p.max(0.0);
        // Hardening H = A + B ε^n exp(−ε^a) and dH/dε = B ε^n exp(−ε^a) (n − a ε^a)/ε, with
        // ε^n exp(−ε^a) = exp(n ln ε − ε^a): one logarithm and one exponential where a power
        // and an exponential cost half as much again (the return evaluates this two or three
        // times per plastic particle and step).
        let (h, dh) = if e > 0.0 {
            let ea = powf(e, m.tanh_a);
            let en_damp = (m.n * e.ln() - ea).exp();
            (
                m.a_pa + m.b_pa * en_damp,
                m.b_pa * en_damp * (m.n - m.tanh_a * ea) / e,
            )
        } else {
            (m.a_pa, 0.0)
        };
        // Softening G = D + (1 − D) tanh(u)^s, u = (ε + p)^−c, and dG/dε.
        let d = self.d;
        let base = e + self.p;
        let (g, dg) = if base > 0.0 {
            let u = powf(base, -m.tanh_c);
            let th = u.tanh();
            // tanh(u)^s as exp(s ln tanh u) (0 < tanh u ≤ 1 here), cheaper than a power.
            let ths = (m.tanh_s * th.ln()).exp();
            let du = -m.tanh_c * u / base;
            let dth = (1.0 - th * th) * du;
            let dths = if th > 0.0 {
                m.tanh_s * ths / th * dth
            } else {
                0.0
            };
            (d + (1.0 - d) * ths, (1.0 - d) * dths)
        } else {
            // ε = p = 0: tanh(∞) = 1.
            (1.0, 0.0)
        };
        let (rf, drf) = m.johnson_cook_part().rate_factor_and_slope(strain_rate);
        let sigma = h * rf * self.soft * g;
        (
            sigma,
            (dh * g + h * dg) * rf * self.soft,
            h * drf * self.soft * g,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Sima–Özel set against the ETH IWF implementation of the same model
    /// (mfree_iwf-ul-cut-refine, `johnson_cook_Sima_2010::sigma_yield` with
    /// `matlib_tial6v4_Sima_tanh2010_SI`), compiled and run beside ours (g++ 14, -O1): the
    /// values below are its output. Above ε̇₀ both use the rate factor 1 + C ln(ε̇/ε̇₀).
    /// The curves show the model's point: hardening to ε ≈ 0.5, then softening.
    #[test]
    fn sima_ozel_matches_the_iwf_implementation() {
        let m = TanhJohnsonCook::ti6al4v_sima_ozel_2010();
        let reference = [
            // (ε, ε̇ 1/s, T K, σ Pa)
            (0.0, 1e4, 298.0, 9.5831567836e8),
            (0.1, 1e4, 298.0, 1.2613498975e9),
            (0.5, 1e4, 298.0, 1.4662063120e9),
            (1.0, 1e4, 298.0, 1.2878522393e9),
            (2.0, 1e4, 298.0, 9.7065514856e8),
            (3.0, 1e4, 298.0, 9.4264993157e8),
            (0.5, 1e4, 573.0, 1.2110051620e9),
            (2.0, 1e4, 873.0, 6.0415049998e8),
            (1.0, 1e4, 1173.0, 5.6907635602e8),
            (0.1, 1e6, 298.0, 1.4150941796e9),
            (3.0, 1e6, 873.0, 6.5065056851e8),
            (0.5, 1e6, 1173.0, 7.3380997748e8),
        ];
        for (e, r, t, want) in reference {
            let got = m.flow_stress(e, r, t);
            assert!(
                (got / want - 1.0).abs() < 1e-9,
                "ε {e}, ε̇ {r}, T {t}: {got} vs {want}"
            );
        }
    }

    /// By hand at ε = 0.5, ε̇ = e·ε̇₀, T = 773 K, Calamaz form (s = 1).
    #[test]
    fn calamaz_form_by_hand() {
        let m = TanhJohnsonCook {
            tanh_s: 1.0,
            ..TanhJohnsonCook::ti6al4v_sima_ozel_2010()
        };
        let (e, t) = (0.5f64, 773.0f64);
        let h = 724.7e6 + 683.1e6 * e.powf(0.47) * (-(e * e)).exp();
        let tstar = (t - 298.0) / (1878.0 - 298.0);
        let d = 1.0 - t / 1878.0;
        let p = (t / 1878.0).powi(5);
        let g = d + (1.0 - d) * (1.0 / (e + p).powi(2)).tanh();
        let want = h * 1.035 * (1.0 - tstar) * g;
        let got = m.flow_stress(e, std::f64::consts::E, t);
        assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
    }

    /// The elastic floor the radial return tests first is a lower bound of σ_y at every
    /// temperature, and equals σ_y where the bound is tight (ε = 0, quasi-static, T = 0 K:
    /// H = A, D = 1).
    #[test]
    fn floor_bounds_the_flow_stress_from_below() {
        let m = TanhJohnsonCook::ti6al4v_sima_ozel_2010();
        for t in [0.0, 298.0, 600.0, 1000.0, 1500.0, 1878.0, 2500.0] {
            let at = m.at_temperature(t);
            let floor = at.floor();
            assert!(floor >= 0.0);
            for e in [0.0, 1e-6, 0.01, 0.1, 0.5, 1.0, 3.0, 10.0, 100.0] {
                for r in [0.0, 0.5, 1.0, 1e3, 1e7] {
                    let y = m.flow_stress(e, r, t);
                    assert!(floor <= y, "T {t}, ε {e}, ε̇ {r}: floor {floor} > σ_y {y}");
                    assert_eq!(at.flow_stress_slopes(e, r), m.flow_stress_slopes(e, r, t));
                }
            }
        }
        let at0 = m.at_temperature(0.0);
        assert_eq!(at0.floor(), m.flow_stress(0.0, 0.0, 0.0));
    }

    /// The quasi-static ceiling the radial return tests bounds σ_y from above at every
    /// temperature, strain and rate up to ε̇₀; the hardening reaches its peak value at the
    /// strain where ε^a = n/a (a set with a stronger, later hardening peak too).
    #[test]
    fn quasi_static_ceiling_bounds_the_flow_stress_from_above() {
        for m in [
            TanhJohnsonCook::ti6al4v_sima_ozel_2010(),
            TanhJohnsonCook {
                tanh_s: 1.0,
                n: 0.9,
                tanh_a: 0.5,
                ..TanhJohnsonCook::ti6al4v_sima_ozel_2010()
            },
        ] {
            let peak = m.hardening_peak_pa();
            let eps_peak = (m.n / m.tanh_a).powf(1.0 / m.tanh_a);
            let h = |e: f64| m.a_pa + m.b_pa * e.powf(m.n) * (-e.powf(m.tanh_a)).exp();
            assert!((h(eps_peak) / peak - 1.0).abs() < 1e-14);
            for e in [0.0, 1e-6, 0.01, 0.1, 0.3, 0.5, 1.0, 2.0, 5.0, 50.0] {
                assert!(h(e) <= peak * (1.0 + 1e-15), "H({e}) {} > {peak}", h(e));
                for t in [0.0, 298.0, 700.0, 1300.0, 1878.0, 2500.0] {
                    let ceiling = m.at_temperature(t).quasi_static_ceiling(peak);
                    for r in [0.0, 0.5, 1.0] {
                        let y = m.flow_stress(e, r, t);
                        assert!(y <= ceiling, "T {t}, ε {e}, ε̇ {r}: σ_y {y} > {ceiling}");
                    }
                }
            }
        }
    }

    /// The analytic slopes the radial return uses agree with central differences.
    #[test]
    fn slopes_match_finite_differences() {
        let m = TanhJohnsonCook::ti6al4v_sima_ozel_2010();
        for (e, r, t) in [(0.05, 1e3, 300.0), (0.7, 1e5, 900.0), (2.5, 1e6, 1400.0)] {
            let (_, de, dr) = m.flow_stress_slopes(e, r, t);
            let h = 1e-6;
            let fd_e = (m.flow_stress(e + h, r, t) - m.flow_stress(e - h, r, t)) / (2.0 * h);
            let f = 1.0 + 1e-6;
            let fd_r = (m.flow_stress(e, r * f, t) - m.flow_stress(e, r / f, t)) / (2.0 * f.ln());
            assert!(
                (de - fd_e).abs() <= 1e-5 * fd_e.abs().max(1e6),
                "{de} vs {fd_e}"
            );
            assert!(
                (dr - fd_r).abs() <= 1e-5 * fd_r.abs().max(1e6),
                "{dr} vs {fd_r}"
            );
        }
    }
}
