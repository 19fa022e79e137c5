//! Structural checks of fitted models read from files.
//!
//! A model file can be well-formed JSON with a valid content hash and still describe a model
//! that cannot be evaluated: a tree child or feature index out of range, a cycle among tree
//! nodes (evaluation would never return), layer sizes that do not match the weights, NaN
//! weights. [`check_model`] finds all of that when the file is read, so that evaluation
//! (`predict`, a law in the cutting simulation, the C ABI inside an FE solver) can never
//! index out of bounds, loop, or answer NaN from a corrupted file.

use crate::family::FittedModel;
use crate::matrix::{Matrix, Standardizer};
use crate::mlp::{MlpModel, MAX_WIDTH};
use crate::svr::{SvrModel, MAX_FEATURES};
use crate::tree::{TreeEnsemble, LEAF};

/// What is wrong, and where in the model (a JSON path below `model`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StructureError {
    pub field: String,
    pub message: String,
}

type Check = Result<(), StructureError>;

fn fail(field: impl Into<String>, message: impl Into<String>) -> Check {
    Err(StructureError {
        field: field.into(),
        message: message.into(),
    })
}

fn finite(field: &str, values: &[f64]) -> Check {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => fail(
            format!("{field}[{i}]"),
            format!("{} is not a finite number", values[i]),
        ),
        None => Ok(()),
    }
}

/// The model as a whole, for inputs of `n_features` features.
pub fn check_model(m: &FittedModel, n_features: usize) -> Check {
    match m {
        FittedModel::TreeEnsemble(t) => check_trees(t, n_features),
        FittedModel::Svr(s) => check_svr(s, n_features),
        FittedModel::Mlp(n) => check_mlp(n, n_features),
    }
}

fn check_scaler(field: &str, s: &Standardizer, n_features: usize) -> Check {
    if s.mean.len() != n_features || s.scale.len() != n_features {
        return fail(
            field,
            format!(
                "{} means and {} scales for {n_features} features",
                s.mean.len(),
                s.scale.len()
            ),
        );
    }
    finite(&format!("{field}.mean"), &s.mean)?;
    finite(&format!("{field}.scale"), &s.scale)?;
    match s.scale.iter().position(|v| !(*v > 0.0)) {
        Some(i) => fail(
            format!("{field}.scale[{i}]"),
            format!("{} is not a positive scale", s.scale[i]),
        ),
        None => Ok(()),
    }
}

/// Trees: every root and child inside the node array, every split feature an input, and
/// every child after its parent (so every path ends: no cycle, no self-reference).
pub fn check_trees(t: &TreeEnsemble, n_features: usize) -> Check {
    if t.n_features != n_features {
        return fail(
            "n_features",
            format!("{} but the file lists {n_features} features", t.n_features),
        );
    }
    finite("base", &[t.base])?;
    finite("scale", &[t.scale])?;
    if t.accumulation == crate::tree::Accumulation::F32 && t.scale != 1.0 {
        return fail(
            "scale",
            format!("{} with float32 accumulation (must be 1)", t.scale),
        );
    }
    let n = t.nodes.len();
    if t.roots.is_empty() {
        return fail("roots", "no trees");
    }
    for (k, r) in t.roots.iter().enumerate() {
        if *r as usize >= n {
            return fail(
                format!("roots[{k}]"),
                format!("node {r} does not exist ({n} nodes)"),
            );
        }
    }
    for (i, node) in t.nodes.iter().enumerate() {
        let field = |what: &str| format!("nodes[{i}].{what}");
        if !node.value.is_finite() {
            return fail(
                field("value"),
                format!("{} is not a finite number", node.value),
            );
        }
        if node.feature == LEAF {
            continue;
        }
        if node.feature as usize >= n_features {
            return fail(
                field("feature"),
                format!(
                    "split on feature {} but the model has {n_features} features",
                    node.feature
                ),
            );
        }
        let left = node.left as usize;
        if left <= i {
            return fail(
                field("left"),
                format!("child {left} does not come after its parent {i}: the tree would loop"),
            );
        }
        if left + 1 >= n {
            return fail(
                field("left"),
                format!("children {left} and {} do not exist ({n} nodes)", left + 1),
            );
        }
    }
    Ok(())
}

/// SVR: support vectors of the input width, one coefficient each, finite numbers.
pub fn check_svr(s: &SvrModel, n_features: usize) -> Check {
    if n_features > MAX_FEATURES {
        return fail(
            "support",
            format!("{n_features} features; SVR models take at most {MAX_FEATURES}"),
        );
    }
    check_scaler("scaler", &s.scaler, n_features)?;
    check_matrix("support", &s.support, n_features)?;
    if s.coef.len() != s.support.n_rows {
        return fail(
            "coef",
            format!(
                "{} coefficients for {} support vectors",
                s.coef.len(),
                s.support.n_rows
            ),
        );
    }
    finite("coef", &s.coef)?;
    finite("support.data", &s.support.data)?;
    finite("rho", &[s.rho])?;
    finite("gamma", &[s.gamma])?;
    finite("coef0", &[s.coef0])?;
    if s.degree > 10 {
        return fail("degree", format!("{} (at most 10)", s.degree));
    }
    Ok(())
}

fn check_matrix(field: &str, m: &Matrix, n_cols: usize) -> Check {
    if m.n_cols != n_cols {
        return fail(
            format!("{field}.n_cols"),
            format!("{} but the model has {n_cols} features", m.n_cols),
        );
    }
    if m.data.len() != m.n_rows.saturating_mul(m.n_cols) {
        return fail(
            format!("{field}.data"),
            format!("{} values for {} × {}", m.data.len(), m.n_rows, m.n_cols),
        );
    }
    Ok(())
}

/// MLP: layer sizes from the inputs to one output, each weight matrix and bias vector of
/// its layer's size, finite numbers.
pub fn check_mlp(m: &MlpModel, n_features: usize) -> Check {
    let s = &m.sizes;
    if s.len() < 2 || s[0] != n_features || s[s.len() - 1] != 1 {
        return fail(
            "sizes",
            format!("{s:?}: expected {n_features} inputs first and 1 output last"),
        );
    }
    if let Some(k) = s.iter().position(|w| *w == 0 || *w > MAX_WIDTH) {
        return fail(
            format!("sizes[{k}]"),
            format!("{} (a layer has 1..{MAX_WIDTH} units)", s[k]),
        );
    }
    let layers = s.len() - 1;
    if m.weights.len() != layers || m.biases.len() != layers {
        return fail(
            "weights",
            format!(
                "{} weight and {} bias arrays for {layers} layers",
                m.weights.len(),
                m.biases.len()
            ),
        );
    }
    for k in 0..layers {
        if m.weights[k].len() != s[k] * s[k + 1] {
            return fail(
                format!("weights[{k}]"),
                format!(
                    "{} values for a {} × {} layer",
                    m.weights[k].len(),
                    s[k],
                    s[k + 1]
                ),
            );
        }
        if m.biases[k].len() != s[k + 1] {
            return fail(
                format!("biases[{k}]"),
                format!("{} values for {} units", m.biases[k].len(), s[k + 1]),
            );
        }
        finite(&format!("weights[{k}]"), &m.weights[k])?;
        finite(&format!("biases[{k}]"), &m.biases[k])?;
    }
    finite("y_mean", &[m.y_mean])?;
    finite("y_scale", &[m.y_scale])?;
    check_scaler("scaler", &m.scaler, n_features)
}
