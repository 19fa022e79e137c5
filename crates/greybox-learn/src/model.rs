//! The regressor seam: a family's hyperparameters validate once and `fit` returns an
//! immutable fitted model (which predicts through [`Predictor`]). The registry of families,
//! their hyperparameters and fitted models is `greybox-model`'s, re-exported here.

use crate::Matrix;
use greybox_core::Result;
pub use greybox_model::family::{Family, FittedModel, Hyperparameters, Predictor};

/// A model family's hyperparameters.
pub trait Regressor: Send + Sync {
    type Fitted: Predictor;
    /// Check the hyperparameters (called once, before any fit).
    fn validate(&self) -> Result<()>;
    /// Fit on (x, y). `seed` drives every random choice.
    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<Self::Fitted>;
}

/// Training for every family of the registry: validate and fit whatever
/// [`Hyperparameters`] hold.
pub trait Train {
    fn validate(&self) -> Result<()>;
    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<FittedModel>;
}

impl Train for Hyperparameters {
    fn validate(&self) -> Result<()> {
        match self {
            Hyperparameters::RandomForest(p) => p.validate(),
            Hyperparameters::Svr(p) => p.validate(),
            Hyperparameters::GradientBoosting(p) => p.validate(),
            Hyperparameters::Mlp(p) => p.validate(),
            Hyperparameters::Imported(i) => Err(refit_imported(i)),
        }
    }
    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<FittedModel> {
        Ok(match self {
            Hyperparameters::RandomForest(p) => FittedModel::TreeEnsemble(p.fit(x, y, seed)?),
            Hyperparameters::Svr(p) => FittedModel::Svr(p.fit(x, y, seed)?),
            Hyperparameters::GradientBoosting(p) => FittedModel::TreeEnsemble(p.fit(x, y, seed)?),
            Hyperparameters::Mlp(p) => FittedModel::Mlp(p.fit(x, y, seed)?),
            Hyperparameters::Imported(i) => return Err(refit_imported(i)),
        })
    }
}

fn refit_imported(i: &greybox_model::family::ImportedFrom) -> greybox_core::Error {
    greybox_core::Error::invalid(
        "hyperparameters",
        format!(
            "an imported {} ({}) carries no greybox training parameters and cannot be refitted here; retrain it where it was made, or fit a greybox family",
            i.estimator, i.library
        ),
    )
}
