//! A dense row-major matrix of features (rows = samples).

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Matrix {
    pub n_rows: usize,
    pub n_cols: usize,
    /// Row-major values, `n_rows * n_cols`.
    pub data: Vec<f64>,
}

impl Matrix {
    pub fn new(n_rows: usize, n_cols: usize, data: Vec<f64>) -> Self {
        assert_eq!(data.len(), n_rows * n_cols, "matrix data length");
        Matrix {
            n_rows,
            n_cols,
            data,
        }
    }
    pub fn from_rows(rows: &[Vec<f64>]) -> Self {
        let n_cols = rows.first().map(|r| r.len()).unwrap_or(0);
        let data: Vec<f64> = rows.iter().flat_map(|r| r.iter().copied()).collect();
        Matrix::new(rows.len(), n_cols, data)
    }
    #[inline]
    pub fn row(&self, i: usize) -> &[f64] {
        &self.data[i * self.n_cols..(i + 1) * self.n_cols]
    }
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.data[i * self.n_cols + j]
    }
    pub fn column(&self, j: usize) -> Vec<f64> {
        (0..self.n_rows).map(|i| self.get(i, j)).collect()
    }
    /// The rows at `idx`, in that order.
    pub fn select_rows(&self, idx: &[usize]) -> Matrix {
        let mut data = Vec::with_capacity(idx.len() * self.n_cols);
        for &i in idx {
            data.extend_from_slice(self.row(i));
        }
        Matrix::new(idx.len(), self.n_cols, data)
    }
    /// Per-column (min, max).
    pub fn column_ranges(&self) -> Vec<(f64, f64)> {
        (0..self.n_cols)
            .map(|j| {
                (0..self.n_rows)
                    .map(|i| self.get(i, j))
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                        (a.min(v), b.max(v))
                    })
            })
            .collect()
    }
}

/// Per-column standardisation z = (x − mean) / std (population std, as scikit-learn's
/// `StandardScaler`; a constant column keeps scale 1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Standardizer {
    pub mean: Vec<f64>,
    pub scale: Vec<f64>,
}

impl Standardizer {
    pub fn fit(x: &Matrix) -> Self {
        let n = x.n_rows as f64;
        let mut mean = vec![0.0; x.n_cols];
        let mut scale = vec![0.0; x.n_cols];
        for j in 0..x.n_cols {
            let m = (0..x.n_rows).map(|i| x.get(i, j)).sum::<f64>() / n;
            let var = (0..x.n_rows)
                .map(|i| (x.get(i, j) - m).powi(2))
                .sum::<f64>()
                / n;
            mean[j] = m;
            scale[j] = if var > 0.0 { var.sqrt() } else { 1.0 };
        }
        Standardizer { mean, scale }
    }
    pub fn transform(&self, x: &Matrix) -> Matrix {
        let mut out = x.clone();
        for i in 0..x.n_rows {
            let r = &mut out.data[i * x.n_cols..(i + 1) * x.n_cols];
            self.transform_in_place(r);
        }
        out
    }
    #[inline]
    pub fn transform_in_place(&self, row: &mut [f64]) {
        for ((v, m), s) in row.iter_mut().zip(&self.mean).zip(&self.scale) {
            *v = (*v - m) / s;
        }
    }
}

/// Standardisation of a target vector (mean, population std).
pub fn standardize_target(y: &[f64]) -> (f64, f64) {
    let n = y.len() as f64;
    let m = y.iter().sum::<f64>() / n;
    let var = y.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n;
    (m, if var > 0.0 { var.sqrt() } else { 1.0 })
}
