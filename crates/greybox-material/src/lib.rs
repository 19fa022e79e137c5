//! Workpiece materials for the simulator: flow stress (Johnson–Cook, TANH Johnson–Cook,
//! tabulated curves), isotropic elasticity and
//! temperature-dependent thermal properties. SI units throughout (Pa, K, kg/m³, W/(m·K),
//! J/(kg·K)).

pub mod fit;
pub mod flow_stress;
pub mod flow_table;
pub mod johnson_cook;
pub mod material;
pub mod table;
pub mod tanh;

pub use flow_stress::FlowStress;
pub use flow_table::FlowTable;
pub use johnson_cook::JohnsonCook;
pub use material::{Elastic, Material, Thermal};
pub use table::Table1d;
pub use tanh::TanhJohnsonCook;
