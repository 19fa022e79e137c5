//! A feed-forward network with hidden layers, trained like scikit-learn's `MLPRegressor`:
//! Glorot-uniform initialisation (bound √(6/(fan_in+fan_out)) for weights and biases),
//! squared loss ½·mean(e²) + α/(2 n_batch)·Σ‖W‖², mini-batches of min(200, n) rows
//! reshuffled every epoch, Adam (Kingma & Ba 2015; β1 0.9, β2 0.999, ε 1e-8) and early
//! stopping: 10 % of the training rows are held out, training stops after `n_iter_no_change`
//! epochs without an R² gain of `tol`, and the best weights are kept. Inputs and the target
//! are standardised inside the model.

use crate::regressor::{GridSearch, Regressor};
use greybox_core::{Error, Result};
use greybox_model::matrix::{standardize_target, Standardizer};
use greybox_model::mlp::{Activation, MlpModel, MlpParams, MAX_WIDTH};
use greybox_model::mlp::{Epochs, LayerWidth, MAX_LAYERS};
use greybox_model::Matrix;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// The activation's derivative expressed through its output a.
#[inline]
fn derivative_from_output(act: Activation, a: f64) -> f64 {
    match act {
        Activation::Relu => {
            if a > 0.0 {
                1.0
            } else {
                0.0
            }
        }
        Activation::Tanh => 1.0 - a * a,
        Activation::Logistic => a * (1.0 - a),
        Activation::Identity => 1.0,
    }
}

/// The activation over a row of pre-activations, in place (tanh by the vectorised
/// [`crate::fast_math`]: training only; inference keeps libm's).
#[inline(always)]
fn activate(act: Activation, v: &mut [f64]) {
    match act {
        Activation::Tanh => crate::fast_math::tanh_in_place(v),
        other => {
            for o in v.iter_mut() {
                *o = other.apply(*o);
            }
        }
    }
}

struct Net {
    sizes: Vec<usize>,
    w: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
    act: Activation,
}

impl Net {
    /// Forward pass for a batch; fills `acts[k]` (batch × sizes[k]).
    #[inline(always)]
    fn forward(&self, x: &[f64], n: usize, acts: &mut [Vec<f64>]) {
        acts[0].clear();
        acts[0].extend_from_slice(x);
        let last = self.sizes.len() - 1;
        for k in 0..last {
            let (fi, fo) = (self.sizes[k], self.sizes[k + 1]);
            let (prev, rest) = acts.split_at_mut(k + 1);
            let a_in = &prev[k];
            let a_out = &mut rest[0];
            a_out.clear();
            a_out.resize(n * fo, 0.0);
            if fo == 1 {
                // output neuron: one dot product per row
                let w = &self.w[k];
                for r in 0..n {
                    let a = &a_in[r * fi..(r + 1) * fi];
                    a_out[r] = self.b[k][0] + a.iter().zip(w).map(|(x, y)| x * y).sum::<f64>();
                }
                continue;
            }
            for out in a_out.chunks_exact_mut(fo) {
                out.copy_from_slice(&self.b[k]);
            }
            // a_out (n × fo) += a_in (n × fi) · W (fi × fo)
            gemm(n, fi, fo, (a_in, fi, 1), (&self.w[k], fo, 1), 1.0, a_out);
            if k + 1 < last {
                for out in a_out.chunks_exact_mut(fo) {
                    activate(self.act, out);
                }
            }
        }
    }
}

/// C (m × n, row-major) ← A (m × k) · B (k × n) + β C, where A and B are given as
/// (elements, row stride, column stride): a transpose is a swap of the strides. The
/// blocked kernels of `matrixmultiply` (run-time AVX/FMA dispatch, one thread).
#[inline]
fn gemm(
    m: usize,
    k: usize,
    n: usize,
    a: (&[f64], usize, usize),
    b: (&[f64], usize, usize),
    beta: f64,
    c: &mut [f64],
) {
    let last = |rows: usize, cols: usize, rs: usize, cs: usize| {
        if rows == 0 || cols == 0 {
            0
        } else {
            (rows - 1) * rs + (cols - 1) * cs + 1
        }
    };
    assert!(a.0.len() >= last(m, k, a.1, a.2) && b.0.len() >= last(k, n, b.1, b.2));
    assert!(c.len() >= m * n);
    // SAFETY: the asserts keep every element the strides reach inside the slices.
    unsafe {
        matrixmultiply::dgemm(
            m,
            k,
            n,
            1.0,
            a.0.as_ptr(),
            a.1 as isize,
            a.2 as isize,
            b.0.as_ptr(),
            b.1 as isize,
            b.2 as isize,
            beta,
            c.as_mut_ptr(),
            n as isize,
            1,
        );
    }
}

fn r2_score(y: &[f64], p: &[f64]) -> f64 {
    crate::metrics::r2(y, p)
}

impl Regressor for MlpParams {
    type Fitted = MlpModel;

    fn validate(&self) -> Result<()> {
        let invalid = |e| Error::invalid("MLP", e);
        for &h in &self.hidden_layers {
            LayerWidth::of_usize(h, "hidden layer size").map_err(invalid)?;
        }
        Epochs::of_usize(self.max_epochs, "max_epochs").map_err(invalid)?;
        if self.hidden_layers.is_empty() || self.hidden_layers.len() > MAX_LAYERS {
            return Err(Error::invalid(
                "MLP",
                format!(
                    "1..={MAX_LAYERS} hidden layers of 1..={MAX_WIDTH} neurons are needed, got {:?}",
                    self.hidden_layers
                ),
            ));
        }
        if !(self.learning_rate > 0.0 && self.learning_rate.is_finite() && self.alpha >= 0.0) {
            return Err(Error::invalid(
                "MLP",
                "learning_rate must be positive and alpha ≥ 0",
            ));
        }
        if !(0.0..0.5).contains(&self.validation_fraction)
            || self.max_epochs == 0
            || self.batch_size == Some(0)
        {
            return Err(Error::invalid(
                "MLP",
                "validation_fraction must be in [0, 0.5), max_epochs and batch_size ≥ 1",
            ));
        }
        Ok(())
    }

    fn fit(&self, x: &Matrix, y: &[f64], seed: u64) -> Result<MlpModel> {
        if x.n_cols > MAX_WIDTH {
            return Err(Error::invalid(
                "MLP",
                format!("at most {MAX_WIDTH} features"),
            ));
        }
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let scaler = Standardizer::fit(x);
        let z = scaler.transform(x);
        let (y_mean, y_scale) = standardize_target(y);
        let ys: Vec<f64> = y.iter().map(|v| (v - y_mean) / y_scale).collect();
        let mut sizes = vec![x.n_cols];
        sizes.extend(&self.hidden_layers);
        sizes.push(1);
        let mut net = Net::glorot(&sizes, self.activation, &mut rng);
        let split = validation_split(self, &z, &ys, &mut rng)?;
        let (epochs, best_epoch) = train(self, &mut net, &z, &ys, split, &mut rng)?;
        if net.w.iter().flatten().any(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "MLP",
                "training diverged (non-finite weights); lower the learning rate",
            ));
        }
        Ok(MlpModel {
            scaler,
            y_mean,
            y_scale,
            activation: self.activation,
            sizes,
            weights: net.w,
            biases: net.b,
            epochs,
            best_epoch,
        })
    }
}

/// Rows held out for early stopping: their standardized features (row-major) and targets.
struct ValidationSplit {
    train_idx: Vec<usize>,
    val_x: Vec<f64>,
    val_y: Vec<f64>,
}

impl ValidationSplit {
    fn len(&self) -> usize {
        self.val_y.len()
    }
}

impl Net {
    /// Glorot-uniform weights and biases in ±√(6 / (fan_in + fan_out)), drawn layer by layer.
    fn glorot(sizes: &[usize], act: Activation, rng: &mut ChaCha8Rng) -> Net {
        let mut net = Net {
            sizes: sizes.to_vec(),
            w: Vec::new(),
            b: Vec::new(),
            act,
        };
        for k in 0..sizes.len() - 1 {
            let (fi, fo) = (sizes[k], sizes[k + 1]);
            let bound = (6.0 / (fi + fo) as f64).sqrt();
            net.w
                .push((0..fi * fo).map(|_| rng.gen_range(-bound..bound)).collect());
            net.b
                .push((0..fo).map(|_| rng.gen_range(-bound..bound)).collect());
        }
        net
    }
}

/// Gradients of ½·mean squared error + ½·α·|W|² over a mini-batch, by backpropagation,
/// with the buffers reused from batch to batch.
struct Backprop {
    g_w: Vec<Vec<f64>>,
    g_b: Vec<Vec<f64>>,
    acts: Vec<Vec<f64>>,
    deltas: Vec<Vec<f64>>,
}

impl Backprop {
    fn new(net: &Net) -> Self {
        let n = net.sizes.len();
        Backprop {
            g_w: net.w.iter().map(|w| vec![0.0; w.len()]).collect(),
            g_b: net.b.iter().map(|b| vec![0.0; b.len()]).collect(),
            acts: vec![Vec::new(); n],
            deltas: vec![Vec::new(); n],
        }
    }

    /// Forward the batch `xb` (`nb` rows) and leave the gradients in `g_w`, `g_b`.
    #[inline(always)]
    fn gradients(&mut self, net: &Net, xb: &[f64], yb: &[f64], nb: usize, alpha: f64) {
        let sizes = &net.sizes;
        let layers = sizes.len() - 1;
        net.forward(xb, nb, &mut self.acts);
        // output delta: d(½ mean e²)/d out = (out − y) / nb
        self.deltas[layers].clear();
        self.deltas[layers].extend(self.acts[layers].iter().zip(yb).map(|(o, y)| o - y));
        for k in (0..layers).rev() {
            self.layer_gradients(net, k, nb, alpha);
            if k > 0 {
                self.delta_below(net, k, nb);
            }
        }
    }

    /// ∂/∂W_k and ∂/∂b_k from the deltas of layer k + 1 and the activations of layer k.
    #[inline(always)]
    fn layer_gradients(&mut self, net: &Net, k: usize, nb: usize, alpha: f64) {
        let (fi, fo) = (net.sizes[k], net.sizes[k + 1]);
        let gw = &mut self.g_w[k];
        let gb = &mut self.g_b[k];
        let d = &self.deltas[k + 1];
        let a = &self.acts[k];
        // ∂W (fi × fo) = a_kᵀ (fi × nb) · δ (nb × fo)
        gemm(fi, nb, fo, (a, 1, fi), (d, fo, 1), 0.0, gw);
        gb.iter_mut().for_each(|v| *v = 0.0);
        for row in d.chunks_exact(fo).take(nb) {
            for (g, dv) in gb.iter_mut().zip(row) {
                *g += dv;
            }
        }
        let inv = 1.0 / nb as f64;
        for (g, w) in gw.iter_mut().zip(&net.w[k]) {
            *g = (*g + alpha * w) * inv;
        }
        gb.iter_mut().for_each(|g| *g *= inv);
    }

    /// The delta of hidden layer k: δ_k = (δ_{k+1} Wᵀ) ⊙ f'(a_k).
    #[inline(always)]
    fn delta_below(&mut self, net: &Net, k: usize, nb: usize) {
        let (fi, fo) = (net.sizes[k], net.sizes[k + 1]);
        let mut dk = std::mem::take(&mut self.deltas[k]);
        dk.clear();
        dk.resize(nb * fi, 0.0);
        // δ_k (nb × fi) = δ_{k+1} (nb × fo) · Wᵀ (fo × fi)
        gemm(
            nb,
            fo,
            fi,
            (&self.deltas[k + 1], fo, 1),
            (&net.w[k], 1, fo),
            0.0,
            &mut dk,
        );
        for (acc, a) in dk.iter_mut().zip(&self.acts[k]) {
            *acc *= derivative_from_output(net.act, *a);
        }
        self.deltas[k] = dk;
    }
}

/// Adam (Kingma & Ba 2015) with β₁ = 0.9, β₂ = 0.999, ε = 1e-8 and the bias correction
/// folded into the step size, as scikit-learn's `MLPRegressor` does.
struct Adam {
    m_w: Vec<Vec<f64>>,
    v_w: Vec<Vec<f64>>,
    m_b: Vec<Vec<f64>>,
    v_b: Vec<Vec<f64>>,
    t: i32,
}

impl Adam {
    const BETA1: f64 = 0.9;
    const BETA2: f64 = 0.999;
    const EPS: f64 = 1e-8;

    fn new(net: &Net) -> Self {
        let m_w: Vec<Vec<f64>> = net.w.iter().map(|w| vec![0.0; w.len()]).collect();
        let m_b: Vec<Vec<f64>> = net.b.iter().map(|b| vec![0.0; b.len()]).collect();
        Adam {
            v_w: m_w.clone(),
            v_b: m_b.clone(),
            m_w,
            m_b,
            t: 0,
        }
    }

    /// One update of every weight and bias with the gradients `g_w`, `g_b`.
    fn step(&mut self, net: &mut Net, g_w: &[Vec<f64>], g_b: &[Vec<f64>], learning_rate: f64) {
        let (beta1, beta2, eps) = (Self::BETA1, Self::BETA2, Self::EPS);
        self.t += 1;
        let lr_t = learning_rate * (1.0 - beta2.powi(self.t)).sqrt() / (1.0 - beta1.powi(self.t));
        let update = |p: &mut [f64], g: &[f64], m: &mut [f64], v: &mut [f64]| {
            for (((p, g), m), v) in p.iter_mut().zip(g).zip(m.iter_mut()).zip(v.iter_mut()) {
                *m = beta1 * *m + (1.0 - beta1) * g;
                *v = beta2 * *v + (1.0 - beta2) * g * g;
                *p -= lr_t * *m / (v.sqrt() + eps);
            }
        };
        for k in 0..net.w.len() {
            update(&mut net.w[k], &g_w[k], &mut self.m_w[k], &mut self.v_w[k]);
            update(&mut net.b[k], &g_b[k], &mut self.m_b[k], &mut self.v_b[k]);
        }
    }
}

/// Shuffle the rows and hold out `validation_fraction` of them (rounded up) for early
/// stopping.
fn validation_split(
    p: &MlpParams,
    z: &Matrix,
    ys: &[f64],
    rng: &mut ChaCha8Rng,
) -> Result<ValidationSplit> {
    let mut idx: Vec<usize> = (0..z.n_rows).collect();
    idx.shuffle(rng);
    let n_val = if p.validation_fraction > 0.0 {
        ((z.n_rows as f64) * p.validation_fraction).ceil() as usize
    } else {
        0
    };
    if z.n_rows < n_val + 2 {
        return Err(Error::invalid(
            "MLP",
            format!("too few rows ({}) for the validation split", z.n_rows),
        ));
    }
    let (val_idx, train_idx) = idx.split_at(n_val);
    Ok(ValidationSplit {
        train_idx: train_idx.to_vec(),
        val_x: val_idx
            .iter()
            .flat_map(|&i| z.row(i).iter().copied())
            .collect(),
        val_y: val_idx.iter().map(|&i| ys[i]).collect(),
    })
}

/// Mini-batch Adam epochs with early stopping on the validation R² (the best weights
/// are kept); returns (epochs run, best epoch).
/// [`train_on`] compiled for AVX2 where the CPU has it (wider vectors for the element-wise
/// arithmetic: activations, deltas, Adam), else for the baseline. The matrix products pick
/// their own kernels ([`gemm`]: fused multiply-add where the CPU has it), so a fit gives the
/// same bits on the same CPU, and may differ in the last bits between CPUs.
fn train(
    p: &MlpParams,
    net: &mut Net,
    z: &Matrix,
    ys: &[f64],
    split: ValidationSplit,
    rng: &mut ChaCha8Rng,
) -> Result<(usize, usize)> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above).
        return unsafe { train_avx2(p, net, z, ys, split, rng) };
    }
    train_on(p, net, z, ys, split, rng)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn train_avx2(
    p: &MlpParams,
    net: &mut Net,
    z: &Matrix,
    ys: &[f64],
    split: ValidationSplit,
    rng: &mut ChaCha8Rng,
) -> Result<(usize, usize)> {
    train_on(p, net, z, ys, split, rng)
}

#[inline(always)]
fn train_on(
    p: &MlpParams,
    net: &mut Net,
    z: &Matrix,
    ys: &[f64],
    mut split: ValidationSplit,
    rng: &mut ChaCha8Rng,
) -> Result<(usize, usize)> {
    let n_val = split.len();
    let layers = net.sizes.len() - 1;
    let batch = p.batch_size.unwrap_or(200).min(split.train_idx.len());
    let mut backprop = Backprop::new(net);
    let mut adam = Adam::new(net);
    let mut xb = Vec::with_capacity(batch * z.n_cols);
    let mut yb = Vec::with_capacity(batch);
    let mut best_score = f64::NEG_INFINITY;
    let mut best = (net.w.clone(), net.b.clone());
    let mut best_epoch = 0;
    let mut no_improve = 0;
    let mut epochs = 0;
    let mut val_acts: Vec<Vec<f64>> = vec![Vec::new(); net.sizes.len()];
    for epoch in 0..p.max_epochs {
        epochs = epoch + 1;
        split.train_idx.shuffle(rng);
        for chunk in split.train_idx.chunks(batch) {
            xb.clear();
            yb.clear();
            for &i in chunk {
                xb.extend_from_slice(z.row(i));
                yb.push(ys[i]);
            }
            backprop.gradients(net, &xb, &yb, chunk.len(), p.alpha);
            adam.step(net, &backprop.g_w, &backprop.g_b, p.learning_rate);
        }
        if n_val == 0 {
            continue;
        }
        net.forward(&split.val_x, n_val, &mut val_acts);
        let score = r2_score(&split.val_y, &val_acts[layers]);
        if !score.is_finite() {
            return Err(Error::invalid(
                "MLP",
                "training diverged (non-finite validation score); lower the learning rate",
            ));
        }
        if score < best_score + p.tol {
            no_improve += 1;
        } else {
            no_improve = 0;
        }
        if score > best_score {
            best_score = score;
            best = (net.w.clone(), net.b.clone());
            best_epoch = epoch + 1;
        }
        if no_improve > p.n_iter_no_change {
            break;
        }
    }
    if n_val > 0 {
        net.w = best.0;
        net.b = best.1;
    } else {
        best_epoch = epochs;
    }
    Ok((epochs, best_epoch))
}

/// MLP grid (article: {(64,32), (32,16)} × {relu, tanh} × lr ∈ {0.001, 0.01, 0.1}).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct MlpGrid {
    pub base: MlpParams,
    pub hidden_layers: Vec<Vec<usize>>,
    pub activation: Vec<Activation>,
    pub learning_rate: Vec<f64>,
}

impl Default for MlpGrid {
    fn default() -> Self {
        MlpGrid {
            base: MlpParams::default(),
            hidden_layers: vec![vec![64, 32], vec![32, 16]],
            activation: vec![Activation::Relu, Activation::Tanh],
            learning_rate: vec![0.001, 0.01, 0.1],
        }
    }
}

impl GridSearch for MlpParams {
    type Grid = MlpGrid;
    /// Layer sizes outermost, then activation, then learning rate.
    fn candidates(grid: &MlpGrid) -> Vec<Self> {
        let mut out = Vec::new();
        for hidden_layers in &grid.hidden_layers {
            for &activation in &grid.activation {
                for &learning_rate in &grid.learning_rate {
                    out.push(MlpParams {
                        hidden_layers: hidden_layers.clone(),
                        activation,
                        learning_rate,
                        ..grid.base.clone()
                    });
                }
            }
        }
        out
    }
}
