//! ε-support vector regression with libsvm's semantics (Chang & Lin, "LIBSVM: a library for
//! support vector machines", ACM TIST 2011): the dual over 2l variables solved by SMO with
//! second-order working-set selection (Fan, Chen & Lin, JMLR 6, 2005, WSS3), stopping when
//! the maximal violation is below `tol` (1e-3). Kernels: linear ⟨x,x'⟩, poly (γ⟨x,x'⟩+c0)^d,
//! rbf exp(−γ‖x−x'‖²), sigmoid tanh(γ⟨x,x'⟩+c0); γ = 'scale' = 1 / (p · Var(X)) as in
//! scikit-learn. Inputs are standardised inside the model; the target is not.
//!
//! Fitting is in `greybox-learn` (`svr.rs`): SMO with libsvm's shrinking heuristic and a
//! bounded cache of kernel rows for the rbf and sigmoid kernels (no row limit), an exact
//! interior-point solve in feature space for the linear and polynomial kernels.

use crate::matrix::Standardizer;
use crate::predictor::Predictor;
use crate::Matrix;
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
    /// The kernel's name (its [`Choice`](greybox_core::choice::Choice) name).
    pub fn name(self) -> &'static str {
        greybox_core::choice::Choice::name(self)
    }
}

greybox_core::choice!(
    Kernel,
    "svr.kernel",
    [Linear => "linear", Poly => "poly", Rbf => "rbf", Sigmoid => "sigmoid"],
    text
);

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
    /// How the dual is solved (absent in files: `auto`).
    #[serde(skip_serializing_if = "SvrSolver::is_auto")]
    pub solver: SvrSolver,
}

/// The solver of the ε-SVR dual.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SvrSolver {
    /// Exactly by an interior-point method in feature space for kernels with a small explicit
    /// feature map (linear; polynomial with c₀ ≥ 0), SMO for the others.
    #[default]
    Auto,
    /// SMO for every kernel (libsvm's route, to its stopping tolerance).
    Smo,
}

impl SvrSolver {
    fn is_auto(&self) -> bool {
        *self == SvrSolver::Auto
    }
}

impl SvrParams {
    /// The grid-relevant values, e.g. `kernel=rbf, C=10, epsilon=0.1`.
    pub fn label(&self) -> String {
        format!(
            "kernel={}, C={}, epsilon={}",
            self.kernel.name(),
            self.c,
            self.epsilon
        )
    }
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
            solver: SvrSolver::Auto,
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

/// K(a, b) for the kernel and its parameters.
#[inline]
pub fn kernel_value(k: Kernel, gamma: f64, degree: u32, coef0: f64, a: &[f64], b: &[f64]) -> f64 {
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
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
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
