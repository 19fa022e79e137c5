//! Classical friction laws (digest §9; Melkote et al., CIRP Annals 66, 2017, review) and the
//! helpers that infer μ from cutting data. States are SI: p in Pa, v in m/s, T in K; laws
//! expressed as a shear stress carry the workpiece shear flow stress k (Pa) used by `mu`.

use greybox_core::{ContactState, Error, FrictionLaw, Result};
use serde::{Deserialize, Serialize};

/// μ = τ/p for a shear-stress law, with μ → its small-pressure limit at p → 0.
fn mu_from_tau(tau: f64, p: f64, limit: f64) -> f64 {
    if p > 0.0 {
        tau / p
    } else {
        limit
    }
}

/// Constant Coulomb friction: τ = μ p.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Coulomb {
    pub mu: f64,
}

impl FrictionLaw for Coulomb {
    fn name(&self) -> String {
        format!("Coulomb μ = {}", self.mu)
    }
    fn mu(&self, _s: &ContactState) -> f64 {
        self.mu
    }
    fn shear_stress(&self, s: &ContactState, _k: f64) -> f64 {
        self.mu * s.pressure_pa
    }
}

/// Constant shear factor: τ = m k (0 ≤ m ≤ 1); the equivalent μ = m k / p.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShearFactor {
    pub m: f64,
    /// Shear flow stress used by `mu`, Pa.
    pub k_pa: f64,
}

impl FrictionLaw for ShearFactor {
    fn name(&self) -> String {
        format!("shear factor m = {}", self.m)
    }
    fn mu(&self, s: &ContactState) -> f64 {
        mu_from_tau(self.m * self.k_pa, s.pressure_pa, f64::INFINITY)
    }
    fn shear_stress(&self, _s: &ContactState, k: f64) -> f64 {
        self.m * k
    }
}

/// Zorev's sticking–sliding law: τ = μ p where μ p < k (sliding), τ = k otherwise (sticking).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Zorev {
    pub mu: f64,
    pub k_pa: f64,
}

impl FrictionLaw for Zorev {
    fn name(&self) -> String {
        format!("Zorev μ = {}", self.mu)
    }
    fn mu(&self, s: &ContactState) -> f64 {
        mu_from_tau(self.shear_stress(s, self.k_pa), s.pressure_pa, self.mu)
    }
    fn shear_stress(&self, s: &ContactState, k: f64) -> f64 {
        (self.mu * s.pressure_pa).min(k)
    }
}

/// Usui's law generalised by Childs: τ = m k [1 − exp(−(μ p/(m k))ⁿ)]^(1/n). n = 1 is Usui's
/// (Usui & Shirakashi 1982); τ → μ p as p → 0 and τ → m k as p → ∞.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UsuiChilds {
    pub mu: f64,
    pub m: f64,
    pub n: f64,
    pub k_pa: f64,
}

impl FrictionLaw for UsuiChilds {
    fn name(&self) -> String {
        format!(
            "Usui/Childs μ = {}, m = {}, n = {}",
            self.mu, self.m, self.n
        )
    }
    fn mu(&self, s: &ContactState) -> f64 {
        mu_from_tau(self.shear_stress(s, self.k_pa), s.pressure_pa, self.mu)
    }
    fn shear_stress(&self, s: &ContactState, k: f64) -> f64 {
        let mk = self.m * k;
        let x = (self.mu * s.pressure_pa.max(0.0) / mk).powf(self.n);
        // 1 − e^(−x) computed as −expm1(−x) to keep τ/p → μ accurate at small p
        mk * (-(-x).exp_m1()).powf(1.0 / self.n)
    }
}

/// Exponential velocity decay: μ = μ_d + (μ_s − μ_d) exp(−v / v_c).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ExponentialVelocity {
    pub mu_static: f64,
    pub mu_dynamic: f64,
    /// Decay velocity v_c, m/s.
    pub v_c_m_s: f64,
}

impl FrictionLaw for ExponentialVelocity {
    fn name(&self) -> String {
        format!(
            "exponential velocity decay μ_s = {}, μ_d = {}",
            self.mu_static, self.mu_dynamic
        )
    }
    fn mu(&self, s: &ContactState) -> f64 {
        self.mu_dynamic
            + (self.mu_static - self.mu_dynamic)
                * (-s.sliding_velocity_m_s.abs() / self.v_c_m_s).exp()
    }
}

/// Thermal softening (Puls et al.): μ = μ0 [1 − ((T − T0)/(Tm − T0))^q], held at μ0 below T0
/// and at 0 above Tm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThermalSoftening {
    pub mu0: f64,
    pub t0_k: f64,
    pub tm_k: f64,
    pub q: f64,
}

impl FrictionLaw for ThermalSoftening {
    fn name(&self) -> String {
        format!("thermal softening μ0 = {}, q = {}", self.mu0, self.q)
    }
    fn mu(&self, s: &ContactState) -> f64 {
        let theta = ((s.temperature_k - self.t0_k) / (self.tm_k - self.t0_k)).clamp(0.0, 1.0);
        self.mu0 * (1.0 - theta.powf(self.q))
    }
}

/// Merchant's μ from orthogonal-cutting forces: μ = tan(β), β = γ + atan(F_t / F_c), i.e.
/// μ = (F_t + F_c tan γ) / (F_c − F_t tan γ) (rake angle γ in radians; the article's text prints
/// a '+' in the denominator, which is wrong — digest §9).
pub fn merchant_mu(cutting_force_n: f64, feed_force_n: f64, rake_rad: f64) -> Result<f64> {
    let den = cutting_force_n - feed_force_n * rake_rad.tan();
    if !(cutting_force_n > 0.0) || !(den > 0.0) || !feed_force_n.is_finite() {
        return Err(Error::invalid(
            "Merchant",
            "needs F_c > 0 and F_c − F_t tan γ > 0 (friction angle below 90°)",
        ));
    }
    Ok((feed_force_n + cutting_force_n * rake_rad.tan()) / den)
}

/// Du et al.'s μ from tool geometry and flank wear:
/// μ = tan(π/4 + γ0 + α0 − arccos(1 − (VB/r_n) sin α0)) (angles in radians).
pub fn du_mu(
    rake_rad: f64,
    clearance_rad: f64,
    flank_wear_m: f64,
    edge_radius_m: f64,
) -> Result<f64> {
    let c = 1.0 - flank_wear_m / edge_radius_m * clearance_rad.sin();
    if !(edge_radius_m > 0.0) || !(-1.0..=1.0).contains(&c) {
        return Err(Error::invalid(
            "Du et al.",
            "needs r_n > 0 and |1 − (VB/r_n) sin α0| ≤ 1",
        ));
    }
    Ok((std::f64::consts::FRAC_PI_4 + rake_rad + clearance_rad - c.acos()).tan())
}

#[cfg(test)]
mod tests {
    use super::*;
    const K: f64 = 400e6;
    fn at(p: f64) -> ContactState {
        ContactState::new(p, 1.0)
    }

    #[test]
    fn velocity_law_limits() {
        let l = ExponentialVelocity {
            mu_static: 0.5,
            mu_dynamic: 0.2,
            v_c_m_s: 2.0,
        };
        assert_eq!(l.mu(&ContactState::new(1e9, 0.0)), 0.5);
        assert!((l.mu(&ContactState::new(1e9, 1e6)) - 0.2).abs() < 1e-15);
        assert!(
            (l.mu(&ContactState::new(1e9, 2.0)) - (0.2 + 0.3 / std::f64::consts::E)).abs() < 1e-15
        );
    }

    #[test]
    fn childs_with_n1_is_usui_and_limits() {
        let c = UsuiChilds {
            mu: 0.4,
            m: 0.8,
            n: 1.0,
            k_pa: K,
        };
        for p in [1e6, 3e8, 1e9, 5e9] {
            let usui = 0.8 * K * (1.0 - (-0.4 * p / (0.8 * K)).exp());
            assert!((c.shear_stress(&at(p), K) - usui).abs() < 1e-6 * usui);
        }
        let c2 = UsuiChilds { n: 2.5, ..c };
        // τ/p → μ as p → 0; τ → m k as p → ∞
        assert!((c2.mu(&at(1.0)) - 0.4).abs() < 1e-9);
        assert!((c2.shear_stress(&at(1e13), K) - 0.8 * K).abs() < 1e-6 * K);
        assert!((c.mu(&at(1e-3)) - 0.4).abs() < 1e-9);
    }

    #[test]
    fn zorev_switches_at_mu_p_equal_k() {
        let z = Zorev { mu: 0.5, k_pa: K };
        let p_switch = K / 0.5;
        assert_eq!(
            z.shear_stress(&at(p_switch * (1.0 - 1e-12)), K),
            0.5 * p_switch * (1.0 - 1e-12)
        );
        assert_eq!(z.shear_stress(&at(p_switch * (1.0 + 1e-12)), K), K);
        assert_eq!(z.mu(&at(0.5 * p_switch)), 0.5);
        assert!((z.mu(&at(2.0 * p_switch)) - 0.25).abs() < 1e-15);
        let m = ShearFactor { m: 0.7, k_pa: K };
        assert_eq!(m.shear_stress(&at(1e9), K), 0.7 * K);
    }

    #[test]
    fn thermal_softening_bounds() {
        let t = ThermalSoftening {
            mu0: 0.4,
            t0_k: 293.0,
            tm_k: 1773.0,
            q: 1.5,
        };
        let st = |tk: f64| ContactState {
            pressure_pa: 1e9,
            sliding_velocity_m_s: 1.0,
            temperature_k: tk,
        };
        assert_eq!(t.mu(&st(200.0)), 0.4);
        assert_eq!(t.mu(&st(1773.0)), 0.0);
        assert!((t.mu(&st(1033.0)) - 0.4 * (1.0 - 0.5f64.powf(1.5))).abs() < 1e-15);
    }

    /// Merchant: γ = 15°, F_c = 1200 N, F_t = 200 N → μ ≈ 0.455 (textbook worked example).
    #[test]
    fn merchant_worked_example() {
        let mu = merchant_mu(1200.0, 200.0, 15f64.to_radians()).unwrap();
        assert!((mu - 0.455).abs() < 5e-4, "{mu}");
        // zero rake: μ = F_t / F_c
        assert!((merchant_mu(1000.0, 400.0, 0.0).unwrap() - 0.4).abs() < 1e-15);
        assert!(merchant_mu(100.0, 1000.0, 1.4).is_err());
    }

    #[test]
    fn du_without_wear() {
        // VB = 0: arccos(1) = 0 → μ = tan(π/4 + γ0 + α0)
        let mu = du_mu(0.0, 0.0, 0.0, 20e-6).unwrap();
        assert!((mu - 1.0).abs() < 1e-12);
    }
}
