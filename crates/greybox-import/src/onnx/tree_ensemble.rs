//! ai.onnx.ml `TreeEnsembleRegressor` as a greybox tree ensemble.
//!
//! A node sends x to its true branch when `z ⋄ t` holds, z being the feature after the
//! graph's scalers and float32 casts (evaluated as the runtime does) and ⋄ the node's mode:
//! `BRANCH_LEQ` (≤), `BRANCH_LT` (<), `BRANCH_GTE` (≥), `BRANCH_GT` (>). Each is restated
//! as an exact boundary on the raw input, the true branch on the left for ≤ and < and on
//! the right for ≥ and > (greybox sends x ≤ b left). Leaf values are the sums of the
//! `target_weights` of the leaf; `SUM` adds `base_values`, `AVERAGE` divides by the number
//! of trees first.

use super::graph::Attributes;
use super::proto::NodeProto;
use super::Elementwise;
use crate::trees::{boundary, ArrayTree};
use greybox_model::family::{Family, FittedModel};
use greybox_model::tree::TreeEnsemble;
use std::collections::{BTreeMap, HashMap};

/// The node arrays of the operator.
struct Nodes {
    tree: Vec<i64>,
    id: Vec<i64>,
    feature: Vec<i64>,
    value: Vec<f64>,
    mode: Vec<String>,
    on_true: Vec<i64>,
    on_false: Vec<i64>,
    /// Σ target weights per (tree, node).
    leaf: HashMap<(i64, i64), f64>,
}

fn read(a: &Attributes) -> Result<Nodes, String> {
    let nodes = Nodes {
        tree: a.ints("nodes_treeids"),
        id: a.ints("nodes_nodeids"),
        feature: a.ints("nodes_featureids"),
        value: a.floats("nodes_values")?,
        mode: a.strings("nodes_modes"),
        on_true: a.ints("nodes_truenodeids"),
        on_false: a.ints("nodes_falsenodeids"),
        leaf: HashMap::new(),
    };
    let n = nodes.tree.len();
    let lengths = [
        nodes.id.len(),
        nodes.feature.len(),
        nodes.value.len(),
        nodes.mode.len(),
        nodes.on_true.len(),
        nodes.on_false.len(),
    ];
    if n == 0 || lengths.iter().any(|l| *l != n) {
        return Err(
            "TreeEnsembleRegressor: the nodes_* attributes are empty or differ in length".into(),
        );
    }
    let (tt, tn, tw) = (
        a.ints("target_treeids"),
        a.ints("target_nodeids"),
        a.floats("target_weights")?,
    );
    if tt.len() != tn.len() || tt.len() != tw.len() {
        return Err("TreeEnsembleRegressor: the target_* attributes differ in length".into());
    }
    let mut nodes = nodes;
    for k in 0..tt.len() {
        *nodes.leaf.entry((tt[k], tn[k])).or_insert(0.0) += tw[k];
    }
    Ok(nodes)
}

/// Whether a node of `mode` sends z left in greybox's sense (the down-set of the split).
fn goes_left(mode: &str, z: f64, t: f64) -> bool {
    match mode {
        "BRANCH_LEQ" => z <= t,
        "BRANCH_LT" => z < t,
        "BRANCH_GTE" => !(z >= t),
        _ => !(z > t),
    }
}

/// The feature after the scalers and casts in front of the operator.
fn preprocess(pre: &[Elementwise], f: usize, x: f64) -> f64 {
    let mut f32 = false;
    pre.iter().fold(x, |z, e| {
        f32 |= matches!(e, Elementwise::ToF32);
        e.apply(f, z, f32)
    })
}

/// The node indices of each tree, trees in increasing id, nodes in file order: one pass over
/// the node arrays (a graph of many trees imports in time linear in its size).
fn nodes_by_tree(nodes: &Nodes) -> BTreeMap<i64, Vec<usize>> {
    let mut by_tree: BTreeMap<i64, Vec<usize>> = BTreeMap::new();
    for (k, t) in nodes.tree.iter().enumerate() {
        by_tree.entry(*t).or_default().push(k);
    }
    by_tree
}

/// One tree's arrays in greybox's left/right convention with exact raw-input boundaries;
/// `idx` are the tree's node indices.
fn tree(
    nodes: &Nodes,
    (t, idx): (i64, &[usize]),
    pre: &[Elementwise],
    float_input: bool,
    n_features: usize,
) -> Result<Vec<greybox_model::tree::Node>, String> {
    let pos: HashMap<i64, usize> = idx
        .iter()
        .enumerate()
        .map(|(p, &k)| (nodes.id[k], p))
        .collect();
    if pos.get(&0) != Some(&0) {
        return Err(format!("tree {t}: node 0 must come first"));
    }
    let (mut left, mut right, mut feature, mut threshold, mut value) =
        (vec![], vec![], vec![], vec![], vec![]);
    for &k in idx {
        let child = |id: i64| {
            pos.get(&id).map(|p| *p as i64).ok_or_else(|| {
                format!("tree {t}: node {} points to missing node {id}", nodes.id[k])
            })
        };
        value.push(nodes.leaf.get(&(t, nodes.id[k])).copied().unwrap_or(0.0));
        let mode = nodes.mode[k].as_str();
        if mode == "LEAF" {
            left.push(-1);
            right.push(-1);
            feature.push(0);
            threshold.push(0.0);
            continue;
        }
        let (on_true, on_false) = (child(nodes.on_true[k])?, child(nodes.on_false[k])?);
        let (l, r) = match mode {
            "BRANCH_LEQ" | "BRANCH_LT" => (on_true, on_false),
            "BRANCH_GTE" | "BRANCH_GT" => (on_false, on_true),
            m => {
                return Err(format!(
                    "tree {t}: split mode {m} is not supported (not an order split)"
                ))
            }
        };
        let f = usize::try_from(nodes.feature[k])
            .map_err(|_| format!("tree {t}: feature {}", nodes.feature[k]))?;
        let v = if float_input {
            nodes.value[k] as f32 as f64
        } else {
            nodes.value[k]
        };
        left.push(l);
        right.push(r);
        feature.push(f as i64);
        threshold.push(boundary(|x| goes_left(mode, preprocess(pre, f, x), v)));
    }
    let arrays = ArrayTree {
        left: &left,
        right: &right,
        feature: &feature,
        threshold: &threshold,
        value: &value,
    };
    arrays.flatten(n_features, &format!("tree {t}"), &|_, b| b)
}

/// The operator as a tree ensemble behind the scalers `pre`.
pub fn convert(
    node: &NodeProto,
    pre: &[Elementwise],
) -> Result<(FittedModel, Family, usize), String> {
    let a = Attributes::of(node);
    if a.int("n_targets", 1) != 1 {
        return Err("TreeEnsembleRegressor with several targets is not supported".into());
    }
    let post = a.string("post_transform", "NONE");
    if post != "NONE" {
        return Err(format!(
            "TreeEnsembleRegressor post_transform {post} is not supported"
        ));
    }
    let nodes = read(&a)?;
    let n_features = nodes.feature.iter().copied().max().unwrap_or(0).max(0) as usize + 1;
    Elementwise::check_covers(pre, n_features)?;
    let trees = nodes_by_tree(&nodes);
    let base = a.floats("base_values")?.first().copied().unwrap_or(0.0);
    // a sum of trees is boosting; an average of trees is a forest
    let (scale, family) = match a.string("aggregate_function", "SUM").as_str() {
        "SUM" => (1.0, Family::GradientBoosting),
        "AVERAGE" => (1.0 / trees.len() as f64, Family::RandomForest),
        other => {
            return Err(format!(
                "TreeEnsembleRegressor aggregate_function {other} is not supported"
            ))
        }
    };
    let float_input = pre.iter().any(|e| matches!(e, Elementwise::ToF32));
    let mut ens = TreeEnsemble::new(n_features, base, scale);
    for (t, idx) in &trees {
        ens.push_tree(tree(&nodes, (*t, idx), pre, float_input, n_features)?, 0);
    }
    Ok((FittedModel::TreeEnsemble(ens), family, n_features))
}
