//! The full-matrix SMO that `svr_smo` replaced, kept verbatim (test-only) as the reference
//! its iterates are compared with: the l × l kernel matrix computed up front and an l × 2l
//! copy with columns in working order.

use greybox_learn::svr_test_kit::{g_bar_change, kernel_row, Dual};
use greybox_model::svr::SvrParams;
use greybox_model::Matrix;

const TAU: f64 = 1e-12;

/// The dual by the full-matrix solver, in the original variable order.
pub fn solve(p: &SvrParams, z: &Matrix, y: &[f64], gamma: f64) -> Dual {
    let l = z.n_rows;
    let mut kmat = vec![0.0; l * l];
    for (i, row) in kmat.chunks_exact_mut(l.max(1)).enumerate() {
        kernel_row(p, gamma, z, i, row);
    }
    let n2 = 2 * l;
    let max_iter = p.max_iter.unwrap_or((100 * l).max(10_000_000));
    let mut smo = Smo::new(&kmat, l, p.c, p.tol, p.epsilon, y);
    let iterations = smo.solve(max_iter);
    let mut alpha = vec![0.0; n2];
    let mut grad = vec![0.0; n2];
    for t in 0..n2 {
        alpha[smo.orig[t]] = smo.alpha[t];
        grad[smo.orig[t]] = smo.grad[t];
    }
    Dual {
        alpha,
        grad,
        iterations,
    }
}

/// libsvm's SMO solver for the ε-SVR dual over 2l variables (variable t < l is α_t with
/// y_t = +1, t ≥ l is α*_{t−l} with y_t = −1; Q_st = y_s y_t K(s mod l, t mod l)).
/// Variables are kept in working order: the active (unshrunk) ones first, as in libsvm, so
/// every loop runs over contiguous memory.
struct Smo {
    /// Kernel rows with columns in working order: `kw[r * 2l + t] = K(r, t mod l)` for the
    /// variable at working position t, so that loops over the active set read contiguously.
    kw: Vec<f64>,
    l: usize,
    c: f64,
    tol: f64,
    alpha: Vec<f64>,
    grad: Vec<f64>,
    ys: Vec<f64>,
    kr: Vec<usize>,
    qd: Vec<f64>,
    lin: Vec<f64>,
    orig: Vec<usize>,
    /// t ∈ I_up (α_t can move up along y_t) and t ∈ I_low, kept in step with α.
    up: Vec<bool>,
    low: Vec<bool>,
    active: usize,
    /// Σ over the variables s at the upper bound of y_s K_ts C (libsvm's Ḡ).
    g_bar: Vec<f64>,
}

impl Smo {
    fn new(kmat: &[f64], l: usize, c: f64, tol: f64, epsilon: f64, y: &[f64]) -> Self {
        let n2 = 2 * l;
        let mut kw = vec![0.0; l * n2];
        for r in 0..l {
            let row = &kmat[r * l..(r + 1) * l];
            kw[r * n2..r * n2 + l].copy_from_slice(row);
            kw[r * n2 + l..(r + 1) * n2].copy_from_slice(row);
        }
        let kr: Vec<usize> = (0..n2).map(|t| t % l).collect();
        let lin: Vec<f64> = (0..n2)
            .map(|t| {
                if t < l {
                    epsilon - y[t]
                } else {
                    epsilon + y[t - l]
                }
            })
            .collect();
        Smo {
            kw,
            l,
            c,
            tol,
            alpha: vec![0.0; n2],
            grad: lin.clone(),
            ys: (0..n2).map(|t| if t < l { 1.0 } else { -1.0 }).collect(),
            qd: kr.iter().map(|&r| kmat[r * l + r]).collect(),
            kr,
            lin,
            orig: (0..n2).collect(),
            up: vec![false; n2],
            low: vec![false; n2],
            active: n2,
            g_bar: vec![0.0; n2],
        }
        .with_flags()
    }

    fn with_flags(mut self) -> Self {
        for t in 0..self.alpha.len() {
            self.set_flags(t);
        }
        self
    }

    #[inline]
    fn set_flags(&mut self, t: usize) {
        let (a, c) = (self.alpha[t], self.c);
        let pos = self.ys[t] > 0.0;
        self.up[t] = if pos { a < c } else { a > 0.0 };
        self.low[t] = if pos { a > 0.0 } else { a < c };
    }

    fn swap(&mut self, a: usize, b: usize) {
        self.alpha.swap(a, b);
        self.grad.swap(a, b);
        self.ys.swap(a, b);
        self.kr.swap(a, b);
        self.qd.swap(a, b);
        self.lin.swap(a, b);
        self.orig.swap(a, b);
        self.up.swap(a, b);
        self.low.swap(a, b);
        self.g_bar.swap(a, b);
        let n2 = self.alpha.len();
        for r in 0..self.l {
            self.kw.swap(r * n2 + a, r * n2 + b);
        }
    }

    #[inline]
    fn is_up(&self, t: usize) -> bool {
        self.up[t]
    }

    #[inline]
    fn is_low(&self, t: usize) -> bool {
        self.low[t]
    }

    /// K(t, ·) over the working positions.
    #[inline]
    fn row(&self, t: usize) -> &[f64] {
        let n2 = self.alpha.len();
        let r = self.kr[t];
        &self.kw[r * n2..(r + 1) * n2]
    }

    /// Recompute the gradients of the shrunk variables: G_t = p_t + y_t (Ḡ_t + Σ_s y_s K_ts
    /// α_s) over the free α_s.
    fn reconstruct(&mut self) {
        let n2 = self.alpha.len();
        let free: Vec<usize> = (0..n2)
            .filter(|&s| self.alpha[s] != 0.0 && self.alpha[s] < self.c)
            .collect();
        for t in self.active..n2 {
            let row = self.row(t);
            let g = free.iter().fold(self.g_bar[t], |acc, &s| {
                acc + self.ys[s] * row[s] * self.alpha[s]
            });
            self.grad[t] = self.lin[t] + self.ys[t] * g;
        }
        self.active = n2;
    }

    /// libsvm's shrinking: set aside bound variables that cannot enter the working set.
    fn shrink(&mut self, unshrunk: &mut bool) {
        let (mut g1, mut g2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
        for t in 0..self.active {
            if self.is_up(t) {
                g1 = g1.max(-self.ys[t] * self.grad[t]);
            }
            if self.is_low(t) {
                g2 = g2.max(self.ys[t] * self.grad[t]);
            }
        }
        if !*unshrunk && g1 + g2 <= self.tol * 10.0 {
            *unshrunk = true;
            self.reconstruct();
        }
        let be_shrunk = |s: &Self, t: usize| {
            let (a, yt, gt) = (s.alpha[t], s.ys[t], s.grad[t]);
            if a >= s.c {
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
            }
        };
        let mut t = 0;
        while t < self.active {
            if be_shrunk(self, t) {
                self.active -= 1;
                while self.active > t {
                    if !be_shrunk(self, self.active) {
                        self.swap(t, self.active);
                        break;
                    }
                    self.active -= 1;
                }
            }
            t += 1;
        }
    }

    /// The i of WSS3: argmax over I_up of −y_t G_t.
    fn select_i(&self) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for t in 0..self.active {
            if self.is_up(t) {
                let v = -self.ys[t] * self.grad[t];
                if best.is_none_or(|(g, _)| v >= g) {
                    best = Some((v, t));
                }
            }
        }
        best
    }

    /// The j of WSS3 (Fan, Chen & Lin 2005) for a given i; `None` at convergence: libsvm's
    /// argmin of −b²/a, here the argmax of b²/a, the last such t on ties.
    #[allow(clippy::needless_range_loop)] // t indexes five parallel arrays
    fn select_j(&self, gmax: f64, i: usize) -> Option<usize> {
        let ki = self.row(i);
        let qdi = self.qd[i];
        let mut gmax2 = f64::NEG_INFINITY;
        let mut j = None;
        // best candidate so far: b²/a maximised (libsvm minimises −b²/a), the last on ties
        let mut best = f64::NEG_INFINITY;
        for t in 0..self.active {
            if !self.low[t] {
                continue;
            }
            let v = self.ys[t] * self.grad[t];
            gmax2 = gmax2.max(v);
            let b = gmax + v;
            if b > 0.0 {
                // Q_ii + Q_tt − 2 y_i y_t Q_it = K_ii + K_tt − 2 K_it
                let quad = qdi + self.qd[t] - 2.0 * ki[t];
                let a = if quad > 0.0 { quad } else { TAU };
                let obj = b * b / a;
                if obj >= best {
                    best = obj;
                    j = Some(t);
                }
            }
        }
        if gmax + gmax2 < self.tol {
            None
        } else {
            j
        }
    }

    /// Two-variable update (libsvm `Solver::Solve`), then the gradient of the active set.
    /// Returns the next i candidate, found in the same pass.
    fn update(&mut self, i: usize, j: usize) -> Option<(f64, usize)> {
        let c = self.c;
        let (old_i, old_j) = (self.alpha[i], self.alpha[j]);
        let kij = self.row(i)[j];
        let quad = self.qd[i] + self.qd[j] - 2.0 * kij;
        let quad = if quad > 0.0 { quad } else { TAU };
        let (mut ai, mut aj) = (old_i, old_j);
        if self.ys[i] != self.ys[j] {
            let delta = (-self.grad[i] - self.grad[j]) / quad;
            let diff = ai - aj;
            ai += delta;
            aj += delta;
            if diff > 0.0 {
                if aj < 0.0 {
                    aj = 0.0;
                    ai = diff;
                }
            } else if ai < 0.0 {
                ai = 0.0;
                aj = -diff;
            }
            if diff > 0.0 {
                if ai > c {
                    ai = c;
                    aj = c - diff;
                }
            } else if aj > c {
                aj = c;
                ai = c + diff;
            }
        } else {
            let delta = (self.grad[i] - self.grad[j]) / quad;
            let sum = ai + aj;
            ai -= delta;
            aj += delta;
            if sum > c {
                if ai > c {
                    ai = c;
                    aj = sum - c;
                }
            } else if aj < 0.0 {
                aj = 0.0;
                ai = sum;
            }
            if sum > c {
                if aj > c {
                    aj = c;
                    ai = sum - c;
                }
            } else if ai < 0.0 {
                ai = 0.0;
                aj = sum;
            }
        }
        self.alpha[i] = ai;
        self.alpha[j] = aj;
        self.set_flags(i);
        self.set_flags(j);
        let n2 = self.alpha.len();
        for (t, old) in [(i, old_i), (j, old_j)] {
            if let Some(term) = g_bar_change(old, self.alpha[t], c, self.ys[t]) {
                let r0 = self.kr[t] * n2;
                for (g, k) in self.g_bar.iter_mut().zip(&self.kw[r0..r0 + n2]) {
                    *g += term * k;
                }
            }
        }
        let (di, dj) = ((ai - old_i) * self.ys[i], (aj - old_j) * self.ys[j]);
        let (ri0, rj0) = (self.kr[i] * n2, self.kr[j] * n2);
        let act = self.active;
        let ri = &self.kw[ri0..ri0 + act];
        let rj = &self.kw[rj0..rj0 + act];
        let mut best: Option<(f64, usize)> = None;
        for (t, (((g, yt), up), (ki, kj))) in self.grad[..act]
            .iter_mut()
            .zip(&self.ys[..act])
            .zip(&self.up[..act])
            .zip(ri.iter().zip(rj))
            .enumerate()
        {
            *g += yt * (ki * di + kj * dj);
            if *up {
                let v = -yt * *g;
                if best.is_none_or(|(b, _)| v >= b) {
                    best = Some((v, t));
                }
            }
        }
        best
    }

    /// Run SMO until the maximal violation is below `tol`; returns the iterations used.
    fn solve(&mut self, max_iter: usize) -> usize {
        let n2 = self.alpha.len();
        let mut unshrunk = false;
        let period = self.l.min(1000);
        let mut counter = period;
        let mut next_i = self.select_i();
        let mut iter = 0;
        while iter < max_iter {
            counter -= 1;
            if counter == 0 {
                counter = period;
                self.shrink(&mut unshrunk);
                next_i = self.select_i();
            }
            let mut pair = next_i.and_then(|(g, i)| self.select_j(g, i).map(|j| (i, j)));
            if pair.is_none() && self.active < n2 {
                self.reconstruct();
                next_i = self.select_i();
                pair = next_i.and_then(|(g, i)| self.select_j(g, i).map(|j| (i, j)));
                counter = 1;
            }
            let Some((i, j)) = pair else { break };
            iter += 1;
            next_i = self.update(i, j);
        }
        if self.active < n2 {
            self.reconstruct();
        }
        iter
    }
}
