//! K-fold cross-validation, grid search and nested cross-validation, written once against
//! [`Hyperparameters`]. Every fit gets a seed derived from (base seed, candidate, fold), so
//! results are identical whatever the number of threads.

use crate::metrics::{mse, r2};
use crate::regressor::Train;
use greybox_core::{Error, Result};
use greybox_model::Matrix;
use greybox_model::{Hyperparameters, Predictor};
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Shuffled k-fold assignment: fold id per row; fold sizes differ by at most one.
pub fn kfold_ids(n: usize, k: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(seed));
    let mut ids = vec![0; n];
    let (base, extra) = (n / k, n % k);
    let mut pos = 0;
    for f in 0..k {
        let size = base + usize::from(f < extra);
        for &i in &order[pos..pos + size] {
            ids[i] = f;
        }
        pos += size;
    }
    ids
}

/// (train rows, test rows) per fold from fold ids (ids need not be contiguous).
pub fn splits(ids: &[usize]) -> Vec<(Vec<usize>, Vec<usize>)> {
    let mut folds: Vec<usize> = ids.to_vec();
    folds.sort_unstable();
    folds.dedup();
    folds
        .iter()
        .map(|&f| {
            let test: Vec<usize> = (0..ids.len()).filter(|&i| ids[i] == f).collect();
            let train: Vec<usize> = (0..ids.len()).filter(|&i| ids[i] != f).collect();
            (train, test)
        })
        .collect()
}

/// Check there are enough rows for `k` folds.
pub fn check_folds(n: usize, k: usize) -> Result<()> {
    if k < 2 {
        return Err(Error::invalid(
            "cross-validation",
            format!("need at least 2 folds, got {k}"),
        ));
    }
    if n < 2 * k {
        return Err(Error::invalid(
            "cross-validation",
            format!(
                "{n} rows are too few for {k}-fold cross-validation (need at least {})",
                2 * k
            ),
        ));
    }
    Ok(())
}

fn derive_seed(seed: u64, a: u64, b: u64) -> u64 {
    let mut z =
        seed ^ a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b.wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z ^ (z >> 31)
}

/// Out-of-fold predictions of one configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CvResult {
    /// Mean of the per-fold MSE.
    pub mse: f64,
    pub mse_per_fold: Vec<f64>,
    /// Out-of-fold prediction for every row.
    pub oof: Vec<f64>,
}

fn fit_fold(
    hp: &Hyperparameters,
    x: &Matrix,
    y: &[f64],
    train: &[usize],
    test: &[usize],
    seed: u64,
) -> Result<Vec<f64>> {
    greybox_core::interrupt::check()?;
    let xt = x.select_rows(train);
    let yt: Vec<f64> = train.iter().map(|&i| y[i]).collect();
    let m = hp.fit(&xt, &yt, seed)?;
    Ok(test.iter().map(|&i| m.predict_one(x.row(i))).collect())
}

/// Cross-validate each candidate on the same folds (parallel over candidates × folds).
pub fn cross_validate_all(
    grid: &[Hyperparameters],
    x: &Matrix,
    y: &[f64],
    ids: &[usize],
    seed: u64,
) -> Result<Vec<CvResult>> {
    let folds = splits(ids);
    let jobs: Vec<(usize, usize)> = (0..grid.len())
        .flat_map(|c| (0..folds.len()).map(move |f| (c, f)))
        .collect();
    let preds: Vec<Vec<f64>> = jobs
        .par_iter()
        .map(|&(c, f)| {
            fit_fold(
                &grid[c],
                x,
                y,
                &folds[f].0,
                &folds[f].1,
                derive_seed(seed, c as u64, f as u64),
            )
        })
        .collect::<Result<_>>()?;
    Ok((0..grid.len())
        .map(|c| {
            let mut oof = vec![0.0; y.len()];
            let mut mse_per_fold = Vec::with_capacity(folds.len());
            for (f, (_, test)) in folds.iter().enumerate() {
                let p = &preds[c * folds.len() + f];
                let yt: Vec<f64> = test.iter().map(|&i| y[i]).collect();
                mse_per_fold.push(mse(&yt, p));
                for (&i, v) in test.iter().zip(p) {
                    oof[i] = *v;
                }
            }
            CvResult {
                mse: mse_per_fold.iter().sum::<f64>() / mse_per_fold.len() as f64,
                mse_per_fold,
                oof,
            }
        })
        .collect())
}

/// Grid search by k-fold CV MSE; returns every candidate's result and the index of the best
/// (lowest mean MSE; the first on ties).
pub fn grid_search(
    grid: &[Hyperparameters],
    x: &Matrix,
    y: &[f64],
    ids: &[usize],
    seed: u64,
) -> Result<(Vec<CvResult>, usize)> {
    if grid.is_empty() {
        return Err(Error::invalid("grid search", "the grid is empty"));
    }
    let results = cross_validate_all(grid, x, y, ids, seed)?;
    let best = (0..results.len()).fold(0, |b, c| {
        if results[c].mse < results[b].mse {
            c
        } else {
            b
        }
    });
    Ok((results, best))
}

/// One outer fold of nested cross-validation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OuterFold {
    pub selected: Hyperparameters,
    pub r2: f64,
    pub mse: f64,
    pub n_test: usize,
}

/// Nested CV: in every outer fold a grid search on the outer-training rows (inner k-fold)
/// selects hyperparameters, which are refitted there and scored on the untouched outer test
/// rows. Returns the out-of-fold predictions and the per-fold results.
pub fn nested_cv(
    grid: &[Hyperparameters],
    x: &Matrix,
    y: &[f64],
    outer_ids: &[usize],
    inner_k: usize,
    seed: u64,
) -> Result<(Vec<f64>, Vec<OuterFold>)> {
    let folds = splits(outer_ids);
    let per: Vec<(Vec<f64>, OuterFold)> = folds
        .par_iter()
        .enumerate()
        .map(|(f, (train, test))| {
            greybox_core::interrupt::check()?;
            let xt = x.select_rows(train);
            let yt: Vec<f64> = train.iter().map(|&i| y[i]).collect();
            check_folds(train.len(), inner_k)?;
            let inner = kfold_ids(train.len(), inner_k, derive_seed(seed, 1_000 + f as u64, 0));
            let (_, best) = grid_search(
                grid,
                &xt,
                &yt,
                &inner,
                derive_seed(seed, 2_000 + f as u64, 0),
            )?;
            let model = grid[best].fit(&xt, &yt, derive_seed(seed, 3_000 + f as u64, 0))?;
            let p: Vec<f64> = test.iter().map(|&i| model.predict_one(x.row(i))).collect();
            let ytest: Vec<f64> = test.iter().map(|&i| y[i]).collect();
            Ok((
                p.clone(),
                OuterFold {
                    selected: grid[best].clone(),
                    r2: r2(&ytest, &p),
                    mse: mse(&ytest, &p),
                    n_test: test.len(),
                },
            ))
        })
        .collect::<Result<_>>()?;
    let mut oof = vec![0.0; y.len()];
    let mut outs = Vec::new();
    for ((_, test), (p, o)) in folds.iter().zip(per) {
        for (&i, v) in test.iter().zip(&p) {
            oof[i] = *v;
        }
        outs.push(o);
    }
    Ok((oof, outs))
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn kfold_balanced_and_deterministic() {
        let ids = kfold_ids(23, 5, 1);
        let mut counts = [0; 5];
        for &i in &ids {
            counts[i] += 1;
        }
        assert_eq!(counts, [5, 5, 5, 4, 4]);
        assert_eq!(ids, kfold_ids(23, 5, 1));
        assert_ne!(ids, kfold_ids(23, 5, 2));
        assert!(check_folds(9, 5).is_err());
    }
}
