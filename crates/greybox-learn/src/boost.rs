//! Gradient-boosted regression trees, XGBoost-style (Chen & Guestrin, KDD 2016): second-order
//! statistics, L2-regularised leaf weights w = −G/(H+λ), split gain G_L²/(H_L+λ) +
//! G_R²/(H_R+λ) − G²/(H+λ) > γ, exact greedy split search, depth-wise growth, shrinkage η.
//! Squared loss (g = ŷ − y, h = 1); the base score is the mean of y (XGBoost ≥ 2.0's
//! estimated intercept for `reg:squarederror`). Defaults follow XGBoost where the grid does
//! not set a value (λ = 1, min_child_weight = 1, γ = 0).

use crate::regressor::{GridSearch, Regressor};
use crate::tree::{grow_with_leaves, GrowParams};
use greybox_core::{Error, Result};
use greybox_model::tree::TreeEnsemble;
use greybox_model::Matrix;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use greybox_model::ensemble::BoostParams;
use greybox_model::ensemble::{BoostDepth, Trees};

/// XGBoost's smallest accepted loss change (kRtEps).
const MIN_LOSS_CHANGE: f64 = 1e-6;

impl Regressor for BoostParams {
    type Fitted = TreeEnsemble;

    fn validate(&self) -> Result<()> {
        let invalid = |e| Error::invalid("gradient boosting", e);
        Trees::of_usize(self.n_estimators, "n_estimators").map_err(invalid)?;
        BoostDepth::of_usize(self.max_depth, "max_depth").map_err(invalid)?;
        if !(self.learning_rate > 0.0 && self.learning_rate <= 1.0) {
            return Err(Error::invalid(
                "gradient boosting",
                format!(
                    "learning_rate must be in (0, 1], got {}",
                    self.learning_rate
                ),
            ));
        }
        if !(self.lambda >= 0.0 && self.min_child_weight >= 0.0 && self.gamma >= 0.0) {
            return Err(Error::invalid(
                "gradient boosting",
                "lambda, min_child_weight and gamma must be ≥ 0",
            ));
        }
        Ok(())
    }

    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<TreeEnsemble> {
        let n = x.n_rows;
        let base = y.iter().sum::<f64>() / n as f64;
        let mut pred = vec![base; n];
        let h = vec![1.0; n];
        let mut g = vec![0.0; n];
        let p = GrowParams {
            max_depth: Some(self.max_depth),
            min_samples_leaf: 1,
            min_child_weight: self.min_child_weight,
            lambda: self.lambda,
            min_split_gain: self.gamma.max(MIN_LOSS_CHANGE),
            max_features: None,
            leaf_scale: self.learning_rate,
        };
        let mut rng = ChaCha8Rng::seed_from_u64(seed); // unused without column sampling; kept for the seam
        let mut ens = TreeEnsemble::new(x.n_cols, base, 1.0);
        let order = crate::tree::presort(x, &(0..n).collect::<Vec<_>>());
        for _ in 0..self.n_estimators {
            for i in 0..n {
                g[i] = pred[i] - y[i];
            }
            let mut nodes = Vec::new();
            let (root, fell) = grow_with_leaves(x, &g, &h, &order, p, &mut rng, &mut nodes);
            // Every row adds the value of the leaf it fell into (what a walk would find).
            for (leaf, rows) in fell.iter() {
                let v = nodes[leaf as usize].value;
                for &i in rows {
                    pred[i as usize] += v;
                }
            }
            ens.push_tree(nodes, root);
        }
        Ok(ens)
    }
}

/// Boosting grid (article: n_estimators ∈ {100, 300, 500} × max_depth ∈ {3, 5, 7} × lr ∈ {0.01, 0.05, 0.1}).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BoostGrid {
    pub base: BoostParams,
    pub n_estimators: Vec<usize>,
    pub max_depth: Vec<usize>,
    pub learning_rate: Vec<f64>,
}

impl Default for BoostGrid {
    fn default() -> Self {
        BoostGrid {
            base: BoostParams::default(),
            n_estimators: vec![100, 300, 500],
            max_depth: vec![3, 5, 7],
            learning_rate: vec![0.01, 0.05, 0.1],
        }
    }
}

impl GridSearch for BoostParams {
    type Grid = BoostGrid;
    /// Rounds outermost, then depth, then learning rate.
    fn candidates(grid: &BoostGrid) -> Vec<Self> {
        let mut out = Vec::new();
        for &n_estimators in &grid.n_estimators {
            for &max_depth in &grid.max_depth {
                for &learning_rate in &grid.learning_rate {
                    out.push(BoostParams {
                        n_estimators,
                        max_depth,
                        learning_rate,
                        ..grid.base.clone()
                    });
                }
            }
        }
        out
    }
}
