//! Prediction intervals by cross-validation conformal prediction.
//!
//! The half-width is the ⌈(n+1)(1−α)⌉-th smallest absolute out-of-fold residual of the
//! selected configuration (split-conformal quantile, Vovk et al. 2005; applied to K-fold
//! residuals as in the CV+ family, Barber et al., Ann. Statist. 49, 2021). Under
//! exchangeability, ŷ ± q covers a new observation from the same distribution with
//! probability ≈ 1 − α. The guarantee is marginal and holds only inside the training
//! domain: outside it the model file's domain check warns or refuses.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PredictionInterval {
    /// Nominal coverage 1 − α.
    pub coverage: f64,
    /// Half-width q (target units): the interval is ŷ ± q.
    pub half_width: f64,
    pub method: IntervalMethod,
}

impl PredictionInterval {
    /// No interval (coverage 0, half-width 0): a model whose held-out residuals are unknown.
    pub const NONE: PredictionInterval = PredictionInterval {
        coverage: 0.0,
        half_width: 0.0,
        method: IntervalMethod::None,
    };
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntervalMethod {
    /// Out-of-fold residuals of greybox's cross-validation.
    CvConformal,
    /// Residuals on calibration rows the model was not trained on (an imported model).
    SplitConformal,
    /// No interval: a model imported without calibration data (half-width 0).
    None,
}

/// Conformal half-width from out-of-fold residuals.
pub fn conformal_half_width(y: &[f64], oof: &[f64], coverage: f64) -> f64 {
    let mut r: Vec<f64> = y.iter().zip(oof).map(|(a, b)| (a - b).abs()).collect();
    r.sort_by(f64::total_cmp);
    let n = r.len();
    let k = (((n + 1) as f64) * coverage).ceil() as usize;
    r[k.clamp(1, n) - 1]
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn quantile_rank() {
        let y: Vec<f64> = (0..19).map(|i| i as f64).collect();
        let p = vec![0.0; 19];
        // (19+1)·0.95 = 19 → the largest residual
        assert_eq!(conformal_half_width(&y, &p, 0.95), 18.0);
        assert_eq!(conformal_half_width(&y, &p, 0.5), 9.0);
    }
}
