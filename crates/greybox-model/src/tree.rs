//! Flat regression-tree ensembles for inference: 16-byte nodes whose two children are
//! adjacent (right = left + 1), walked without allocation. Growing trees is
//! `greybox-learn`'s `tree` module.

use serde::{Deserialize, Serialize};

/// Marks a leaf in [`Node::feature`].
pub const LEAF: u32 = u32::MAX;

/// One node of a flat tree: a split (`x[feature] <= value` goes to `left`, otherwise to
/// `left + 1`) or, when `feature` is [`LEAF`], a leaf whose prediction is `value` (already
/// scaled by the learning rate for boosting).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Node {
    /// Split threshold, or the leaf value.
    pub value: f64,
    /// Split feature, or [`LEAF`].
    pub feature: u32,
    /// Index of the left child; the right child follows it.
    pub left: u32,
}

/// Value of the leaf that `x` falls into, starting at `root`.
#[inline]
pub fn walk(nodes: &[Node], root: u32, x: &[f64]) -> f64 {
    nodes[leaf_index(nodes, root, x) as usize].value
}

/// Index of the leaf that `x` falls into, starting at `root`.
#[inline]
fn leaf_index(nodes: &[Node], root: u32, x: &[f64]) -> u32 {
    let mut k = root;
    loop {
        let n = &nodes[k as usize];
        if n.feature == LEAF {
            return k;
        }
        k = n.left + u32::from(x[n.feature as usize] > n.value);
    }
}

/// How the leaves of the trees are added up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Accumulation {
    /// base + scale · Σ_t leaf_t in f64 (greybox's own ensembles, scikit-learn's).
    #[default]
    F64,
    /// ((base + leaf_1) + leaf_2) + … in f32, tree by tree, as XGBoost's CPU predictor
    /// adds leaf values to the margin (scale must be 1): reproduces its float32 output bit
    /// for bit.
    F32,
}

impl Accumulation {
    fn is_f64(&self) -> bool {
        *self == Accumulation::F64
    }
}

/// A fitted tree ensemble: prediction = base + scale · Σ_t tree_t(x) (see [`Accumulation`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TreeEnsemble {
    pub n_features: usize,
    pub base: f64,
    pub scale: f64,
    pub roots: Vec<u32>,
    pub nodes: Vec<Node>,
    /// How leaves are summed (absent in files: f64).
    #[serde(default, skip_serializing_if = "Accumulation::is_f64")]
    pub accumulation: Accumulation,
}

impl TreeEnsemble {
    /// An ensemble without trees yet (f64 accumulation): prediction = base + scale · Σ.
    pub fn new(n_features: usize, base: f64, scale: f64) -> Self {
        TreeEnsemble {
            n_features,
            base,
            scale,
            roots: Vec::new(),
            nodes: Vec::new(),
            accumulation: Accumulation::F64,
        }
    }

    /// Prediction for one row. Eight trees are walked in lockstep so that their dependent
    /// node loads overlap; leaves are summed in tree order.
    #[inline]
    pub fn predict_one(&self, x: &[f64]) -> f64 {
        match self.accumulation {
            Accumulation::F64 => self.base + self.scale * self.sum_leaves(x, 0.0f64, |v| v),
            Accumulation::F32 => self.sum_leaves(x, self.base as f32, |v| v as f32) as f64,
        }
    }

    /// `start` plus the leaves `x` falls into, converted by `leaf` and added in tree order.
    #[inline]
    fn sum_leaves<T: std::ops::AddAssign + Copy>(
        &self,
        x: &[f64],
        start: T,
        leaf: impl Fn(f64) -> T,
    ) -> T {
        let mut s = start;
        for chunk in self.roots.chunks(WALK_LANES) {
            self.add_chunk_leaves(chunk, x, &mut s, &leaf);
        }
        s
    }

    /// Walks the trees `chunk` (at most [`WALK_LANES`]) in lockstep for `x` and adds their
    /// leaves to `s` in tree order.
    #[inline]
    fn add_chunk_leaves<T: std::ops::AddAssign + Copy>(
        &self,
        chunk: &[u32],
        x: &[f64],
        s: &mut T,
        leaf: &impl Fn(f64) -> T,
    ) {
        let mut idx = [0u32; WALK_LANES];
        idx[..chunk.len()].copy_from_slice(chunk);
        loop {
            let mut moved = false;
            for k in idx.iter_mut().take(chunk.len()) {
                let n = &self.nodes[*k as usize];
                if n.feature != LEAF {
                    *k = n.left + u32::from(x[n.feature as usize] > n.value);
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        for k in &idx[..chunk.len()] {
            *s += leaf(self.nodes[*k as usize].value);
        }
    }

    /// Predictions for every row of `x`, equal bit for bit to [`Self::predict_one`] row by
    /// row. Rows go in blocks of [`PREDICT_BLOCK`], and each block walks one chunk of trees
    /// for all its rows before the next chunk, so those trees' nodes stay in cache: a large
    /// forest (200 deep trees of 10⁴ rows are ≈ 30 MB of nodes) is read once per block
    /// instead of once per row. The blocks take the rows in [`Self::locality_order`], so
    /// that a block's rows lie close together in feature space and walk mostly the same
    /// nodes; every row still adds its leaves in tree order.
    pub fn predict_rows(&self, x: &crate::matrix::Matrix) -> Vec<f64> {
        let mut out = vec![0.0; x.n_rows];
        for block in self.locality_order(x).chunks(PREDICT_BLOCK) {
            match self.accumulation {
                Accumulation::F64 => {
                    let sums = self.block_sums(x, block, 0.0f64, |v| v);
                    for (&r, s) in block.iter().zip(sums) {
                        out[r as usize] = self.base + self.scale * s;
                    }
                }
                Accumulation::F32 => {
                    let sums = self.block_sums(x, block, self.base as f32, |v| v as f32);
                    for (&r, s) in block.iter().zip(sums) {
                        out[r as usize] = s as f64;
                    }
                }
            }
        }
        out
    }

    /// The rows of `x` ordered by the leaf of the first tree they fall into (ties in row
    /// order), or in row order when there are too few rows to fill two blocks. The first
    /// tree's leaves, numbered depth first, partition the feature space into cells whose
    /// neighbours in index are neighbours in space, so consecutive rows walk mostly the same
    /// paths of every tree. Deep trees of 10⁵ training rows are megabytes each, and rows in
    /// their given (random) order miss the cache at nearly every level.
    fn locality_order(&self, x: &crate::matrix::Matrix) -> Vec<u32> {
        let rows = 0..x.n_rows as u32;
        let Some(&first) = self.roots.first() else {
            return rows.collect();
        };
        if x.n_rows < 2 * PREDICT_BLOCK {
            return rows.collect();
        }
        let mut keyed: Vec<(u32, u32)> = rows
            .map(|r| (leaf_index(&self.nodes, first, x.row(r as usize)), r))
            .collect();
        keyed.sort_unstable();
        keyed.into_iter().map(|(_, r)| r).collect()
    }

    /// [`Self::sum_leaves`] for the rows `block` of `x`, trees chunk by chunk.
    fn block_sums<T: std::ops::AddAssign + Copy>(
        &self,
        x: &crate::matrix::Matrix,
        block: &[u32],
        start: T,
        leaf: impl Fn(f64) -> T,
    ) -> Vec<T> {
        let mut sums = vec![start; block.len()];
        for chunk in self.roots.chunks(WALK_LANES) {
            for (s, &r) in sums.iter_mut().zip(block) {
                self.add_chunk_leaves(chunk, x.row(r as usize), s, &leaf);
            }
        }
        sums
    }
    /// Append a tree grown in its own node buffer.
    pub fn push_tree(&mut self, nodes: Vec<Node>, root: u32) {
        let off = self.nodes.len() as u32;
        self.roots.push(root + off);
        self.nodes.extend(nodes.into_iter().map(|mut n| {
            if n.feature != LEAF {
                n.left += off;
            }
            n
        }));
    }
}

/// Trees walked in lockstep by one prediction.
const WALK_LANES: usize = 8;
/// Rows per block of [`TreeEnsemble::predict_rows`].
const PREDICT_BLOCK: usize = 256;

impl crate::predictor::Predictor for TreeEnsemble {
    fn predict_one(&self, x: &[f64]) -> f64 {
        TreeEnsemble::predict_one(self, x)
    }
    fn predict(&self, x: &crate::matrix::Matrix) -> Vec<f64> {
        self.predict_rows(x)
    }
}

/// A tree ensemble compiled into a lookup table over the cells its split thresholds cut the
/// feature space into. Within a cell every split of every tree goes the same way (a split
/// sends `x` right exactly when `x > threshold`), so the cell holds the ensemble's
/// prediction bit for bit: [`TreeEnsemble::predict_one`] at a point of the cell, whose
/// leaves are summed in the same order for every point of it. A lookup is one binary search
/// per feature instead of a walk down every tree.
#[derive(Debug, Clone, PartialEq)]
pub struct DecisionGrid {
    /// Per feature: the distinct split thresholds, ascending.
    thresholds: Vec<Vec<f64>>,
    /// Per feature: the index step of one cell along it.
    strides: Vec<usize>,
    /// Prediction per cell, row-major in feature order.
    values: Vec<f64>,
}

impl DecisionGrid {
    /// The grid of `ensemble`, or `None` when it would have more than `max_cells` cells (the
    /// product over features of the distinct thresholds plus one).
    pub fn build(ensemble: &TreeEnsemble, max_cells: usize) -> Option<Self> {
        let n = ensemble.n_features;
        let mut thresholds = vec![Vec::new(); n];
        for node in ensemble.nodes.iter().filter(|node| node.feature != LEAF) {
            thresholds.get_mut(node.feature as usize)?.push(node.value);
        }
        for t in &mut thresholds {
            t.sort_by(f64::total_cmp);
            t.dedup();
        }
        let mut strides = vec![0; n];
        let mut cells = 1usize;
        for f in (0..n).rev() {
            strides[f] = cells;
            cells = cells.checked_mul(thresholds[f].len() + 1)?;
            if cells > max_cells {
                return None;
            }
        }
        let mut values = Vec::with_capacity(cells);
        let mut x = vec![0.0; n];
        for cell in 0..cells {
            for f in 0..n {
                x[f] = Self::inside(
                    &thresholds[f],
                    (cell / strides[f]) % (thresholds[f].len() + 1),
                );
            }
            values.push(ensemble.predict_one(&x));
        }
        Some(DecisionGrid {
            thresholds,
            strides,
            values,
        })
    }

    /// A value of cell `c` along a feature with these thresholds: cell c holds the x with
    /// t[c−1] < x ≤ t[c] (the first cell everything up to t[0], the last everything above
    /// the largest threshold).
    fn inside(t: &[f64], c: usize) -> f64 {
        match (t.get(c), t.last()) {
            (Some(&upper), _) => upper,
            (None, Some(&largest)) => largest.next_up(),
            (None, None) => 0.0,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether the grid has no cells (never: a grid has at least one).
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The ensemble's prediction at `x`: the value of the cell `x` lies in. A NaN feature
    /// falls into the first cell, where every split sends it left, as the trees do.
    #[inline]
    pub fn predict_one(&self, x: &[f64]) -> f64 {
        let mut cell = 0;
        for ((t, stride), &xf) in self.thresholds.iter().zip(&self.strides).zip(x) {
            cell += t.partition_point(|&v| v < xf) * stride;
        }
        self.values[cell]
    }

    /// Per feature: the distinct split thresholds, ascending (a split sends `x` left when
    /// `x <= threshold`).
    pub fn thresholds(&self) -> &[Vec<f64>] {
        &self.thresholds
    }
}
