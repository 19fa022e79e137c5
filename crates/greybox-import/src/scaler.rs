//! scikit-learn's scalers in front of a model, evaluated exactly as scikit-learn does, and
//! folded into greybox's standardiser for SVR and MLP models.
//!
//! * `StandardScaler.transform`: `X -= mean_` (if `with_mean`), `X /= scale_` (if `with_std`).
//! * `MinMaxScaler.transform`: `X *= scale_`, `X += min_`, then optionally clipped to
//!   `feature_range`.
//!
//! Both are monotone non-decreasing in each feature (positive scales), which is what lets
//! tree splits behind them be restated as exact raw-input boundaries.

use greybox_model::matrix::Standardizer;
use serde::Deserialize;

/// One scaler step of a pipeline (exported by greybox's Python package).
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Scaler {
    /// (x − mean) / scale; `mean` 0 without centring, `scale` 1 without scaling.
    StandardScaler { mean: Vec<f64>, scale: Vec<f64> },
    /// x · scale + min, clipped to `clip` = (low, high) when the scaler clips.
    MinMaxScaler {
        scale: Vec<f64>,
        min: Vec<f64>,
        #[serde(default)]
        clip: Option<(f64, f64)>,
    },
}

impl Scaler {
    pub fn name(&self) -> &'static str {
        match self {
            Scaler::StandardScaler { .. } => "StandardScaler",
            Scaler::MinMaxScaler { .. } => "MinMaxScaler",
        }
    }

    /// Sizes match, numbers finite, scales positive (a scaler that reverses a feature would
    /// turn `<=` splits around).
    pub fn check(&self, n_features: usize) -> Result<(), String> {
        let (a, b) = match self {
            Scaler::StandardScaler { mean, scale } => (scale, mean),
            Scaler::MinMaxScaler { scale, min, .. } => (scale, min),
        };
        if a.len() != n_features || b.len() != n_features {
            return Err(format!(
                "{}: {} and {} values for {n_features} features",
                self.name(),
                a.len(),
                b.len()
            ));
        }
        if let Some(i) = a.iter().position(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(format!(
                "{}: scale of feature {i} is {} (must be positive and finite)",
                self.name(),
                a[i]
            ));
        }
        if let Some(i) = b.iter().position(|s| !s.is_finite()) {
            return Err(format!(
                "{}: offset of feature {i} is {}",
                self.name(),
                b[i]
            ));
        }
        Ok(())
    }

    /// Feature `f` of a row, transformed exactly as scikit-learn does (float64).
    #[inline]
    pub fn apply(&self, f: usize, x: f64) -> f64 {
        match self {
            Scaler::StandardScaler { mean, scale } => (x - mean[f]) / scale[f],
            Scaler::MinMaxScaler { scale, min, clip } => {
                let z = x * scale[f] + min[f];
                match clip {
                    Some((lo, hi)) => z.clamp(*lo, *hi),
                    None => z,
                }
            }
        }
    }

    /// The affine map z = a·x + b of feature `f`, or `None` for a clipping scaler.
    fn affine(&self, f: usize) -> Option<(f64, f64)> {
        match self {
            Scaler::StandardScaler { mean, scale } => Some((1.0 / scale[f], -mean[f] / scale[f])),
            Scaler::MinMaxScaler {
                scale,
                min,
                clip: None,
            } => Some((scale[f], min[f])),
            Scaler::MinMaxScaler { clip: Some(_), .. } => None,
        }
    }
}

/// Per feature, the composition of affine maps z = a·x + b (applied in order) as the
/// standardiser (x − mean) / scale with mean = −b/a, scale = 1/a; `None` if a map is missing.
pub(crate) fn compose_affine(
    n_features: usize,
    maps: impl Fn(usize) -> Option<Vec<(f64, f64)>>,
) -> Option<Standardizer> {
    let mut mean = Vec::with_capacity(n_features);
    let mut scale = Vec::with_capacity(n_features);
    for f in 0..n_features {
        let (mut a, mut b) = (1.0, 0.0);
        for (sa, sb) in maps(f)? {
            (a, b) = (sa * a, sa * b + sb);
        }
        mean.push(-b / a);
        scale.push(1.0 / a);
    }
    Some(Standardizer { mean, scale })
}

/// The chain of scalers as one standardiser z = (x − mean) / scale: exact for no scaler or a
/// lone StandardScaler, otherwise the composed affine map (agreeing with the chain to a few
/// ulp). `None` when a step clips (not affine).
pub fn fold(steps: &[Scaler], n_features: usize) -> Option<Standardizer> {
    match steps {
        [] => Some(Standardizer {
            mean: vec![0.0; n_features],
            scale: vec![1.0; n_features],
        }),
        [Scaler::StandardScaler { mean, scale }] => Some(Standardizer {
            mean: mean.clone(),
            scale: scale.clone(),
        }),
        _ => compose_affine(n_features, |f| steps.iter().map(|s| s.affine(f)).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folded_chain_agrees_with_the_steps() {
        let steps = vec![
            Scaler::MinMaxScaler {
                scale: vec![0.5, 2.0],
                min: vec![-1.0, 0.25],
                clip: None,
            },
            Scaler::StandardScaler {
                mean: vec![0.3, -0.7],
                scale: vec![1.7, 0.2],
            },
        ];
        let s = fold(&steps, 2).unwrap();
        for x in [-3.0, 0.0, 0.4, 12.5] {
            for f in 0..2 {
                let chain = steps.iter().fold(x, |z, st| st.apply(f, z));
                let folded = (x - s.mean[f]) / s.scale[f];
                assert!((chain - folded).abs() <= 1e-14 * chain.abs().max(1.0));
            }
        }
    }
}
