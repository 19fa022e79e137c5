//! ε-support vector regression with libsvm's semantics (Chang & Lin, "LIBSVM: a library for
//! support vector machines", ACM TIST 2011): the dual over 2l variables solved by SMO with
//! second-order working-set selection (Fan, Chen & Lin, JMLR 6, 2005, WSS3), stopping when
//! the maximal violation is below `tol` (1e-3). Kernels: linear ⟨x,x'⟩, poly (γ⟨x,x'⟩+c0)^d,
//! rbf exp(−γ‖x−x'‖²), sigmoid tanh(γ⟨x,x'⟩+c0); γ = 'scale' = 1 / (p · Var(X)) as in
//! scikit-learn. Inputs are standardised inside the model; the target is not.
//!
//! The kernel matrix is computed once (l² entries), which suits the few hundred to few
//! thousand rows of a tribometer campaign; there is no shrinking heuristic.

use crate::matrix::Standardizer;
use crate::model::{Predictor, Regressor};
use crate::Matrix;
use greybox_core::{Error, Result};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kernel {
    Linear,
    Poly,
    Rbf,
    Sigmoid,
}

impl Kernel {
    pub fn name(self) -> &'static str {
        match self {
            Kernel::Linear => "linear",
            Kernel::Poly => "poly",
            Kernel::Rbf => "rbf",
            Kernel::Sigmoid => "sigmoid",
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SvrParams {
    /// Penalty C.
    pub c: f64,
    /// Width of the ε-insensitive tube (target units).
    pub epsilon: f64,
    pub kernel: Kernel,
    /// Kernel coefficient γ (`None`: 'scale').
    pub gamma: Option<f64>,
    pub degree: u32,
    pub coef0: f64,
    /// Stopping tolerance on the maximal KKT violation.
    pub tol: f64,
    /// Iteration cap (`None`: max(10⁷, 100 l), as libsvm).
    pub max_iter: Option<usize>,
}

impl Default for SvrParams {
    fn default() -> Self {
        SvrParams {
            c: 1.0,
            epsilon: 0.1,
            kernel: Kernel::Rbf,
            gamma: None,
            degree: 3,
            coef0: 0.0,
            tol: 1e-3,
            max_iter: None,
        }
    }
}

/// A fitted ε-SVR: f(x) = Σ_i β_i K(s_i, z(x)) − ρ with z the standardised input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SvrModel {
    pub scaler: Standardizer,
    pub kernel: Kernel,
    pub gamma: f64,
    pub degree: u32,
    pub coef0: f64,
    /// Support vectors (standardised), row-major.
    pub support: Matrix,
    pub coef: Vec<f64>,
    pub rho: f64,
    /// SMO iterations used.
    pub iterations: usize,
}

#[inline]
fn kernel_value(k: Kernel, gamma: f64, degree: u32, coef0: f64, a: &[f64], b: &[f64]) -> f64 {
    match k {
        Kernel::Linear => dot(a, b),
        Kernel::Poly => (gamma * dot(a, b) + coef0).powi(degree as i32),
        Kernel::Rbf => {
            let d2: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
            (-gamma * d2).exp()
        }
        Kernel::Sigmoid => (gamma * dot(a, b) + coef0).tanh(),
    }
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

const TAU: f64 = 1e-12;

impl Regressor for SvrParams {
    type Fitted = SvrModel;

    fn validate(&self) -> Result<()> {
        if !(self.c > 0.0 && self.c.is_finite()) {
            return Err(Error::invalid(
                "SVR",
                format!("C must be positive, got {}", self.c),
            ));
        }
        if !(self.epsilon >= 0.0 && self.epsilon.is_finite()) {
            return Err(Error::invalid(
                "SVR",
                format!("epsilon must be ≥ 0, got {}", self.epsilon),
            ));
        }
        if let Some(g) = self.gamma {
            if !(g > 0.0 && g.is_finite()) {
                return Err(Error::invalid(
                    "SVR",
                    format!("gamma must be positive, got {g}"),
                ));
            }
        }
        if !(self.tol > 0.0) || self.degree == 0 {
            return Err(Error::invalid("SVR", "tol must be positive and degree ≥ 1"));
        }
        Ok(())
    }

    fn fit(&self, x: &Matrix, y: &[f64], _seed: u64) -> Result<SvrModel> {
        let scaler = Standardizer::fit(x);
        let z = scaler.transform(x);
        let l = z.n_rows;
        let gamma = self.gamma.unwrap_or_else(|| {
            let n = z.data.len() as f64;
            let m = z.data.iter().sum::<f64>() / n;
            let var = z.data.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n;
            if var > 0.0 {
                1.0 / (z.n_cols as f64 * var)
            } else {
                1.0
            }
        });
        let k = |i: usize, j: usize| {
            kernel_value(
                self.kernel,
                gamma,
                self.degree,
                self.coef0,
                z.row(i),
                z.row(j),
            )
        };
        let mut kmat = vec![0.0; l * l];
        for i in 0..l {
            for j in 0..=i {
                let v = k(i, j);
                kmat[i * l + j] = v;
                kmat[j * l + i] = v;
            }
        }
        let n2 = 2 * l;
        let c = self.c;
        // variable t: sign y_t (+1 for α, −1 for α*), kernel row t mod l
        let ys: Vec<f64> = (0..n2).map(|t| if t < l { 1.0 } else { -1.0 }).collect();
        let kr: Vec<usize> = (0..n2).map(|t| t % l).collect();
        let qd: Vec<f64> = (0..n2).map(|t| kmat[kr[t] * l + kr[t]]).collect();
        let lin: Vec<f64> = (0..n2)
            .map(|t| {
                if t < l {
                    self.epsilon - y[t]
                } else {
                    self.epsilon + y[t - l]
                }
            })
            .collect();
        let mut alpha = vec![0.0; n2];
        let mut grad = lin.clone();
        let max_iter = self.max_iter.unwrap_or((100 * l).max(10_000_000));
        let is_up = |a: f64, yt: f64| if yt > 0.0 { a < c } else { a > 0.0 };
        let is_low = |a: f64, yt: f64| if yt > 0.0 { a > 0.0 } else { a < c };
        // Shrinking (Chang & Lin 2011, §5.1): variables at a bound that cannot enter the
        // working set are set aside; their gradients are rebuilt before the final check.
        let mut active: Vec<usize> = (0..n2).collect();
        let mut unshrunk = false;
        let reconstruct = |alpha: &[f64], grad: &mut [f64], active: &[usize]| {
            let mut is_active = vec![false; n2];
            for &t in active {
                is_active[t] = true;
            }
            let nz: Vec<usize> = (0..n2).filter(|&s| alpha[s] != 0.0).collect();
            for t in (0..n2).filter(|&t| !is_active[t]) {
                let row = &kmat[kr[t] * l..(kr[t] + 1) * l];
                grad[t] = lin[t]
                    + nz.iter()
                        .map(|&s| ys[t] * ys[s] * row[kr[s]] * alpha[s])
                        .sum::<f64>();
            }
        };
        let mut counter = l.min(1000);
        let mut iter = 0;
        while iter < max_iter {
            counter -= 1;
            if counter == 0 {
                counter = l.min(1000);
                let (mut g1, mut g2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
                for &t in &active {
                    if is_up(alpha[t], ys[t]) {
                        g1 = g1.max(-ys[t] * grad[t]);
                    }
                    if is_low(alpha[t], ys[t]) {
                        g2 = g2.max(ys[t] * grad[t]);
                    }
                }
                if !unshrunk && g1 + g2 <= self.tol * 10.0 {
                    unshrunk = true;
                    reconstruct(&alpha, &mut grad, &active);
                    active = (0..n2).collect();
                }
                active.retain(|&t| {
                    let (a, yt, gt) = (alpha[t], ys[t], grad[t]);
                    let shrink = if a >= c {
                        if yt > 0.0 {
                            -gt > g1
                        } else {
                            -gt > g2
                        }
                    } else if a <= 0.0 {
                        if yt > 0.0 {
                            gt > g2
                        } else {
                            gt > g1
                        }
                    } else {
                        false
                    };
                    !shrink
                });
            }
            let mut pair =
                select_pair(&active, &alpha, &grad, &ys, &kr, &qd, &kmat, l, c, self.tol);
            if pair.is_none() && active.len() < n2 {
                reconstruct(&alpha, &mut grad, &active);
                active = (0..n2).collect();
                pair = select_pair(&active, &alpha, &grad, &ys, &kr, &qd, &kmat, l, c, self.tol);
                counter = 1;
            }
            let Some((i, j)) = pair else { break };
            iter += 1;
            let (old_i, old_j) = (alpha[i], alpha[j]);
            let kij = kmat[kr[i] * l + kr[j]];
            if ys[i] != ys[j] {
                let quad = qd[i] + qd[j] - 2.0 * kij;
                let quad = if quad > 0.0 { quad } else { TAU };
                let delta = (-grad[i] - grad[j]) / quad;
                let diff = alpha[i] - alpha[j];
                alpha[i] += delta;
                alpha[j] += delta;
                if diff > 0.0 {
                    if alpha[j] < 0.0 {
                        alpha[j] = 0.0;
                        alpha[i] = diff;
                    }
                } else if alpha[i] < 0.0 {
                    alpha[i] = 0.0;
                    alpha[j] = -diff;
                }
                if diff > 0.0 {
                    if alpha[i] > c {
                        alpha[i] = c;
                        alpha[j] = c - diff;
                    }
                } else if alpha[j] > c {
                    alpha[j] = c;
                    alpha[i] = c + diff;
                }
            } else {
                let quad = qd[i] + qd[j] - 2.0 * kij;
                let quad = if quad > 0.0 { quad } else { TAU };
                let delta = (grad[i] - grad[j]) / quad;
                let sum = alpha[i] + alpha[j];
                alpha[i] -= delta;
                alpha[j] += delta;
                if sum > c {
                    if alpha[i] > c {
                        alpha[i] = c;
                        alpha[j] = sum - c;
                    }
                } else if alpha[j] < 0.0 {
                    alpha[j] = 0.0;
                    alpha[i] = sum;
                }
                if sum > c {
                    if alpha[j] > c {
                        alpha[j] = c;
                        alpha[i] = sum - c;
                    }
                } else if alpha[i] < 0.0 {
                    alpha[i] = 0.0;
                    alpha[j] = sum;
                }
            }
            let (di, dj) = ((alpha[i] - old_i) * ys[i], (alpha[j] - old_j) * ys[j]);
            if di != 0.0 || dj != 0.0 {
                let ri = &kmat[kr[i] * l..(kr[i] + 1) * l];
                let rj = &kmat[kr[j] * l..(kr[j] + 1) * l];
                for &t in &active {
                    let tt = kr[t];
                    grad[t] += ys[t] * (ri[tt] * di + rj[tt] * dj);
                }
            }
        }
        if active.len() < n2 {
            reconstruct(&alpha, &mut grad, &active);
        }
        let sign = |t: usize| ys[t];
        // ρ from the free variables, else the middle of the feasible interval
        let (mut ub, mut lb, mut sum_free, mut n_free) =
            (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0usize);
        for t in 0..n2 {
            let yg = sign(t) * grad[t];
            if alpha[t] >= c {
                if sign(t) < 0.0 {
                    ub = ub.min(yg);
                } else {
                    lb = lb.max(yg);
                }
            } else if alpha[t] <= 0.0 {
                if sign(t) > 0.0 {
                    ub = ub.min(yg);
                } else {
                    lb = lb.max(yg);
                }
            } else {
                n_free += 1;
                sum_free += yg;
            }
        }
        let rho = if n_free > 0 {
            sum_free / n_free as f64
        } else {
            0.5 * (ub + lb)
        };
        let mut sv_rows = Vec::new();
        let mut coef = Vec::new();
        for r in 0..l {
            let b = alpha[r] - alpha[r + l];
            if b != 0.0 {
                sv_rows.push(r);
                coef.push(b);
            }
        }
        Ok(SvrModel {
            scaler,
            kernel: self.kernel,
            gamma,
            degree: self.degree,
            coef0: self.coef0,
            support: z.select_rows(&sv_rows),
            coef,
            rho,
            iterations: iter,
        })
    }
}

/// WSS3 working-set selection over the active variables (Fan, Chen & Lin 2005). Returns
/// `None` when the maximal violation is below `tol`.
#[allow(clippy::too_many_arguments)]
fn select_pair(
    active: &[usize],
    alpha: &[f64],
    grad: &[f64],
    ys: &[f64],
    kr: &[usize],
    qd: &[f64],
    kmat: &[f64],
    l: usize,
    c: f64,
    tol: f64,
) -> Option<(usize, usize)> {
    let mut gmax = f64::NEG_INFINITY;
    let mut i = usize::MAX;
    for &t in active {
        let up = if ys[t] > 0.0 {
            alpha[t] < c
        } else {
            alpha[t] > 0.0
        };
        if up {
            let v = -ys[t] * grad[t];
            if v >= gmax {
                gmax = v;
                i = t;
            }
        }
    }
    if i == usize::MAX {
        return None;
    }
    let ki = &kmat[kr[i] * l..(kr[i] + 1) * l];
    let mut gmax2 = f64::NEG_INFINITY;
    let mut j = usize::MAX;
    let mut obj_min = f64::INFINITY;
    for &t in active {
        let low = if ys[t] > 0.0 {
            alpha[t] > 0.0
        } else {
            alpha[t] < c
        };
        if !low {
            continue;
        }
        let v = ys[t] * grad[t];
        if v >= gmax2 {
            gmax2 = v;
        }
        let grad_diff = gmax + v;
        if grad_diff > 0.0 {
            // quad = Q_ii + Q_tt − 2 y_i y_t Q_it = K_ii + K_tt − 2 K_it
            let quad = qd[i] + qd[t] - 2.0 * ki[kr[t]];
            let obj = -(grad_diff * grad_diff) / if quad > 0.0 { quad } else { TAU };
            if obj <= obj_min {
                obj_min = obj;
                j = t;
            }
        }
    }
    if gmax + gmax2 < tol || j == usize::MAX {
        None
    } else {
        Some((i, j))
    }
}

/// Largest number of features a single-point prediction handles without allocating.
pub const MAX_FEATURES: usize = 32;

impl Predictor for SvrModel {
    #[inline]
    fn predict_one(&self, x: &[f64]) -> f64 {
        let p = x.len().min(MAX_FEATURES);
        let mut z = [0.0; MAX_FEATURES];
        z[..p].copy_from_slice(&x[..p]);
        self.scaler.transform_in_place(&mut z[..p]);
        let mut s = -self.rho;
        for (k, c) in self.coef.iter().enumerate() {
            s += c * kernel_value(
                self.kernel,
                self.gamma,
                self.degree,
                self.coef0,
                self.support.row(k),
                &z[..p],
            );
        }
        s
    }
}
