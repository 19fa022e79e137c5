//! Workpiece materials for the simulator: flow stress (Johnson–Cook, TANH Johnson–Cook,
//! tabulated curves), ductile damage (Johnson–Cook), isotropic elasticity and
//! temperature-dependent thermal properties. SI units throughout (Pa, K, kg/m³, W/(m·K),
//! J/(kg·K)).

pub mod damage;
pub mod fit;
pub mod flow_stress;
pub mod flow_table;
pub mod johnson_cook;
pub mod material;
pub mod table;
pub mod tanh;

pub use damage::JohnsonCookDamage;
pub use flow_stress::FlowStress;
pub use flow_table::FlowTable;
pub use johnson_cook::JohnsonCook;
pub use material::{Elastic, Material, Thermal};
pub use table::Table1d;
pub use tanh::TanhJohnsonCook;

/// x^e, with whole exponents up to 8 in size (the published sets use several: the
/// Sima–Özel a = c = 2, b = 5, d = m = 1) taken by repeated multiplication ([`powi_inline`])
/// instead of a call of `pow`: the flow stress is evaluated several times per plastic
/// particle and step. (The whole-number test compares with the exponent cast to an integer
/// rather than calling `fract`, which costs a call of `trunc` on every particle's
/// temperature factors.)
#[inline]
pub(crate) fn powf(x: f64, e: f64) -> f64 {
    if e.abs() <= 8.0 && f64::from(e as i32) == e {
        powi_inline(x, e as i32)
    } else {
        x.powf(e)
    }
}

/// x^k by binary powering, inlined: the same products in the same order as the runtime
/// routine behind `f64::powi` with an exponent known only at run time (`__powidf2` of
/// compiler-rt / compiler-builtins: r ← r·x on each set bit from the lowest, x ← x² between,
/// 1/r for k < 0), so the same bytes, without the call (about 6 ns, the price of one `exp`,
/// on every particle's temperature factors and every evaluation of the TANH flow stress).
#[inline(always)]
pub(crate) fn powi_inline(x: f64, k: i32) -> f64 {
    let mut base = x;
    let mut bits = k.unsigned_abs();
    let mut r = 1.0;
    loop {
        if bits & 1 != 0 {
            r *= base;
        }
        bits >>= 1;
        if bits == 0 {
            break;
        }
        base *= base;
    }
    if k < 0 {
        1.0 / r
    } else {
        r
    }
}

#[cfg(test)]
mod power_tests {
    use super::powi_inline;

    /// The inlined power is `powi` bit for bit (the results of every cut rest on it), for
    /// whole exponents −8..=8 over bases across the ranges the flow-stress models raise
    /// (T/T_m, ε + p, T*) and beyond, zero and negative included.
    #[test]
    fn inlined_power_is_powi_bit_for_bit() {
        let mut x = 1e-3f64;
        let mut bases = vec![0.0, -0.0, 1.0, -1.5, 2.0, 1e-300, 1e300];
        while x < 50.0 {
            bases.push(x);
            bases.push(-x);
            x *= 1.037_13;
        }
        for b in bases {
            for k in -8..=8 {
                let want = b.powi(std::hint::black_box(k));
                let got = powi_inline(b, k);
                assert!(
                    got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                    "{b}^{k}: {got:e} vs {want:e}"
                );
            }
        }
    }
}
