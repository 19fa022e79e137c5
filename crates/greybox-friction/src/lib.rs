#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-friction: every way greybox expresses friction, behind one trait
//! ([`greybox_core::FrictionLaw`]).
//!
//! * [`classical`] — Coulomb, shear factor, Zorev, Usui/Childs, exponential velocity decay,
//!   thermal softening, and μ from cutting forces (Merchant) or tool geometry (Du et al.).
//! * [`learned`] — a model file from `greybox fit` as a law of (p, v, T).
//! * [`greybox`] — the grey-box composition: learned inside the training domain, a physics or
//!   fitted white-box law outside, smoothly blended, optional Zorev cap and clamping.
//! * [`table`] — laws baked onto uniform (p, v[, T]) grids with bi/trilinear interpolation.
//! * [`spec`] — law files (JSON) that describe any of the above.
//! * [`export`] — Abaqus `*FRICTION`, DEFORM `FRCFAC`/`FRCWIN`, LS-DYNA tables, CSV.
//! * [`gradient`] — ∂μ/∂p, ∂μ/∂v, ∂μ/∂T for implicit solvers.

pub mod classical;
pub mod export;
pub mod gradient;
pub mod greybox;
pub mod learned;
pub mod spec;
pub mod table;

pub use greybox_core::{ContactState, FrictionLaw};
