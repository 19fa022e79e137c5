//! scikit-learn estimators, as greybox's Python package exports them
//! (`greybox.from_sklearn`): the fitted attributes, untouched, in a JSON document of schema
//! `greybox-sklearn` — scikit-learn models themselves are pickles only Python can read.
//!
//! | estimator | greybox model | agreement |
//! |---|---|---|
//! | `RandomForestRegressor`, `ExtraTreesRegressor` | tree ensemble, mean of trees | splits bit-exact, sum to rounding |
//! | `GradientBoostingRegressor` | tree ensemble, init + Σ lr·leaf | splits bit-exact, sum to rounding |
//! | `HistGradientBoostingRegressor` (numerical splits, identity-link losses) | tree ensemble, baseline + Σ leaf | splits bit-exact (float64 comparisons), sum to rounding |
//! | `SVR` (linear, poly, rbf, sigmoid) | ε-SVR | to rounding |
//! | `MLPRegressor` (relu, tanh, logistic, identity) | network | to rounding |
//!
//! each optionally behind `StandardScaler`/`MinMaxScaler` steps of a `Pipeline`. scikit-learn's
//! trees cast inputs to float32 and send a sample left when `float32(x) <= threshold`
//! (`sklearn/tree/_tree.pyx`, `apply_dense`); the splits are restated on the raw input through
//! the scalers and that cast ([`crate::trees`]).

use crate::scaler::{fold, Scaler};
use crate::trees::{boundary, ArrayTree};
use greybox_model::family::{Family, FittedModel};
use greybox_model::matrix::Matrix;
use greybox_model::mlp::{Activation, MlpModel};
use greybox_model::svr::{Kernel, SvrModel};
use greybox_model::tree::TreeEnsemble;
use serde::Deserialize;

pub const SCHEMA: &str = "greybox-sklearn";
pub const SCHEMA_VERSION: u32 = 1;

/// A fitted scikit-learn estimator (optionally a pipeline of scalers and one regressor).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Export {
    pub schema: String,
    pub schema_version: u32,
    /// scikit-learn's version.
    pub library_version: String,
    /// What it was, e.g. `Pipeline(StandardScaler, SVR)`.
    pub estimator: String,
    pub n_features: usize,
    /// `feature_names_in_`, when the model was fitted on a DataFrame.
    #[serde(default)]
    pub feature_names: Option<Vec<String>>,
    #[serde(default)]
    pub scalers: Vec<Scaler>,
    pub model: Regressor,
}

/// One tree's `tree_` arrays (regression: one value per node).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tree {
    pub children_left: Vec<i64>,
    pub children_right: Vec<i64>,
    pub feature: Vec<i64>,
    pub threshold: Vec<f64>,
    pub value: Vec<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Regressor {
    /// Random forest or extra trees: the mean of the trees.
    Forest { trees: Vec<Tree> },
    /// Gradient boosting: `init` (the constant initial prediction) + Σ learning_rate · tree.
    GradientBoosting {
        init: f64,
        learning_rate: f64,
        trees: Vec<Tree>,
    },
    /// Histogram gradient boosting: `init` (the baseline prediction) + Σ tree, leaf values
    /// already scaled by the learning rate, splits `x <= threshold` on the float64 input.
    HistGradientBoosting { init: f64, trees: Vec<Tree> },
    /// ε-SVR: Σ dual_coef_i K(sv_i, x) + intercept.
    Svr {
        kernel: String,
        gamma: f64,
        degree: u32,
        coef0: f64,
        support_vectors: Vec<Vec<f64>>,
        dual_coef: Vec<f64>,
        intercept: f64,
    },
    /// Multi-layer perceptron, identity output: `coefs[k]` is n_in × n_out, row-major rows.
    Mlp {
        activation: String,
        coefs: Vec<Vec<Vec<f64>>>,
        intercepts: Vec<Vec<f64>>,
    },
}

/// The greybox model and family of an exported estimator. Errors say what is wrong, naming
/// the tree, step or array.
pub fn convert(e: &Export) -> Result<(FittedModel, Family), String> {
    if e.schema != SCHEMA || e.schema_version != SCHEMA_VERSION {
        return Err(format!(
            "schema {} version {}: this greybox reads {SCHEMA} version {SCHEMA_VERSION}",
            e.schema, e.schema_version
        ));
    }
    let n = e.n_features;
    if n == 0 {
        return Err("n_features is 0".into());
    }
    for s in &e.scalers {
        s.check(n)?;
    }
    match &e.model {
        Regressor::Forest { trees } => {
            if trees.is_empty() {
                return Err("the forest has no trees".into());
            }
            let ens = ensemble(e, trees, 0.0, 1.0 / trees.len() as f64, 1.0, true)?;
            Ok((FittedModel::TreeEnsemble(ens), Family::RandomForest))
        }
        Regressor::GradientBoosting {
            init,
            learning_rate,
            trees,
        } => {
            if !(init.is_finite() && learning_rate.is_finite()) {
                return Err(format!("init {init}, learning rate {learning_rate}"));
            }
            let ens = ensemble(e, trees, *init, 1.0, *learning_rate, true)?;
            Ok((FittedModel::TreeEnsemble(ens), Family::GradientBoosting))
        }
        Regressor::HistGradientBoosting { init, trees } => {
            if !init.is_finite() {
                return Err(format!("baseline prediction {init}"));
            }
            let ens = ensemble(e, trees, *init, 1.0, 1.0, false)?;
            Ok((FittedModel::TreeEnsemble(ens), Family::GradientBoosting))
        }
        Regressor::Svr { .. } => Ok((FittedModel::Svr(svr(e)?), Family::Svr)),
        Regressor::Mlp { .. } => Ok((FittedModel::Mlp(mlp(e)?), Family::Mlp)),
    }
}

/// Trees with splits restated on the raw input: left ⟺ float32(scalers(x)) <= t, or
/// scalers(x) <= t without the float32 cast (`float32` false: histogram boosting, which
/// compares its float64 input).
fn ensemble(
    e: &Export,
    trees: &[Tree],
    base: f64,
    scale: f64,
    leaf_factor: f64,
    float32: bool,
) -> Result<TreeEnsemble, String> {
    let mut ens = TreeEnsemble::new(e.n_features, base, scale);
    let split = |f: usize, t: f64| {
        boundary(|x| {
            let z = e.scalers.iter().fold(x, |z, s| s.apply(f, z));
            let z = if float32 { (z as f32) as f64 } else { z };
            z <= t
        })
    };
    for (k, t) in trees.iter().enumerate() {
        // scikit-learn's boosting adds learning_rate · value per tree: the same product here.
        let value: Vec<f64> = t.value.iter().map(|v| leaf_factor * v).collect();
        let tree = ArrayTree {
            left: &t.children_left,
            right: &t.children_right,
            feature: &t.feature,
            threshold: &t.threshold,
            value: &value,
        };
        let nodes = tree.flatten(e.n_features, &format!("tree {k}"), &split)?;
        ens.push_tree(nodes, 0);
    }
    Ok(ens)
}

fn standardizer(e: &Export, what: &str) -> Result<greybox_model::matrix::Standardizer, String> {
    fold(&e.scalers, e.n_features).ok_or_else(|| {
        format!("a clipping MinMaxScaler in front of {what} is not supported (not an affine map)")
    })
}

fn svr(e: &Export) -> Result<SvrModel, String> {
    let Regressor::Svr {
        kernel,
        gamma,
        degree,
        coef0,
        support_vectors,
        dual_coef,
        intercept,
    } = &e.model
    else {
        unreachable!("called for SVR only")
    };
    let kernel = match kernel.as_str() {
        "linear" => Kernel::Linear,
        "poly" => Kernel::Poly,
        "rbf" => Kernel::Rbf,
        "sigmoid" => Kernel::Sigmoid,
        k => {
            return Err(format!(
                "SVR kernel '{k}' (supported: linear, poly, rbf, sigmoid)"
            ))
        }
    };
    if let Some(i) = support_vectors.iter().position(|r| r.len() != e.n_features) {
        return Err(format!(
            "support vector {i} has {} values for {} features",
            support_vectors[i].len(),
            e.n_features
        ));
    }
    Ok(SvrModel {
        scaler: standardizer(e, "an SVR")?,
        kernel,
        gamma: *gamma,
        degree: *degree,
        coef0: *coef0,
        support: Matrix {
            n_rows: support_vectors.len(),
            n_cols: e.n_features,
            data: support_vectors.concat(),
        },
        coef: dual_coef.clone(),
        rho: -intercept,
        iterations: 0,
    })
}

fn mlp(e: &Export) -> Result<MlpModel, String> {
    let Regressor::Mlp {
        activation,
        coefs,
        intercepts,
    } = &e.model
    else {
        unreachable!("called for MLP only")
    };
    let activation = match activation.as_str() {
        "relu" => Activation::Relu,
        "tanh" => Activation::Tanh,
        "logistic" => Activation::Logistic,
        "identity" => Activation::Identity,
        a => {
            return Err(format!(
                "MLP activation '{a}' (supported: relu, tanh, logistic, identity)"
            ))
        }
    };
    let mut sizes = vec![e.n_features];
    let mut weights = Vec::new();
    for (k, layer) in coefs.iter().enumerate() {
        let n_out = layer.first().map_or(0, |r| r.len());
        if layer.len() != *sizes.last().unwrap_or(&0) || layer.iter().any(|r| r.len() != n_out) {
            return Err(format!(
                "coefs[{k}] is not a {} × n matrix",
                sizes.last().unwrap_or(&0)
            ));
        }
        sizes.push(n_out);
        weights.push(layer.concat());
    }
    Ok(MlpModel {
        scaler: standardizer(e, "an MLP")?,
        y_mean: 0.0,
        y_scale: 1.0,
        activation,
        sizes,
        weights,
        biases: intercepts.clone(),
        epochs: 0,
        best_epoch: 0,
    })
}
