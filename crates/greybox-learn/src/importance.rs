//! Permutation feature importance (Breiman 2001; scikit-learn's `permutation_importance`):
//! importance_j = score(X, y) − score(X with column j permuted, y), repeated with seeded
//! permutations; reported as mean ± population standard deviation. Score: R².

use crate::metrics::r2;
use greybox_model::Matrix;
use greybox_model::Predictor;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Importance {
    pub feature: String,
    pub mean: f64,
    pub std: f64,
}

/// Permutation importance of every feature. The permutations are drawn from one seeded
/// stream in a fixed order (feature by feature, repeat by repeat) and the repeats are then
/// scored in parallel, so the result does not depend on the thread count. No repeats: none
/// (the importance skipped).
pub fn permutation_importance(
    model: &dyn Predictor,
    x: &Matrix,
    y: &[f64],
    names: &[String],
    repeats: usize,
    seed: u64,
) -> Vec<Importance> {
    if repeats == 0 {
        return Vec::new(); // skipped (`importance_repeats` 0): no mean over no repeats
    }
    let base = r2(y, &model.predict(x));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..x.n_cols)
        .map(|j| {
            let col = x.column(j);
            let permuted: Vec<Vec<f64>> = (0..repeats)
                .map(|_| {
                    let mut perm = col.clone();
                    perm.shuffle(&mut rng);
                    perm
                })
                .collect();
            let drops: Vec<f64> = permuted
                .par_iter()
                .map(|perm| {
                    let mut xp = x.clone();
                    for (i, v) in perm.iter().enumerate() {
                        xp.data[i * x.n_cols + j] = *v;
                    }
                    base - r2(y, &model.predict(&xp))
                })
                .collect();
            let m = drops.iter().sum::<f64>() / repeats as f64;
            let sd = (drops.iter().map(|d| (d - m).powi(2)).sum::<f64>() / repeats as f64).sqrt();
            Importance {
                feature: names.get(j).cloned().unwrap_or_else(|| format!("x{j}")),
                mean: m,
                std: sd,
            }
        })
        .collect()
}
