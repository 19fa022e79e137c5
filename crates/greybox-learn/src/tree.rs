//! Regression trees, grown greedily on first- and second-order statistics, stored flat.
//!
//! One builder serves both ensembles. A node's statistics are G = Σ g and H = Σ h over its
//! rows; a split's score is G_L²/(H_L+λ) + G_R²/(H_R+λ) − G²/(H+λ) and a leaf's value is
//! −G/(H+λ) (Chen & Guestrin, "XGBoost", KDD 2016, eqs. 5–7).
//! * Random forest (CART, Breiman 2001): g = −y, h = 1, λ = 0 — the score is the reduction
//!   of the squared error and the leaf value is the mean of y.
//! * Gradient boosting, squared loss: g = ŷ − y, h = 1, λ = L2 leaf regularisation.
//!
//! Split thresholds lie midway between consecutive distinct values; a row goes left when
//! `x[f] <= threshold`. Trees are stored as flat arrays of 16-byte nodes whose two children
//! are adjacent (right = left + 1), so prediction is a short branch-free walk with no
//! allocation.
//!
//! The builder keeps, per feature, the node's rows sorted by that feature as [`Entry`]s that
//! carry the feature value and the row's g and h, so the split scan reads memory in order;
//! only the partition after a split looks a row up (one byte per row).

use greybox_model::tree::{Node, LEAF};
use greybox_model::Matrix;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// Growth limits.
#[derive(Debug, Clone, Copy)]
pub struct GrowParams {
    pub max_depth: Option<usize>,
    pub min_samples_leaf: usize,
    pub min_child_weight: f64,
    pub lambda: f64,
    /// A split must improve the score by more than this.
    pub min_split_gain: f64,
    /// Features tried per split (`None`: all).
    pub max_features: Option<usize>,
    /// Multiplies leaf values (the learning rate).
    pub leaf_scale: f64,
}

/// One row in a feature's sorted list: its value of that feature and its statistics.
#[derive(Debug, Clone, Copy)]
struct Entry {
    x: f64,
    g: f64,
    h: f64,
    row: u32,
}

struct Builder<'a> {
    n_cols: usize,
    p: GrowParams,
    rng: &'a mut ChaCha8Rng,
    nodes: &'a mut Vec<Node>,
    features: Vec<usize>,
    /// Per feature, the node's rows sorted by that feature; a node owns the range
    /// `start..end` of every list (presorting, as in exact greedy split finding).
    order: Vec<Vec<Entry>>,
    scratch: Vec<Entry>,
    /// Per row, whether it goes left at the split being applied.
    goes_left: Vec<bool>,
    /// Every leaf as (node, start, end): its rows are `order[f][start..end]` for any f.
    leaves: Vec<(u32, usize, usize)>,
}

/// A grown tree's leaves with the training rows that fell into each (repeated as often as
/// the sample held them).
pub struct LeafRows {
    /// The rows, leaf after leaf.
    rows: Vec<u32>,
    /// (node index, range of `rows`) per leaf.
    leaves: Vec<(u32, usize, usize)>,
}

impl LeafRows {
    /// (leaf node index, its rows) per leaf.
    pub fn iter(&self) -> impl Iterator<Item = (u32, &[u32])> {
        self.leaves
            .iter()
            .map(|&(node, start, end)| (node, &self.rows[start..end]))
    }
}

/// Per feature, `rows` sorted by that feature (stable: ties keep their order).
pub fn presort(x: &Matrix, rows: &[usize]) -> Vec<Vec<usize>> {
    (0..x.n_cols)
        .map(|f| {
            let mut o = rows.to_vec();
            o.sort_by(|&a, &b| x.get(a, f).total_cmp(&x.get(b, f)));
            o
        })
        .collect()
}

/// Grow one tree over `rows` (repetitions allowed: bootstrap samples) and append its nodes;
/// returns the root's index.
pub fn grow(
    x: &Matrix,
    g: &[f64],
    h: &[f64],
    rows: &[usize],
    p: GrowParams,
    rng: &mut ChaCha8Rng,
    nodes: &mut Vec<Node>,
) -> u32 {
    grow_with_leaves(x, g, h, &presort(x, rows), p, rng, nodes).0
}

/// [`grow`] from rows already sorted per feature ([`presort`]; boosting sorts its rows once
/// for all its trees), also returning which rows ended in which leaf.
pub fn grow_with_leaves(
    x: &Matrix,
    g: &[f64],
    h: &[f64],
    order: &[Vec<usize>],
    p: GrowParams,
    rng: &mut ChaCha8Rng,
    nodes: &mut Vec<Node>,
) -> (u32, LeafRows) {
    let root = nodes.len() as u32;
    let mut b = builder(x, g, h, order, p, rng, nodes);
    b.build(0, order.first().map_or(0, |o| o.len()), 0, root);
    let rows = b.order.swap_remove(0).iter().map(|e| e.row).collect();
    (
        root,
        LeafRows {
            rows,
            leaves: b.leaves,
        },
    )
}

/// A builder over the rows `order` (sorted per feature), with the root node pushed.
fn builder<'a>(
    x: &Matrix,
    g: &[f64],
    h: &[f64],
    order: &[Vec<usize>],
    p: GrowParams,
    rng: &'a mut ChaCha8Rng,
    nodes: &'a mut Vec<Node>,
) -> Builder<'a> {
    nodes.push(Node {
        value: 0.0,
        feature: LEAF,
        left: 0,
    });
    let order: Vec<Vec<Entry>> = order
        .iter()
        .enumerate()
        .map(|(f, rows)| {
            rows.iter()
                .map(|&r| Entry {
                    x: x.get(r, f),
                    g: g[r],
                    h: h[r],
                    row: r as u32,
                })
                .collect()
        })
        .collect();
    Builder {
        n_cols: x.n_cols,
        p,
        rng,
        nodes,
        features: (0..x.n_cols).collect(),
        scratch: Vec::with_capacity(order.first().map_or(0, |o| o.len())),
        order,
        goes_left: vec![false; x.n_rows],
        leaves: Vec::new(),
    }
}

impl Builder<'_> {
    fn leaf_value(&self, gs: f64, hs: f64) -> f64 {
        -gs / (hs + self.p.lambda) * self.p.leaf_scale
    }

    /// Grow the subtree of rows `start..end` into the already allocated node `me`.
    fn build(&mut self, start: usize, end: usize, depth: usize, me: u32) {
        let n = end - start;
        let (gs, hs) = self.order[0][start..end]
            .iter()
            .fold((0.0, 0.0), |(a, b), e| (a + e.g, b + e.h));
        self.nodes[me as usize] = Node {
            value: self.leaf_value(gs, hs),
            feature: LEAF,
            left: 0,
        };
        let p = self.p;
        if p.max_depth.is_some_and(|d| depth >= d)
            || n < 2 * p.min_samples_leaf.max(1)
            || hs < 2.0 * p.min_child_weight
        {
            self.leaves.push((me, start, end));
            return;
        }
        let Some((f, thr)) = self.best_split(start, end, gs, hs) else {
            self.leaves.push((me, start, end));
            return;
        };
        let n_left = self.partition(start, end, f, thr);
        let left = self.nodes.len() as u32;
        self.nodes.push(Node {
            value: 0.0,
            feature: LEAF,
            left: 0,
        });
        self.nodes.push(Node {
            value: 0.0,
            feature: LEAF,
            left: 0,
        });
        self.nodes[me as usize] = Node {
            value: thr,
            feature: f as u32,
            left,
        };
        self.build(start, start + n_left, depth + 1, left);
        self.build(start + n_left, end, depth + 1, left + 1);
    }

    /// The best split (feature, threshold) of the rows `start..end`, whose sums are `gs`, `hs`,
    /// if it improves the score by more than `min_split_gain`.
    fn best_split(&mut self, start: usize, end: usize, gs: f64, hs: f64) -> Option<(usize, f64)> {
        let p = self.p;
        let n = end - start;
        let parent_score = gs * gs / (hs + p.lambda);
        let n_try = p.max_features.unwrap_or(self.n_cols).clamp(1, self.n_cols);
        if n_try < self.n_cols {
            self.features.shuffle(self.rng);
        }
        let mut best: Option<(f64, usize, f64)> = None; // (gain, feature, threshold)
        for fi in 0..n_try {
            let f = self.features[fi];
            let sorted = &self.order[f][start..end];
            let (mut gl, mut hl) = (0.0, 0.0);
            for k in 0..n - 1 {
                let e = &sorted[k];
                gl += e.g;
                hl += e.h;
                let (xv, xn) = (e.x, sorted[k + 1].x);
                if xv >= xn {
                    continue; // not a boundary between distinct values
                }
                if k + 1 < p.min_samples_leaf || n - k - 1 < p.min_samples_leaf {
                    continue;
                }
                let (gr, hr) = (gs - gl, hs - hl);
                if hl < p.min_child_weight || hr < p.min_child_weight {
                    continue;
                }
                let gain = gl * gl / (hl + p.lambda) + gr * gr / (hr + p.lambda) - parent_score;
                if best.is_none_or(|(bg, _, _)| gain > bg) {
                    let mut thr = 0.5 * (xv + xn);
                    if thr >= xn {
                        thr = xv; // midpoint rounded up to the next value
                    }
                    best = Some((gain, f, thr));
                }
            }
        }
        let (gain, f, thr) = best?;
        (gain > p.min_split_gain).then_some((f, thr))
    }

    /// Stable partition of every feature's list over `start..end`: rows with x[f] <= thr
    /// first. Returns how many went left.
    fn partition(&mut self, start: usize, end: usize, f: usize, thr: f64) -> usize {
        for e in &self.order[f][start..end] {
            self.goes_left[e.row as usize] = e.x <= thr;
        }
        // Branch-free: each entry is written to both sides and the side it belongs to
        // advances (whether a row goes left is unpredictable).
        let mut n_left = 0;
        let right = &mut self.scratch;
        right.resize(end - start, self.order[0][start]);
        for list in self.order.iter_mut() {
            let seg = &mut list[start..end];
            let (mut w, mut r) = (0, 0);
            for k in 0..seg.len() {
                let e = seg[k];
                let left = self.goes_left[e.row as usize];
                seg[w] = e; // w <= k: entry k is already read
                right[r] = e;
                w += usize::from(left);
                r += usize::from(!left);
            }
            seg[w..].copy_from_slice(&right[..r]);
            n_left = w;
        }
        n_left
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use greybox_model::tree::walk;
    use rand::{Rng, SeedableRng};

    /// The rows a leaf reports are exactly the rows whose walk ends in it: every training
    /// row once, with ties in the features (a coarse grid) so that thresholds sit between
    /// repeated values.
    #[test]
    fn leaf_rows_are_where_the_rows_walk_to() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 500;
        let data: Vec<f64> = (0..2 * n)
            .map(|_| f64::from(rng.gen_range(0..12u8)) * 0.25)
            .collect();
        let x = Matrix::new(n, 2, data);
        let g: Vec<f64> = (0..n)
            .map(|i| x.get(i, 0) * x.get(i, 1) - 1.0 + 0.01 * (i % 7) as f64)
            .collect();
        let h = vec![1.0; n];
        let p = GrowParams {
            max_depth: Some(6),
            min_samples_leaf: 1,
            min_child_weight: 1.0,
            lambda: 1.0,
            min_split_gain: 1e-6,
            max_features: None,
            leaf_scale: 0.3,
        };
        let mut nodes = Vec::new();
        let order = presort(&x, &(0..n).collect::<Vec<_>>());
        let (root, fell) = grow_with_leaves(&x, &g, &h, &order, p, &mut rng, &mut nodes);
        let mut seen = vec![0; n];
        let mut leaves = 0;
        for (leaf, rows) in fell.iter() {
            leaves += 1;
            assert_eq!(nodes[leaf as usize].feature, LEAF);
            for &r in rows {
                seen[r as usize] += 1;
                let value = walk(&nodes, root, x.row(r as usize));
                assert_eq!(
                    value.to_bits(),
                    nodes[leaf as usize].value.to_bits(),
                    "row {r}"
                );
            }
        }
        assert!(leaves > 8, "{leaves} leaves");
        assert!(seen.iter().all(|&k| k == 1));
    }
}
