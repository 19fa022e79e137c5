//! Random forest regression (Breiman, "Random Forests", Machine Learning 45, 2001): bagged
//! CART trees grown to purity on bootstrap samples, averaged. Defaults follow
//! scikit-learn's `RandomForestRegressor` (all features per split, min_samples_leaf = 1).

use crate::regressor::{GridSearch, Regressor};
use crate::tree::{grow, GrowParams};
use greybox_core::{Error, Result};
use greybox_model::tree::TreeEnsemble;
use greybox_model::Matrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use greybox_model::ensemble::ForestParams;
use greybox_model::ensemble::Trees;

impl Regressor for ForestParams {
    type Fitted = TreeEnsemble;

    fn validate(&self) -> Result<()> {
        Trees::of_usize(self.n_estimators, "n_estimators")
            .map_err(|e| Error::invalid("random forest", e))?;
        if self.min_samples_leaf == 0 {
            return Err(Error::invalid(
                "random forest",
                "min_samples_leaf must be ≥ 1",
            ));
        }
        if self.max_features == Some(0) || self.max_depth == Some(0) {
            return Err(Error::invalid(
                "random forest",
                "max_features and max_depth must be ≥ 1",
            ));
        }
        Ok(())
    }

    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<TreeEnsemble> {
        let n = x.n_rows;
        let g: Vec<f64> = y.iter().map(|v| -v).collect();
        let h = vec![1.0; n];
        let p = GrowParams {
            max_depth: self.max_depth,
            min_samples_leaf: self.min_samples_leaf,
            min_child_weight: 0.0,
            lambda: 0.0,
            min_split_gain: 1e-14,
            max_features: self.max_features,
            leaf_scale: 1.0,
        };
        let trees: Vec<(Vec<greybox_model::tree::Node>, u32)> = (0..self.n_estimators)
            .into_par_iter()
            .map(|t| {
                let mut rng = ChaCha8Rng::seed_from_u64(
                    seed ^ (t as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15),
                );
                let rows: Vec<usize> = if self.bootstrap {
                    (0..n).map(|_| rng.gen_range(0..n)).collect()
                } else {
                    (0..n).collect()
                };
                let mut nodes = Vec::new();
                let root = grow(x, &g, &h, &rows, p, &mut rng, &mut nodes);
                (nodes, root)
            })
            .collect();
        let mut ens = TreeEnsemble::new(x.n_cols, 0.0, 1.0 / self.n_estimators as f64);
        for (nodes, root) in trees {
            ens.push_tree(nodes, root);
        }
        Ok(ens)
    }
}

/// Random-forest grid (article: n_estimators ∈ {10, 50, 100, 200}).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ForestGrid {
    pub base: ForestParams,
    pub n_estimators: Vec<usize>,
}

impl Default for ForestGrid {
    fn default() -> Self {
        ForestGrid {
            base: ForestParams::default(),
            n_estimators: vec![10, 50, 100, 200],
        }
    }
}

impl GridSearch for ForestParams {
    type Grid = ForestGrid;
    fn candidates(grid: &ForestGrid) -> Vec<Self> {
        grid.n_estimators
            .iter()
            .map(|&n| ForestParams {
                n_estimators: n,
                ..grid.base.clone()
            })
            .collect()
    }
}
