//! The regressor seam: hyperparameters are plain serde data, validated once; `fit` returns
//! an immutable fitted model; fitted models predict single points without allocating.

use crate::boost::BoostParams;
use crate::forest::ForestParams;
use crate::mlp::{MlpModel, MlpParams};
use crate::svr::{SvrModel, SvrParams};
use crate::tree::TreeEnsemble;
use crate::Matrix;
use greybox_core::Result;
use serde::{Deserialize, Serialize};

/// Something that predicts a scalar from a feature row.
pub trait Predictor: Send + Sync {
    /// Prediction for one row (no allocation).
    fn predict_one(&self, x: &[f64]) -> f64;
    /// Predictions for every row of `x`.
    fn predict(&self, x: &Matrix) -> Vec<f64> {
        (0..x.n_rows).map(|i| self.predict_one(x.row(i))).collect()
    }
}

/// A model family's hyperparameters.
pub trait Regressor: Send + Sync {
    type Fitted: Predictor;
    /// Check the hyperparameters (called once, before any fit).
    fn validate(&self) -> Result<()>;
    /// Fit on (x, y). `seed` drives every random choice.
    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<Self::Fitted>;
}

impl Predictor for TreeEnsemble {
    fn predict_one(&self, x: &[f64]) -> f64 {
        TreeEnsemble::predict_one(self, x)
    }
}

/// The four model families.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    RandomForest,
    Svr,
    GradientBoosting,
    Mlp,
}

impl Family {
    pub const ALL: [Family; 4] = [
        Family::RandomForest,
        Family::Svr,
        Family::GradientBoosting,
        Family::Mlp,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Family::RandomForest => "random-forest",
            Family::Svr => "svr",
            Family::GradientBoosting => "gradient-boosting",
            Family::Mlp => "mlp",
        }
    }
    /// Column title as in the article's tables.
    pub fn title(self) -> &'static str {
        match self {
            Family::RandomForest => "RF",
            Family::Svr => "SV",
            Family::GradientBoosting => "XGBoost-style",
            Family::Mlp => "FFNN",
        }
    }
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == s.trim())
    }
}

/// Hyperparameters of any family (the unit a grid enumerates and a model file stores).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "kebab-case")]
pub enum Hyperparameters {
    RandomForest(ForestParams),
    Svr(SvrParams),
    GradientBoosting(BoostParams),
    Mlp(MlpParams),
}

/// A fitted model of any family.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum FittedModel {
    TreeEnsemble(TreeEnsemble),
    Svr(SvrModel),
    Mlp(MlpModel),
}

impl Predictor for FittedModel {
    #[inline]
    fn predict_one(&self, x: &[f64]) -> f64 {
        match self {
            FittedModel::TreeEnsemble(m) => m.predict_one(x),
            FittedModel::Svr(m) => m.predict_one(x),
            FittedModel::Mlp(m) => m.predict_one(x),
        }
    }
}

impl Hyperparameters {
    pub fn family(&self) -> Family {
        match self {
            Hyperparameters::RandomForest(_) => Family::RandomForest,
            Hyperparameters::Svr(_) => Family::Svr,
            Hyperparameters::GradientBoosting(_) => Family::GradientBoosting,
            Hyperparameters::Mlp(_) => Family::Mlp,
        }
    }
    pub fn validate(&self) -> Result<()> {
        match self {
            Hyperparameters::RandomForest(p) => p.validate(),
            Hyperparameters::Svr(p) => p.validate(),
            Hyperparameters::GradientBoosting(p) => p.validate(),
            Hyperparameters::Mlp(p) => p.validate(),
        }
    }
    pub fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<FittedModel> {
        Ok(match self {
            Hyperparameters::RandomForest(p) => FittedModel::TreeEnsemble(p.fit(x, y, seed)?),
            Hyperparameters::Svr(p) => FittedModel::Svr(p.fit(x, y, seed)?),
            Hyperparameters::GradientBoosting(p) => FittedModel::TreeEnsemble(p.fit(x, y, seed)?),
            Hyperparameters::Mlp(p) => FittedModel::Mlp(p.fit(x, y, seed)?),
        })
    }
    /// Short description of the grid-relevant values, e.g. `n_estimators=100`.
    pub fn label(&self) -> String {
        match self {
            Hyperparameters::RandomForest(p) => format!("n_estimators={}", p.n_estimators),
            Hyperparameters::Svr(p) => format!(
                "kernel={}, C={}, epsilon={}",
                p.kernel.name(),
                p.c,
                p.epsilon
            ),
            Hyperparameters::GradientBoosting(p) => {
                format!(
                    "n_estimators={}, max_depth={}, learning_rate={}",
                    p.n_estimators, p.max_depth, p.learning_rate
                )
            }
            Hyperparameters::Mlp(p) => format!(
                "hidden=({}), activation={}, learning_rate={}",
                p.hidden_layers
                    .iter()
                    .map(|h| h.to_string())
                    .collect::<Vec<_>>()
                    .join(","),
                p.activation.name(),
                p.learning_rate
            ),
        }
    }
}
