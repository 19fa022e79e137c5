#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-learn: data-driven friction models with honest validation.
//!
//! * [`matrix`] — a row-major feature matrix; [`table`] — strict numeric CSV tables.
//! * [`model`] — the [`Regressor`](model::Regressor) seam: hyperparameters are serde data,
//!   validated once; `fit` returns an immutable fitted model that predicts single points
//!   without allocating.
//! * Families: [`forest`] (random forest, CART), [`boost`] (XGBoost-style second-order
//!   gradient boosting with L2 leaf regularisation), [`svr`] (ε-SVR, libsvm's SMO), [`mlp`]
//!   (two-hidden-layer network, Adam, early stopping). Trees share [`tree`].
//! * Protocol, written once against the seam: [`cv`] (k-fold, grid search, nested CV),
//!   [`metrics`] (MAE, MSE, MAPE, R², bootstrap CIs), [`importance`] (permutation),
//!   [`interval`] (CV-conformal prediction intervals), [`protocol`] (the article's study).
//! * [`modelfile`] — versioned, hashed JSON model files; [`plot`] — SVG plots.

pub mod boost;
pub mod cv;
mod fast_math;
pub mod forest;
pub mod importance;
pub mod metrics;
pub mod mlp;
pub mod protocol;
pub mod regressor;
pub mod svr;
pub mod svr_lowrank;
mod svr_rows;
mod svr_smo;
/// The SMO solver's insides, for the integration test that compares it with the full-matrix
/// solver it replaced (`tests/svr_smo_reference.rs`). Not part of the API.
#[doc(hidden)]
pub mod svr_test_kit {
    pub use crate::svr_rows::kernel_row;
    pub use crate::svr_smo::{g_bar_change, solve, Dual};
}
pub mod table;
pub mod tree;
