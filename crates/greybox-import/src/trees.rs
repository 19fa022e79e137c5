//! Trees stored as parallel node arrays (scikit-learn's `tree_`, XGBoost's JSON), rebuilt as
//! greybox's flat trees with every split restated as an exact f64 boundary on the raw input.
//!
//! A source tree sends `x` left when `cmp(g(x[f]), t)` holds, where `g` is the library's
//! input path (a scaler, a cast to float32) and `cmp` its comparison (`<=` in scikit-learn,
//! `<` in XGBoost). Both are monotone, so the set of raw x going left is `x <= b` for one f64
//! `b` ([`greybox_core::boundary::last_true`]), which is what a greybox node stores: the
//! rebuilt tree sends every f64 input the way the source does, bit for bit.

use greybox_core::boundary::last_true;
use greybox_model::tree::{Node, LEAF};

/// One tree as parallel arrays; `left[i] < 0` marks a leaf.
pub struct ArrayTree<'a> {
    pub left: &'a [i64],
    pub right: &'a [i64],
    pub feature: &'a [i64],
    /// The split thresholds in the source's space (leaves: ignored).
    pub threshold: &'a [f64],
    /// The leaf values (splits: ignored).
    pub value: &'a [f64],
}

/// Clamp a boundary into the finite range a model file stores: −∞ (nothing goes left) and +∞
/// (everything goes left) differ from ∓f64::MAX only at ±f64::MAX itself.
fn finite(b: Option<f64>) -> f64 {
    b.unwrap_or(f64::NEG_INFINITY).clamp(f64::MIN, f64::MAX)
}

/// The raw-input boundary of a split: the largest x with `goes_left(x)`.
pub fn boundary(goes_left: impl Fn(f64) -> bool) -> f64 {
    finite(last_true(goes_left))
}

impl ArrayTree<'_> {
    /// The flat nodes (children adjacent, after their parent) and the root index. `split`
    /// maps (feature, source threshold) to the raw-input boundary. `what` names the tree in
    /// errors: sizes that disagree, a child index out of range, a feature out of range, a
    /// node reached twice (a cycle or a shared subtree).
    pub fn flatten(
        &self,
        n_features: usize,
        what: &str,
        split: &dyn Fn(usize, f64) -> f64,
    ) -> Result<Vec<Node>, String> {
        let n = self.left.len();
        if n == 0 {
            return Err(format!("{what}: no nodes"));
        }
        for (name, len) in [
            ("right children", self.right.len()),
            ("features", self.feature.len()),
            ("thresholds", self.threshold.len()),
            ("values", self.value.len()),
        ] {
            if len != n {
                return Err(format!("{what}: {len} {name} for {n} nodes"));
            }
        }
        let mut seen = vec![false; n];
        let mut nodes = vec![Node {
            value: 0.0,
            feature: LEAF,
            left: 0,
        }];
        let mut stack = vec![(0usize, 0usize)]; // (source node, flat slot)
        while let Some((src, slot)) = stack.pop() {
            if std::mem::replace(&mut seen[src], true) {
                return Err(format!("{what}: node {src} is reached twice"));
            }
            if self.left[src] < 0 {
                let v = self.value[src];
                if !v.is_finite() {
                    return Err(format!("{what}: leaf {src} has value {v}"));
                }
                nodes[slot] = Node {
                    value: v,
                    feature: LEAF,
                    left: 0,
                };
                continue;
            }
            let child = |c: i64| {
                usize::try_from(c)
                    .ok()
                    .filter(|c| *c < n)
                    .ok_or_else(|| format!("{what}: node {src} has child {c} ({n} nodes)"))
            };
            let (l, r) = (child(self.left[src])?, child(self.right[src])?);
            let f = usize::try_from(self.feature[src])
                .ok()
                .filter(|f| *f < n_features)
                .ok_or_else(|| {
                    format!(
                        "{what}: node {src} splits on feature {} ({n_features} features)",
                        self.feature[src]
                    )
                })?;
            let t = self.threshold[src];
            if t.is_nan() {
                return Err(format!("{what}: node {src} has threshold NaN"));
            }
            let first = nodes.len();
            nodes[slot] = Node {
                value: split(f, t),
                feature: f as u32,
                left: first as u32,
            };
            nodes.extend([nodes[slot]; 2]);
            stack.push((r, first + 1));
            stack.push((l, first));
        }
        Ok(nodes)
    }
}
