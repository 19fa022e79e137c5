#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-model: what a fitted friction model needs at run time, apart from training — so
//! that the C ABI inside a user's FE solver links no training code, no recording readers and
//! no FFTs.
//!
//! * [`modelfile`] — versioned, hashed JSON model files with the training domain, the
//!   prediction interval, the dataset's force-to-pressure map and provenance; predictions
//!   with a domain check.
//! * [`structure`] — structural checks on load, so evaluation can never panic or loop.
//! * [`family`] — the registry of families: hyperparameters and fitted models, and the
//!   [`Predictor`] seam.
//! * Fitted models: [`tree`] (flat tree ensembles), [`svr`] (ε-SVR), [`mlp`] (networks);
//!   hyperparameters of the tree ensembles in [`ensemble`].
//! * [`matrix`] (feature matrix, standardiser), [`column`](mod@column) (names with units), [`interval`]
//!   (conformal prediction intervals).

pub mod column;
pub mod ensemble;
pub mod family;
pub mod interval;
pub mod matrix;
pub mod mlp;
pub mod modelfile;
pub mod predictor;
pub mod structure;
pub mod svr;
pub mod tree;

pub use family::{Family, FittedModel, Hyperparameters, Predictor};
pub use matrix::Matrix;
pub use modelfile::ModelFile;
