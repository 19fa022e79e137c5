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
/// Sima–Özel a = c = 2, b = 5, d = m = 1) taken by repeated multiplication (`powi`, within
/// a few ulp) instead of a call of `pow`: the flow stress is evaluated several times per
/// plastic particle and step. (The whole-number test compares with the exponent cast to
/// an integer rather than calling `fract`, which costs a call of `trunc` on every
/// particle's temperature factors.)
#[inline]
pub(crate) fn powf(x: f64, e: f64) -> f64 {
    if e.abs() <= 8.0 && f64::from(e as i32) == e {
        x.powi(e as i32)
    } else {
        x.powf(e)
    }
}
