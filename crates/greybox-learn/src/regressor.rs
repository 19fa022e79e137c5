//! The regressor seam: a family's hyperparameters validate once and `fit` returns an
//! immutable fitted model (which predicts through [`Predictor`]). The registry of families,
//! their hyperparameters and fitted models is `greybox-model`'s.

use greybox_core::Result;
use greybox_model::family::{FittedModel, Hyperparameters, Predictor};
use greybox_model::Matrix;

/// A model family's hyperparameters: the seam for a new family. `validate` once, then `fit`
/// returns an immutable [`Predictor`]. A baseline family (the mean of the targets):
///
/// ```
/// use greybox_core::Result;
/// use greybox_learn::regressor::Regressor;
/// use greybox_model::Predictor;
/// use greybox_model::Matrix;
/// struct MeanFamily;
/// struct Mean(f64);
/// impl Predictor for Mean {
///     fn predict_one(&self, _x: &[f64]) -> f64 { self.0 }
/// }
/// impl Regressor for MeanFamily {
///     type Fitted = Mean;
///     fn validate(&self) -> Result<()> { Ok(()) }
///     fn fit(&self, _x: &Matrix, y: &[f64], _seed: u64) -> Result<Mean> {
///         Ok(Mean(y.iter().sum::<f64>() / y.len() as f64))
///     }
/// }
/// let x = Matrix { n_rows: 3, n_cols: 1, data: vec![1.0, 2.0, 3.0] };
/// let m = MeanFamily.fit(&x, &[0.2, 0.4, 0.6], 42)?;
/// assert!((m.predict(&x)[1] - 0.4).abs() < 1e-15);
/// # Ok::<(), greybox_core::Error>(())
/// ```
pub trait Regressor: Send + Sync {
    type Fitted: Predictor;
    /// Check the hyperparameters (called once, before any fit).
    fn validate(&self) -> Result<()>;
    /// Fit on (x, y). `seed` drives every random choice.
    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<Self::Fitted>;
}

/// A family's grid search: the grid type (a study's `[fit.grid.<family>]`, serde data with
/// the article's values as default) and the hyperparameter sets it expands to, in the order
/// they are tried.
pub trait GridSearch: Regressor + Sized {
    type Grid: std::fmt::Debug
        + Clone
        + PartialEq
        + Default
        + serde::Serialize
        + serde::de::DeserializeOwned;
    /// Every candidate of the grid (unvalidated).
    fn candidates(grid: &Self::Grid) -> Vec<Self>;
}

/// Training for every family of the registry: validate and fit whatever
/// [`Hyperparameters`] hold.
pub trait Train {
    fn validate(&self) -> Result<()>;
    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<FittedModel>;
}

/// [`Train`] from the registry's entries: each family's [`Regressor`].
macro_rules! train_families {
    ($($v:ident { name: $n:literal, title: $t:literal, grid: $g:ident, params: $p:ty },)+) => {
        impl Train for Hyperparameters {
            fn validate(&self) -> Result<()> {
                match self {
                    $(Hyperparameters::$v(p) => p.validate(),)+
                    Hyperparameters::Imported(i) => Err(refit_imported(i)),
                }
            }
            fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<FittedModel> {
                match self {
                    $(Hyperparameters::$v(p) => Ok(p.fit(x, y, seed)?.into()),)+
                    Hyperparameters::Imported(i) => Err(refit_imported(i)),
                }
            }
        }
    };
}
greybox_model::for_each_family!(train_families);

fn refit_imported(i: &greybox_model::family::ImportedFrom) -> greybox_core::Error {
    greybox_core::Error::invalid(
        "hyperparameters",
        format!(
            "an imported {} ({}) carries no greybox training parameters and cannot be refitted here; retrain it where it was made, or fit a greybox family",
            i.estimator, i.library
        ),
    )
}
