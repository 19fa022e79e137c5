//! Hyperparameters of the tree ensembles (plain data, stored in model files): random forest
//! (scikit-learn's `RandomForestRegressor` defaults) and XGBoost-style gradient boosting
//! (XGBoost's defaults where the grid sets none). Fitting is `greybox-learn`'s.

use greybox_core::count::Count;
use serde::{Deserialize, Serialize};

/// Trees of a forest or boosting rounds: each is fitted and held in memory.
pub type Trees = Count<1, 100_000>;
/// Depth of a boosted tree: up to 2^depth leaves each.
pub type BoostDepth = Count<1, 64>;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ForestParams {
    pub n_estimators: usize,
    /// Depth limit (`None`: grow until leaves are pure).
    pub max_depth: Option<usize>,
    pub min_samples_leaf: usize,
    /// Features tried per split (`None`: all, scikit-learn's regression default).
    pub max_features: Option<usize>,
    /// Draw a bootstrap sample per tree.
    pub bootstrap: bool,
}

impl ForestParams {
    /// The grid-relevant values, e.g. `n_estimators=100`.
    pub fn label(&self) -> String {
        format!("n_estimators={}", self.n_estimators)
    }
}

impl Default for ForestParams {
    fn default() -> Self {
        ForestParams {
            n_estimators: 100,
            max_depth: None,
            min_samples_leaf: 1,
            max_features: None,
            bootstrap: true,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BoostParams {
    pub n_estimators: usize,
    pub max_depth: usize,
    pub learning_rate: f64,
    /// L2 regularisation of leaf weights λ.
    pub lambda: f64,
    /// Minimum sum of hessians (= rows, for squared loss) in a child.
    pub min_child_weight: f64,
    /// Minimum split gain γ.
    pub gamma: f64,
}

impl BoostParams {
    /// The grid-relevant values, e.g. `n_estimators=100, max_depth=3, learning_rate=0.1`.
    pub fn label(&self) -> String {
        format!(
            "n_estimators={}, max_depth={}, learning_rate={}",
            self.n_estimators, self.max_depth, self.learning_rate
        )
    }
}

impl Default for BoostParams {
    fn default() -> Self {
        BoostParams {
            n_estimators: 100,
            max_depth: 6,
            learning_rate: 0.3,
            lambda: 1.0,
            min_child_weight: 1.0,
            gamma: 0.0,
        }
    }
}
