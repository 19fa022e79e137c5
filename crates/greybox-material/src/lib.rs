//! Workpiece materials for the simulator: Johnson–Cook flow stress, isotropic elasticity and
//! temperature-dependent thermal properties. SI units throughout (Pa, K, kg/m³, W/(m·K),
//! J/(kg·K)).

pub mod fit;
pub mod johnson_cook;
pub mod material;
pub mod table;

pub use johnson_cook::JohnsonCook;
pub use material::{Elastic, Material, Thermal};
pub use table::Table1d;
