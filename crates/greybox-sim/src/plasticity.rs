//! Johnson–Cook radial return (Wilkins 1964; Simo & Hughes, *Computational Inelasticity*, 1998,
//! §3.3) for the plane-strain deviatoric stress (xx, xy, yy, zz).
//!
//! With a trial von Mises stress σ_tr above the flow stress, the plastic increment Δε solves
//! f(Δε) = σ_tr − 3GΔε − σ_JC(ε_p + Δε, Δε/Δt, T) = 0 on [0, σ_tr/3G], where f(0) > 0 and
//! f(σ_tr/3G) ≤ 0: a bracketed Illinois (regula falsi) iteration always converges, also where
//! the ε^n hardening has an infinite slope at ε = 0 and Newton would fail. The deviator is then
//! scaled by σ_y/σ_tr.

use greybox_material::JohnsonCook;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Return {
    /// Plastic strain increment.
    pub d_eps: f64,
    /// Flow stress at the end of the increment, Pa.
    pub flow_stress: f64,
}

/// Returns the deviator `s` = [xx, xy, yy, zz] to the yield surface in place.
pub fn radial_return(
    jc: &JohnsonCook,
    shear: f64,
    s: &mut [f64; 4],
    eps_p: f64,
    temperature_k: f64,
    dt: f64,
    rate_scale: f64,
) -> Return {
    let ss = s[0] * s[0] + s[2] * s[2] + s[3] * s[3] + 2.0 * s[1] * s[1];
    let trial = (1.5 * ss).sqrt();
    let soft = jc.thermal_factor(temperature_k);
    let y0 = jc.hardening(eps_p) * soft;
    if trial <= y0 {
        return Return {
            d_eps: 0.0,
            flow_stress: y0,
        };
    }
    let hard = |d: f64| jc.hardening(eps_p + d) * jc.rate_factor(rate_scale * d / dt) * soft;
    let g3 = 3.0 * shear;
    let f = |d: f64| trial - g3 * d - hard(d);
    // σ_y only grows with Δε, so the perfectly plastic increment (σ_tr − σ_y(0))/3G is an
    // upper bound: a tight bracket from the start.
    let (mut lo, mut hi) = (0.0, (trial - y0) / g3);
    let (mut flo, mut fhi) = (trial - y0, f(hi));
    let mut d = hi;
    if fhi < 0.0 {
        let tol = 1e-10 * hi;
        let mut side = 0i8;
        for _ in 0..100 {
            d = (lo * fhi - hi * flo) / (fhi - flo);
            let fd = f(d);
            if fd == 0.0 || hi - lo < tol {
                break;
            }
            if fd > 0.0 {
                lo = d;
                flo = fd;
                if side == 1 {
                    fhi *= 0.5;
                }
                side = 1;
            } else {
                hi = d;
                fhi = fd;
                if side == -1 {
                    flo *= 0.5;
                }
                side = -1;
            }
        }
    }
    let y = (trial - g3 * d).max(0.0);
    let scale = y / trial;
    for v in s.iter_mut() {
        *v *= scale;
    }
    Return {
        d_eps: d,
        flow_stress: y,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// After the return the von Mises stress equals σ_JC at the updated strain and rate, and
    /// consistency σ_tr − 3GΔε = σ_y holds.
    #[test]
    fn lands_on_the_rate_dependent_yield_surface() {
        let jc = JohnsonCook::aisi1045_article();
        let g = 80e9;
        for (t, amp) in [(293.15, 2e9), (700.0, 1e9), (1700.0, 5e8), (2000.0, 5e8)] {
            let mut s = [amp, 0.3 * amp, -0.4 * amp, -0.6 * amp];
            let r = radial_return(&jc, g, &mut s, 0.1, t, 1e-9, 1.0);
            let vm = (1.5 * (s[0] * s[0] + s[2] * s[2] + s[3] * s[3] + 2.0 * s[1] * s[1])).sqrt();
            let want = jc.flow_stress(0.1 + r.d_eps, r.d_eps / 1e-9, t);
            assert!(
                (vm - want).abs() <= 1e-6 * want.max(1.0),
                "T {t}: {vm} vs {want}"
            );
            assert!(r.d_eps.is_finite() && r.d_eps >= 0.0);
        }
        // Elastic: untouched.
        let mut s = [1e6, 0.0, -1e6, 0.0];
        assert_eq!(
            radial_return(&jc, g, &mut s, 0.0, 293.15, 1e-9, 1.0).d_eps,
            0.0
        );
        assert_eq!(s, [1e6, 0.0, -1e6, 0.0]);
    }
}
