//! The registry of model families for inference: which families exist, their hyperparameters
//! (plain serde data) and their fitted models, each predicting single points without
//! allocating. Training (the `Regressor` seam) lives in `greybox-learn`.

use crate::ensemble::{BoostParams, ForestParams};
use crate::mlp::{MlpModel, MlpParams};
use crate::svr::{SvrModel, SvrParams};
use crate::tree::TreeEnsemble;
use serde::{Deserialize, Serialize};

pub use crate::predictor::Predictor;

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

impl greybox_core::choice::Choice for Family {
    const FIELD: &'static str = "family";
    const ALL: &'static [Self] = &[
        Family::RandomForest,
        Family::Svr,
        Family::GradientBoosting,
        Family::Mlp,
    ];
    fn name(self) -> &'static str {
        Family::name(self)
    }
}
greybox_core::choice_traits!(Family, text);

/// Hyperparameters of any family (the unit a grid enumerates and a model file stores).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "kebab-case")]
pub enum Hyperparameters {
    RandomForest(ForestParams),
    Svr(SvrParams),
    GradientBoosting(BoostParams),
    Mlp(MlpParams),
    /// A model trained elsewhere and imported (`greybox import`): no greybox training
    /// parameters, only where it came from.
    Imported(ImportedFrom),
}

/// Where an imported model came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImportedFrom {
    /// The greybox family it belongs to (tree ensembles: random forest or boosting).
    pub as_family: Family,
    /// The library and its version, e.g. "scikit-learn 1.9.1", "xgboost 3.2.0".
    pub library: String,
    /// The estimator, e.g. "Pipeline(StandardScaler, SVR)", "xgboost.Booster (gbtree)".
    pub estimator: String,
    /// The source file's name and SHA-256, when imported from a file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
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
    fn predict(&self, x: &crate::matrix::Matrix) -> Vec<f64> {
        match self {
            FittedModel::TreeEnsemble(m) => m.predict_rows(x),
            FittedModel::Svr(m) => m.predict(x),
            FittedModel::Mlp(m) => m.predict(x),
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
            Hyperparameters::Imported(i) => i.as_family,
        }
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
            Hyperparameters::Imported(i) => format!("imported {} ({})", i.estimator, i.library),
        }
    }
}
