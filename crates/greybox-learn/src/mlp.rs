//! A feed-forward network with hidden layers, trained like scikit-learn's `MLPRegressor`:
//! Glorot-uniform initialisation (bound √(6/(fan_in+fan_out)) for weights and biases),
//! squared loss ½·mean(e²) + α/(2 n_batch)·Σ‖W‖², mini-batches of min(200, n) rows
//! reshuffled every epoch, Adam (Kingma & Ba 2015; β1 0.9, β2 0.999, ε 1e-8) and early
//! stopping: 10 % of the training rows are held out, training stops after `n_iter_no_change`
//! epochs without an R² gain of `tol`, and the best weights are kept. Inputs and the target
//! are standardised inside the model.

use crate::matrix::{standardize_target, Standardizer};
use crate::model::Regressor;
use crate::Matrix;
use greybox_core::{Error, Result};
pub use greybox_model::mlp::{Activation, MlpModel, MlpParams, MAX_WIDTH};
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

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
            for r in 0..n {
                let out = &mut a_out[r * fo..(r + 1) * fo];
                out.copy_from_slice(&self.b[k]);
                for i in 0..fi {
                    let v = a_in[r * fi + i];
                    if v != 0.0 {
                        let wrow = &self.w[k][i * fo..(i + 1) * fo];
                        for (o, w) in out.iter_mut().zip(wrow) {
                            *o += v * w;
                        }
                    }
                }
                if k + 1 < last {
                    for o in out.iter_mut() {
                        *o = self.act.apply(*o);
                    }
                }
            }
        }
    }
}

fn r2_score(y: &[f64], p: &[f64]) -> f64 {
    crate::metrics::r2(y, p)
}

impl Regressor for MlpParams {
    type Fitted = MlpModel;

    fn validate(&self) -> Result<()> {
        if self.hidden_layers.is_empty()
            || self.hidden_layers.iter().any(|&h| h == 0 || h > MAX_WIDTH)
        {
            return Err(Error::invalid(
                "MLP",
                format!(
                    "hidden layer sizes must be 1..={MAX_WIDTH}, got {:?}",
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
        let mut net = Net {
            sizes: sizes.clone(),
            w: Vec::new(),
            b: Vec::new(),
            act: self.activation,
        };
        for k in 0..sizes.len() - 1 {
            let (fi, fo) = (sizes[k], sizes[k + 1]);
            let bound = (6.0 / (fi + fo) as f64).sqrt();
            net.w
                .push((0..fi * fo).map(|_| rng.gen_range(-bound..bound)).collect());
            net.b
                .push((0..fo).map(|_| rng.gen_range(-bound..bound)).collect());
        }
        // split train / validation
        let mut idx: Vec<usize> = (0..x.n_rows).collect();
        idx.shuffle(&mut rng);
        let n_val = if self.validation_fraction > 0.0 {
            ((x.n_rows as f64) * self.validation_fraction).ceil() as usize
        } else {
            0
        };
        if x.n_rows < n_val + 2 {
            return Err(Error::invalid(
                "MLP",
                format!("too few rows ({}) for the validation split", x.n_rows),
            ));
        }
        let (val_idx, train_idx) = idx.split_at(n_val);
        let mut train_idx = train_idx.to_vec();
        let val_x: Vec<f64> = val_idx
            .iter()
            .flat_map(|&i| z.row(i).iter().copied())
            .collect();
        let val_y: Vec<f64> = val_idx.iter().map(|&i| ys[i]).collect();
        let n_train = train_idx.len();
        let batch = self.batch_size.unwrap_or(200).min(n_train);
        let layers = sizes.len() - 1;
        let mut m_w: Vec<Vec<f64>> = net.w.iter().map(|w| vec![0.0; w.len()]).collect();
        let mut v_w = m_w.clone();
        let mut m_b: Vec<Vec<f64>> = net.b.iter().map(|b| vec![0.0; b.len()]).collect();
        let mut v_b = m_b.clone();
        let mut g_w = m_w.clone();
        let mut g_b = m_b.clone();
        let mut acts: Vec<Vec<f64>> = vec![Vec::new(); sizes.len()];
        let mut deltas: Vec<Vec<f64>> = vec![Vec::new(); sizes.len()];
        let mut wt_buf: Vec<Vec<f64>> = vec![Vec::new(); sizes.len()];
        let mut xb = Vec::with_capacity(batch * x.n_cols);
        let mut yb = Vec::with_capacity(batch);
        let (beta1, beta2, eps) = (0.9f64, 0.999f64, 1e-8);
        let mut t = 0i32;
        let mut best_score = f64::NEG_INFINITY;
        let mut best = (net.w.clone(), net.b.clone());
        let mut best_epoch = 0;
        let mut no_improve = 0;
        let mut epochs = 0;
        let mut val_acts: Vec<Vec<f64>> = vec![Vec::new(); sizes.len()];
        for epoch in 0..self.max_epochs {
            epochs = epoch + 1;
            train_idx.shuffle(&mut rng);
            for chunk in train_idx.chunks(batch) {
                let nb = chunk.len();
                xb.clear();
                yb.clear();
                for &i in chunk {
                    xb.extend_from_slice(z.row(i));
                    yb.push(ys[i]);
                }
                net.forward(&xb, nb, &mut acts);
                // output delta: d(½ mean e²)/d out = (out − y) / nb
                deltas[layers].clear();
                deltas[layers].extend(acts[layers].iter().zip(&yb).map(|(o, y)| o - y));
                for k in (0..layers).rev() {
                    let (fi, fo) = (sizes[k], sizes[k + 1]);
                    let gw = &mut g_w[k];
                    let gb = &mut g_b[k];
                    gw.iter_mut().for_each(|v| *v = 0.0);
                    gb.iter_mut().for_each(|v| *v = 0.0);
                    for r in 0..nb {
                        let d = &deltas[k + 1][r * fo..(r + 1) * fo];
                        let a = &acts[k][r * fi..(r + 1) * fi];
                        if fo == 1 {
                            for (g, av) in gw.iter_mut().zip(a) {
                                *g += av * d[0];
                            }
                            gb[0] += d[0];
                            continue;
                        }
                        for i in 0..fi {
                            if a[i] != 0.0 {
                                let row = &mut gw[i * fo..(i + 1) * fo];
                                for (g, dv) in row.iter_mut().zip(d) {
                                    *g += a[i] * dv;
                                }
                            }
                        }
                        for (g, dv) in gb.iter_mut().zip(d) {
                            *g += dv;
                        }
                    }
                    let inv = 1.0 / nb as f64;
                    for (g, w) in gw.iter_mut().zip(&net.w[k]) {
                        *g = (*g + self.alpha * w) * inv;
                    }
                    gb.iter_mut().for_each(|g| *g *= inv);
                    if k > 0 {
                        // delta of the hidden layer below: δ_k = (δ_{k+1} Wᵀ) ⊙ f'(a_k),
                        // accumulated row by row as axpy over the transposed weights
                        let wt = &mut wt_buf[k];
                        wt.clear();
                        wt.resize(fi * fo, 0.0);
                        for i in 0..fi {
                            for o in 0..fo {
                                wt[o * fi + i] = net.w[k][i * fo + o];
                            }
                        }
                        let mut dk = std::mem::take(&mut deltas[k]);
                        dk.clear();
                        dk.resize(nb * fi, 0.0);
                        for r in 0..nb {
                            let d = &deltas[k + 1][r * fo..(r + 1) * fo];
                            let out = &mut dk[r * fi..(r + 1) * fi];
                            for (o, dv) in d.iter().enumerate() {
                                for (acc, w) in out.iter_mut().zip(&wt[o * fi..(o + 1) * fi]) {
                                    *acc += dv * w;
                                }
                            }
                            for (acc, a) in out.iter_mut().zip(&acts[k][r * fi..(r + 1) * fi]) {
                                *acc *= derivative_from_output(self.activation, *a);
                            }
                        }
                        deltas[k] = dk;
                    }
                }
                t += 1;
                let lr_t =
                    self.learning_rate * (1.0 - beta2.powi(t)).sqrt() / (1.0 - beta1.powi(t));
                for k in 0..layers {
                    for (((w, g), m), v) in net.w[k]
                        .iter_mut()
                        .zip(&g_w[k])
                        .zip(m_w[k].iter_mut())
                        .zip(v_w[k].iter_mut())
                    {
                        *m = beta1 * *m + (1.0 - beta1) * g;
                        *v = beta2 * *v + (1.0 - beta2) * g * g;
                        *w -= lr_t * *m / (v.sqrt() + eps);
                    }
                    for (((b, g), m), v) in net.b[k]
                        .iter_mut()
                        .zip(&g_b[k])
                        .zip(m_b[k].iter_mut())
                        .zip(v_b[k].iter_mut())
                    {
                        *m = beta1 * *m + (1.0 - beta1) * g;
                        *v = beta2 * *v + (1.0 - beta2) * g * g;
                        *b -= lr_t * *m / (v.sqrt() + eps);
                    }
                }
            }
            if n_val == 0 {
                continue;
            }
            net.forward(&val_x, n_val, &mut val_acts);
            let score = r2_score(&val_y, &val_acts[layers]);
            if !score.is_finite() {
                return Err(Error::invalid(
                    "MLP",
                    "training diverged (non-finite validation score); lower the learning rate",
                ));
            }
            if score < best_score + self.tol {
                no_improve += 1;
            } else {
                no_improve = 0;
            }
            if score > best_score {
                best_score = score;
                best = (net.w.clone(), net.b.clone());
                best_epoch = epoch + 1;
            }
            if no_improve > self.n_iter_no_change {
                break;
            }
        }
        if n_val > 0 {
            net.w = best.0;
            net.b = best.1;
        } else {
            best_epoch = epochs;
        }
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
