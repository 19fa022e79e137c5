//! Kernel rows for SVR training (`svr_smo`): K(r, s) for every s in one call, so that the
//! rbf's exp and the sigmoid's tanh run over the whole row in vectorised arithmetic
//! ([`crate::fast_math`], within a few ulp of libm) instead of a libm call per element,
//! built for AVX-512 or AVX2 where the processor has them (picked at run time; the same
//! operations without fused multiply–add, so the same bits on every path).
//! Training only: a fitted model predicts with `greybox_model::svr::kernel_value` (libm),
//! as scikit-learn does.
//!
//! Each element is computed as the full kernel matrix had it: K(r, s) from (row r, row s)
//! for s ≤ r and from (row s, row r) above the diagonal, so row r and column r agree bit
//! for bit whatever the kernel's arithmetic.

use crate::fast_math::{exp_nonpositive_in_place, tanh_in_place};
use greybox_model::svr::{dot, kernel_value, Kernel, SvrParams};
use greybox_model::Matrix;

/// Row r of the kernel matrix of the standardised rows `z` into `row` (length z.n_rows).
pub fn kernel_row(p: &SvrParams, gamma: f64, z: &Matrix, r: usize, row: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has AVX-512F (checked above)
            return unsafe { kernel_row_avx512(p, gamma, z, r, row) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked above)
            return unsafe { kernel_row_avx2(p, gamma, z, r, row) };
        }
    }
    kernel_row_portable(p, gamma, z, r, row)
}

/// [`kernel_row`] compiled for AVX2: the same operations (no fused multiply–add), so the
/// same bits as the portable build.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn kernel_row_avx2(p: &SvrParams, gamma: f64, z: &Matrix, r: usize, row: &mut [f64]) {
    kernel_row_portable(p, gamma, z, r, row)
}

/// [`kernel_row`] compiled for AVX-512 (eight lanes), the same bits as the portable build.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn kernel_row_avx512(p: &SvrParams, gamma: f64, z: &Matrix, r: usize, row: &mut [f64]) {
    kernel_row_portable(p, gamma, z, r, row)
}

#[inline(always)]
fn kernel_row_portable(p: &SvrParams, gamma: f64, z: &Matrix, r: usize, row: &mut [f64]) {
    let pairs = (0..row.len()).map(|s| {
        if s <= r {
            (z.row(r), z.row(s))
        } else {
            (z.row(s), z.row(r))
        }
    });
    kernel_values(p, gamma, pairs, row);
}

/// The diagonal K(r, r) of the kernel matrix, equal bit for bit to the rows' diagonals.
pub(crate) fn kernel_diagonal(p: &SvrParams, gamma: f64, z: &Matrix) -> Vec<f64> {
    let mut d = vec![0.0; z.n_rows];
    kernel_values(
        p,
        gamma,
        (0..z.n_rows).map(|r| (z.row(r), z.row(r))),
        &mut d,
    );
    d
}

/// K(a, b) of each pair into `out`: the arguments first, then the rbf's exp or the
/// sigmoid's tanh over all of them.
#[inline(always)]
fn kernel_values<'z>(
    p: &SvrParams,
    gamma: f64,
    pairs: impl Iterator<Item = (&'z [f64], &'z [f64])>,
    out: &mut [f64],
) {
    match p.kernel {
        Kernel::Rbf => {
            for (v, (a, b)) in out.iter_mut().zip(pairs) {
                *v = -gamma * squared_distance(a, b);
            }
            exp_nonpositive_in_place(out);
        }
        Kernel::Sigmoid => {
            for (v, (a, b)) in out.iter_mut().zip(pairs) {
                *v = gamma * dot(a, b) + p.coef0;
            }
            tanh_in_place(out);
        }
        Kernel::Linear | Kernel::Poly => {
            for (v, (a, b)) in out.iter_mut().zip(pairs) {
                *v = kernel_value(p.kernel, gamma, p.degree, p.coef0, a, b);
            }
        }
    }
}

/// ‖a − b‖², summed in feature order as `kernel_value` sums it.
#[inline(always)]
fn squared_distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows agree with libm's kernel within a few ulp, are symmetric bit for bit, and the
    /// diagonal is the rows' diagonal; the dispatched build (AVX-512 where the processor has
    /// it), AVX2 and the portable build give the same bits.
    #[test]
    fn rows_are_the_kernel_matrix() {
        let n = 40;
        let z = Matrix::new(
            n,
            2,
            (0..2 * n)
                .map(|i| ((i * 37 % 23) as f64 - 11.0) * 0.31)
                .collect(),
        );
        for kernel in [Kernel::Rbf, Kernel::Sigmoid, Kernel::Poly, Kernel::Linear] {
            let p = SvrParams {
                kernel,
                degree: 3,
                coef0: 0.5,
                ..SvrParams::default()
            };
            let gamma = 0.7;
            let rows: Vec<Vec<f64>> = (0..n)
                .map(|r| {
                    let mut row = vec![0.0; n];
                    kernel_row(&p, gamma, &z, r, &mut row);
                    let mut portable = vec![0.0; n];
                    kernel_row_portable(&p, gamma, &z, r, &mut portable);
                    assert_eq!(row, portable, "{kernel:?} row {r}");
                    #[cfg(target_arch = "x86_64")]
                    if std::arch::is_x86_feature_detected!("avx2") {
                        let mut avx2 = vec![0.0; n];
                        // SAFETY: the processor has AVX2 (checked above)
                        unsafe { kernel_row_avx2(&p, gamma, &z, r, &mut avx2) };
                        assert_eq!(avx2, portable, "{kernel:?} row {r}, AVX2");
                    }
                    row
                })
                .collect();
            let diag = kernel_diagonal(&p, gamma, &z);
            for r in 0..n {
                assert_eq!(
                    diag[r].to_bits(),
                    rows[r][r].to_bits(),
                    "{kernel:?} diagonal {r}"
                );
                for (s, &v) in rows[r].iter().enumerate() {
                    assert_eq!(v.to_bits(), rows[s][r].to_bits(), "{kernel:?} ({r}, {s})");
                    let libm = kernel_value(kernel, gamma, 3, 0.5, z.row(r), z.row(s));
                    let scale = libm.abs().max(1e-300);
                    assert!(
                        (v - libm).abs() <= 8.0 * f64::EPSILON * scale,
                        "{kernel:?} ({r}, {s}): {v} against {libm}"
                    );
                }
            }
        }
    }
}
