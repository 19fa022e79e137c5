//! The prediction seam every fitted model implements.

use crate::Matrix;

/// Something that predicts a scalar from a feature row.
pub trait Predictor: Send + Sync {
    /// Prediction for one row (no allocation).
    fn predict_one(&self, x: &[f64]) -> f64;
    /// Predictions for every row of `x`.
    fn predict(&self, x: &Matrix) -> Vec<f64> {
        (0..x.n_rows).map(|i| self.predict_one(x.row(i))).collect()
    }
}
