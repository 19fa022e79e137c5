#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-sim: a 2D plane-strain updated-Lagrangian SPH solver for solids with rigid tools,
//! penalty contact and friction windows — the tribometer pin sliding and orthogonal cutting.
//!
//! Layout (the argmin split: problem / one step / executor with observers):
//! * [`model`] what is simulated (particles, material, tools, boundary groups, numerics);
//! * [`solver`] one explicit step ([`solver::Solver::step`]) with its pure per-particle kernels;
//! * [`executor`] the time loop and its seams ([`executor::Hooks`]): read-only
//!   [`executor::Observer`]s (outputs, histories), [`executor::Controller`]s (the friction
//!   windows' update) and [`executor::CheckpointWriter`]s;
//! * [`pin`] the pin-sliding set-up and the inverse search for the adhesive μ.

pub mod checkpoint;
pub mod chip;
pub mod coarsen;
pub(crate) mod contact;
pub mod cpu;
pub mod cut_run;
pub mod cut_series;
pub mod cutting;
pub(crate) mod disjoint;
pub mod executor;
pub mod friction_loop;
pub mod geometry;
pub mod kernel;
pub mod model;
pub mod neighbours;
pub mod output;
pub(crate) mod pair_lanes;
pub mod particles;
pub mod pin;
pub mod plasticity;
mod rates;
pub mod refine;
pub mod serration;
pub mod sink;
pub mod solver;
pub mod steady;
pub mod steady_report;
pub mod tool;
pub mod tool_thermal;

pub use executor::{
    restored_state, run, CheckpointWriter, Control, Controller, Hooks, Observer, ObserverStates,
    RunSummary, SavedState,
};
pub use geometry::RoundedPolygon;
pub use model::{BoundaryGroup, Model, Numerics};
pub use particles::Particles;
pub use solver::{SimError, Solver};
pub use tool::{ConstantMu, Motion, MotionSegment, Tool, Window};

/// Worker threads the solver runs on (rayon's pool: `RAYON_NUM_THREADS` or the core count).
pub fn threads() -> usize {
    rayon::current_num_threads()
}
