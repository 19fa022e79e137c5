//! XGBoost boosters saved with `Booster.save_model` as JSON (`.json`) or UBJSON (`.ubj`),
//! following XGBoost's model schema (`doc/model.schema` in the XGBoost repository).
//!
//! XGBoost's CPU predictor reads features as float32, sends a row left when
//! `float32(x) < split_condition` (missing values: `default_left`), and adds each tree's
//! float32 leaf value to a float32 margin that starts at `base_score`, tree by tree. The
//! import restates every split on the raw f64 input ([`crate::trees`]) and keeps the float32
//! accumulation ([`Accumulation::F32`]), so predictions agree with `Booster.predict` bit for
//! bit. Supported: `gbtree` boosters with numerical splits, one target, objectives whose
//! prediction is the margin itself (squared, absolute, pseudo-Huber, squared-log error).

use crate::trees::{boundary, ArrayTree};
use greybox_model::tree::{Accumulation, Node, TreeEnsemble};
use serde_json::Value;

/// Objectives whose prediction is the raw margin (no link function).
const IDENTITY_OBJECTIVES: [&str; 4] = [
    "reg:squarederror",
    "reg:absoluteerror",
    "reg:pseudohubererror",
    "reg:squaredlogerror",
];

/// The imported booster.
pub struct Booster {
    pub ensemble: TreeEnsemble,
    /// XGBoost's version, e.g. "3.2.0".
    pub version: String,
    pub objective: String,
    /// The booster's `feature_names`, when it was trained with them.
    pub feature_names: Option<Vec<String>>,
}

fn get<'a>(v: &'a Value, path: &[&str]) -> Result<&'a Value, String> {
    path.iter().try_fold(v, |v, k| {
        v.get(k)
            .ok_or_else(|| format!("field '{}' is missing", path.join(".")))
    })
}

fn text<'a>(v: &'a Value, path: &[&str]) -> Result<&'a str, String> {
    get(v, path)?
        .as_str()
        .ok_or_else(|| format!("field '{}' is not a string", path.join(".")))
}

/// A number XGBoost writes as a string: "0.5", "[5E-1]" (one-element vector, version ≥ 2).
fn number_string(v: &Value, path: &[&str]) -> Result<f64, String> {
    let s = text(v, path)?;
    s.trim_matches(|c| c == '[' || c == ']')
        .parse::<f64>()
        .map_err(|_| format!("field '{}' is '{s}', not one number", path.join(".")))
}

fn numbers<T>(
    tree: &Value,
    key: &str,
    k: usize,
    conv: impl Fn(&Value) -> Option<T>,
) -> Result<Vec<T>, String> {
    tree.get(key)
        .and_then(|a| a.as_array())
        .ok_or_else(|| format!("tree {k}: '{key}' is missing or not an array"))?
        .iter()
        .enumerate()
        .map(|(i, x)| {
            conv(x).ok_or_else(|| {
                format!("tree {k}: {key}[{i}] is {x}, not a number of the expected kind")
            })
        })
        .collect()
}

/// Read a booster from its JSON document (parsed from `.json` or `.ubj`).
pub fn convert(doc: &Value) -> Result<Booster, String> {
    let learner = get(doc, &["learner"])?;
    let version = get(doc, &["version"])
        .ok()
        .and_then(|v| v.as_array())
        .map(|v| {
            v.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(".")
        })
        .unwrap_or_else(|| "unknown".into());
    let objective = supported_objective(learner)?;
    let (n_features, base) = model_params(learner)?;
    let trees = get(learner, &["gradient_booster", "model", "trees"])?
        .as_array()
        .ok_or("gradient_booster.model.trees is not an array")?;
    if trees.is_empty() {
        return Err("the booster has no trees".into());
    }
    let mut ensemble = TreeEnsemble::new(n_features, base as f64, 1.0);
    ensemble.accumulation = Accumulation::F32;
    for (k, tree) in trees.iter().enumerate() {
        ensemble.push_tree(tree_nodes(tree, k, n_features)?, 0);
    }
    let feature_names = learner
        .get("feature_names")
        .and_then(|v| v.as_array())
        .filter(|v| !v.is_empty())
        .map(|v| {
            v.iter()
                .filter_map(|s| s.as_str().map(str::to_string))
                .collect()
        });
    Ok(Booster {
        ensemble,
        version,
        objective,
        feature_names,
    })
}

/// The learner's objective, if it predicts the margin itself, with a `gbtree` booster.
fn supported_objective(learner: &Value) -> Result<String, String> {
    let objective = text(learner, &["objective", "name"])?.to_string();
    if !IDENTITY_OBJECTIVES.contains(&objective.as_str()) {
        return Err(format!(
            "objective '{objective}': only objectives predicting the margin itself are supported ({})",
            IDENTITY_OBJECTIVES.join(", ")
        ));
    }
    let booster = text(learner, &["gradient_booster", "name"])?;
    if booster != "gbtree" {
        return Err(format!(
            "booster '{booster}': only 'gbtree' is supported (dart and gblinear are not)"
        ));
    }
    Ok(objective)
}

/// The number of features and the base score of a single-output regression model.
fn model_params(learner: &Value) -> Result<(usize, f32), String> {
    let param = get(learner, &["learner_model_param"])?;
    for (key, ok) in [("num_class", "0"), ("num_target", "1")] {
        if let Ok(v) = text(param, &[key]) {
            if v != ok && !(key == "num_class" && v == "1") {
                return Err(format!(
                    "{key} = {v}: only single-output regression is supported"
                ));
            }
        }
    }
    let n_features: usize = text(param, &["num_feature"])?
        .parse()
        .map_err(|_| "learner_model_param.num_feature is not a count".to_string())?;
    if n_features == 0 {
        return Err("num_feature is 0".into());
    }
    let base = number_string(param, &["base_score"])? as f32;
    Ok((n_features, base))
}

/// Tree `k` as greybox nodes (numerical splits and scalar leaves only).
fn tree_nodes(tree: &Value, k: usize, n_features: usize) -> Result<Vec<Node>, String> {
    // left ⟺ float32(x) < s: restated as x <= boundary on the f64 input.
    let split = |_f: usize, s: f64| {
        let s = s as f32;
        boundary(|x| (x as f32) < s)
    };
    let int = |x: &Value| x.as_i64();
    let float = |x: &Value| x.as_f64().map(|v| v as f32 as f64);
    let left = numbers(tree, "left_children", k, int)?;
    let right = numbers(tree, "right_children", k, int)?;
    let feature = numbers(tree, "split_indices", k, int)?;
    let cond = numbers(tree, "split_conditions", k, float)?;
    if let Ok(types) = numbers(tree, "split_type", k, int) {
        if let Some(i) = types.iter().position(|t| *t != 0) {
            return Err(format!(
                "tree {k}: node {i} is a categorical split (not supported)"
            ));
        }
    }
    if let Some(size) = tree.pointer("/tree_param/size_leaf_vector") {
        if !matches!(size.as_str(), Some("1") | Some("0")) {
            return Err(format!(
                "tree {k}: vector leaves (size_leaf_vector {size}) are not supported"
            ));
        }
    }
    // A leaf's value is its split_condition.
    let arrays = ArrayTree {
        left: &left,
        right: &right,
        feature: &feature,
        threshold: &cond,
        value: &cond,
    };
    arrays.flatten(n_features, &format!("tree {k}"), &split)
}
