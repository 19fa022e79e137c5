//! ε-support vector regression with libsvm's semantics (Chang & Lin, "LIBSVM: a library for
//! support vector machines", ACM TIST 2011): the dual over 2l variables solved by SMO with
//! second-order working-set selection (Fan, Chen & Lin, JMLR 6, 2005, WSS3), stopping when
//! the maximal violation is below `tol` (1e-3). Kernels: linear ⟨x,x'⟩, poly (γ⟨x,x'⟩+c0)^d,
//! rbf exp(−γ‖x−x'‖²), sigmoid tanh(γ⟨x,x'⟩+c0); γ = 'scale' = 1 / (p · Var(X)) as in
//! scikit-learn. Inputs are standardised inside the model; the target is not.
//!
//! The rbf and sigmoid kernels are solved by SMO (`svr_smo.rs`) with libsvm's
//! shrinking heuristic and kernel rows computed on demand into a least-recently-used cache of
//! [`KERNEL_CACHE_BYTES`]: memory is O(l) plus the cache, so there is no row limit. The linear
//! and polynomial kernels are solved exactly in their small feature space
//! ([`crate::svr_lowrank`]).

use crate::regressor::{GridSearch, Regressor};
use greybox_core::{Error, Result};
use greybox_model::matrix::Standardizer;
use greybox_model::svr::{Kernel, SvrModel, SvrParams, SvrSolver};
use greybox_model::Matrix;
use serde::{Deserialize, Serialize};

/// Memory for the kernel rows SMO keeps between iterations (each row K(r, ·) takes 8 l bytes;
/// a row that does not fit is recomputed when needed). When the whole kernel matrix fits, it
/// is computed once, row by row as SMO asks for it.
pub const KERNEL_CACHE_BYTES: usize = 512 << 20;

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
        let model = if self.solver == SvrSolver::Smo {
            None
        } else {
            fit_low_rank(self, &z, y, gamma)
        };
        let model = model.unwrap_or_else(|| fit_smo(self, &z, y, gamma));
        Ok(SvrModel { scaler, ..model })
    }
}

/// libsvm's route: SMO on the dual (any kernel), kernel rows cached. The scaler of the
/// returned model is a placeholder.
fn fit_smo(p: &SvrParams, z: &Matrix, y: &[f64], gamma: f64) -> SvrModel {
    let l = z.n_rows;
    let n2 = 2 * l;
    let c = p.c;
    let crate::svr_smo::Dual {
        alpha,
        grad,
        iterations: iter,
    } = crate::svr_smo::solve(p, z, y, gamma, KERNEL_CACHE_BYTES);
    let sign = |t: usize| if t < l { 1.0 } else { -1.0 };
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
    SvrModel {
        scaler: Standardizer {
            mean: Vec::new(),
            scale: Vec::new(),
        },
        kernel: p.kernel,
        gamma,
        degree: p.degree,
        coef0: p.coef0,
        support: z.select_rows(&sv_rows),
        coef,
        rho,
        iterations: iter,
    }
}

/// Kernels with a small explicit feature map (linear; polynomial with c₀ ≥ 0) solved exactly
/// in feature space ([`crate::svr_lowrank`]); `None` for the other kernels, or when the
/// interior-point method does not converge (then SMO solves it). The scaler of the returned
/// model is a placeholder.
fn fit_low_rank(p: &SvrParams, z: &Matrix, y: &[f64], gamma: f64) -> Option<SvrModel> {
    use crate::svr_lowrank::{solve, FeatureMap};
    let map = match p.kernel {
        Kernel::Linear => FeatureMap::new(z.n_cols, None)?,
        Kernel::Poly => FeatureMap::new(z.n_cols, Some((gamma, p.coef0, p.degree)))?,
        Kernel::Rbf | Kernel::Sigmoid => return None,
    };
    let dim = map.dimension();
    let mut phi = vec![0.0; z.n_rows * dim];
    for r in 0..z.n_rows {
        map.apply(z.row(r), &mut phi[r * dim..(r + 1) * dim]);
    }
    let sol = solve(&phi, dim, y, p.c, p.epsilon)?;
    let rows: Vec<usize> = (0..z.n_rows).filter(|&r| sol.beta[r] != 0.0).collect();
    Some(SvrModel {
        scaler: Standardizer {
            mean: Vec::new(),
            scale: Vec::new(),
        },
        kernel: p.kernel,
        gamma,
        degree: p.degree,
        coef0: p.coef0,
        support: z.select_rows(&rows),
        coef: rows.iter().map(|&r| sol.beta[r]).collect(),
        rho: -sol.bias,
        iterations: sol.iterations,
    })
}

/// SVR grid (article: C ∈ {0.1, 1, 10, 100} × 4 kernels × ε ∈ {0.01, 0.1, 0.2, 0.5}).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SvrGrid {
    pub base: SvrParams,
    pub c: Vec<f64>,
    pub kernel: Vec<Kernel>,
    pub epsilon: Vec<f64>,
}

impl Default for SvrGrid {
    fn default() -> Self {
        SvrGrid {
            base: SvrParams::default(),
            c: vec![0.1, 1.0, 10.0, 100.0],
            kernel: vec![Kernel::Linear, Kernel::Poly, Kernel::Rbf, Kernel::Sigmoid],
            epsilon: vec![0.01, 0.1, 0.2, 0.5],
        }
    }
}

impl GridSearch for SvrParams {
    type Grid = SvrGrid;
    /// Kernels outermost, then C, then ε.
    fn candidates(grid: &SvrGrid) -> Vec<Self> {
        let mut out = Vec::new();
        for &kernel in &grid.kernel {
            for &c in &grid.c {
                for &epsilon in &grid.epsilon {
                    out.push(SvrParams {
                        kernel,
                        c,
                        epsilon,
                        ..grid.base.clone()
                    });
                }
            }
        }
        out
    }
}
