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
    let mut n = &nodes[root as usize];
    while n.feature != LEAF {
        n = &nodes[(n.left + u32::from(x[n.feature as usize] > n.value)) as usize];
    }
    n.value
}

/// A fitted tree ensemble: prediction = base + scale · Σ_t tree_t(x).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TreeEnsemble {
    pub n_features: usize,
    pub base: f64,
    pub scale: f64,
    pub roots: Vec<u32>,
    pub nodes: Vec<Node>,
}

impl TreeEnsemble {
    /// Prediction for one row. Eight trees are walked in lockstep so that their dependent
    /// node loads overlap; leaves are summed in tree order.
    #[inline]
    pub fn predict_one(&self, x: &[f64]) -> f64 {
        const LANES: usize = 8;
        let mut s = 0.0;
        for chunk in self.roots.chunks(LANES) {
            let mut idx = [0u32; LANES];
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
                s += self.nodes[*k as usize].value;
            }
        }
        self.base + self.scale * s
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

impl crate::predictor::Predictor for TreeEnsemble {
    fn predict_one(&self, x: &[f64]) -> f64 {
        TreeEnsemble::predict_one(self, x)
    }
}
