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

use crate::Matrix;
pub use greybox_model::tree::{walk, Node, TreeEnsemble, LEAF};
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

struct Builder<'a> {
    x: &'a Matrix,
    g: &'a [f64],
    h: &'a [f64],
    p: GrowParams,
    rng: &'a mut ChaCha8Rng,
    nodes: &'a mut Vec<Node>,
    features: Vec<usize>,
    /// Per feature, the node's rows sorted by that feature; a node owns the range
    /// `start..end` of every list (presorting, as in exact greedy split finding).
    order: Vec<Vec<usize>>,
    scratch: Vec<usize>,
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
    grow_presorted(x, g, h, presort(x, rows), p, rng, nodes)
}

/// [`grow`] from rows already sorted per feature ([`presort`]); boosting sorts its rows once
/// for all its trees.
pub fn grow_presorted(
    x: &Matrix,
    g: &[f64],
    h: &[f64],
    order: Vec<Vec<usize>>,
    p: GrowParams,
    rng: &mut ChaCha8Rng,
    nodes: &mut Vec<Node>,
) -> u32 {
    let n_rows = order.first().map_or(0, |o| o.len());
    let root = nodes.len() as u32;
    nodes.push(Node {
        value: 0.0,
        feature: LEAF,
        left: 0,
    });
    let mut b = Builder {
        x,
        g,
        h,
        p,
        rng,
        nodes,
        features: (0..x.n_cols).collect(),
        order,
        scratch: Vec::with_capacity(n_rows),
    };
    b.build(0, n_rows, 0, root);
    root
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
            .fold((0.0, 0.0), |(a, b), &i| (a + self.g[i], b + self.h[i]));
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
            return;
        }
        let parent_score = gs * gs / (hs + p.lambda);
        let n_try = p
            .max_features
            .unwrap_or(self.x.n_cols)
            .clamp(1, self.x.n_cols);
        if n_try < self.x.n_cols {
            self.features.shuffle(self.rng);
        }
        let mut best: Option<(f64, usize, f64)> = None; // (gain, feature, threshold)
        for fi in 0..n_try {
            let f = self.features[fi];
            let x = self.x;
            let sorted = &self.order[f][start..end];
            let (mut gl, mut hl) = (0.0, 0.0);
            for k in 0..n - 1 {
                let i = sorted[k];
                gl += self.g[i];
                hl += self.h[i];
                let (xv, xn) = (x.get(i, f), x.get(sorted[k + 1], f));
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
        let Some((gain, f, thr)) = best else {
            return;
        };
        if gain <= p.min_split_gain {
            return;
        }
        // stable partition of every feature's list: left = x[f] <= thr
        let mut n_left = 0;
        for list in self.order.iter_mut() {
            self.scratch.clear();
            let seg = &mut list[start..end];
            let mut w = 0;
            for k in 0..seg.len() {
                let r = seg[k];
                if self.x.get(r, f) <= thr {
                    seg[w] = r;
                    w += 1;
                } else {
                    self.scratch.push(r);
                }
            }
            seg[w..].copy_from_slice(&self.scratch);
            n_left = w;
        }
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
}
