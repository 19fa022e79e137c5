#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-friction: every way greybox expresses friction, behind one trait
//! ([`greybox_core::FrictionLaw`]).
//!
//! * [`classical`] — Coulomb, shear factor, Zorev, Usui/Childs, exponential velocity decay,
//!   thermal softening, and μ from cutting forces (Merchant) or tool geometry (Du et al.).
//! * [`compose`] — a factor on any law's μ, and the Zorev shear cap on any law.
//! * [`learned`] — a model file from `greybox fit` as a law of (p, v, T).
//! * [`greybox`] — the grey-box composition: learned inside the training domain, a physics or
//!   fitted white-box law outside, smoothly blended, optional Zorev cap and clamping.
//! * [`table`] — laws baked onto uniform (p, v[, T]) grids with bi/trilinear interpolation.
//! * [`exact_table`] — tree ensembles as cells between their split thresholds (exact).
//! * [`adaptive`] — non-uniform grids refined until a max deviation is met (smooth laws);
//!   the refinement is [`refine`].
//! * [`table_file`] — table files of every kind and schema version ([`table_schema`]).
//! * [`surrogate`] — the right table for a law (exact, adaptive or uniform) and its check.
//! * [`lines`] — axis lines with constant-time lookup, shared interpolation.
//! * [`spec`] — law files (JSON) that describe any of the above; [`spec_fields`] reads and
//!   sets their numeric fields by dotted path (what a calibration fits).
//! * [`export`] — Abaqus `*FRICTION`, DEFORM `FRCFAC`/`FRCWIN`, LS-DYNA tables, CSV, each with
//!   its max deviation from the law ([`engine_table`]: engine units, exact step lines; the
//!   grid and units in [`grid`]).
//! * [`gradient`] — ∂μ/∂p, ∂μ/∂v, ∂μ/∂T for implicit solvers.

pub mod adaptive;
pub mod adaptive_refine;
pub mod classical;
pub mod compose;
pub mod engine_table;
pub mod exact_table;
pub mod export;
pub mod gradient;
pub mod greybox;
pub mod grid;
pub mod learned;
pub mod lines;
pub mod spec;
pub mod spec_fields;
pub mod surrogate;
pub mod table;
pub mod table_file;
pub mod table_schema;
