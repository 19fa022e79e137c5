//! The prediction seam every fitted model implements.

use crate::Matrix;

/// Something that predicts a scalar from a feature row: the seam every fitted model
/// ([`crate::FittedModel`]: trees, ensembles, MLPs, SVRs) implements and every consumer
/// (grey-box laws, cross-validation, reports) calls.
///
/// Implement [`Predictor::predict_one`]; [`Predictor::predict`] maps it over a matrix's
/// rows (override it for a faster batch path that gives the same values).
///
/// ```
/// use greybox_model::{Matrix, Predictor};
///
/// /// y = w · x + b.
/// struct Linear { w: Vec<f64>, b: f64 }
/// impl Predictor for Linear {
///     fn predict_one(&self, x: &[f64]) -> f64 {
///         self.w.iter().zip(x).map(|(w, x)| w * x).sum::<f64>() + self.b
///     }
/// }
///
/// let model = Linear { w: vec![2.0, -1.0], b: 0.5 };
/// assert_eq!(model.predict_one(&[1.0, 1.0]), 1.5);
/// let x = Matrix::from_rows(&[vec![1.0, 1.0], vec![0.0, 2.0]]);
/// assert_eq!(model.predict(&x), vec![1.5, -1.5]);
/// ```
pub trait Predictor: Send + Sync {
    /// Prediction for one row (no allocation).
    fn predict_one(&self, x: &[f64]) -> f64;
    /// Predictions for every row of `x`.
    fn predict(&self, x: &Matrix) -> Vec<f64> {
        (0..x.n_rows).map(|i| self.predict_one(x.row(i))).collect()
    }
}
