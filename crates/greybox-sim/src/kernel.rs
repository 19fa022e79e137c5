//! The 2D cubic-spline kernel (Monaghan & Lattanzio, A&A 149, 1985), support radius 2h:
//!
//! W(q) = σ (1 − 1.5 q² + 0.75 q³) for 0 ≤ q < 1, σ/4 (2 − q)³ for 1 ≤ q < 2, 0 beyond,
//! with q = r/h and σ = 10/(7π h²).

/// Cubic-spline kernel with a fixed smoothing length.
#[derive(Debug, Clone, Copy)]
pub struct CubicSpline {
    /// Smoothing length h, m.
    pub h: f64,
    inv_h: f64,
    sigma: f64,
}

impl CubicSpline {
    pub fn new(h: f64) -> Self {
        CubicSpline {
            h,
            inv_h: 1.0 / h,
            sigma: 10.0 / (7.0 * std::f64::consts::PI * h * h),
        }
    }

    /// Support radius 2h, m.
    #[inline]
    pub fn radius(&self) -> f64 {
        2.0 * self.h
    }

    /// W(r), 1/m².
    #[inline]
    pub fn w(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        if q < 1.0 {
            self.sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q)
        } else if q < 2.0 {
            let t = 2.0 - q;
            0.25 * self.sigma * t * t * t
        } else {
            0.0
        }
    }

    /// (1/r) dW/dr, 1/m⁴: the gradient is ∇_i W_ij = (x_i − x_j) · this.
    #[inline]
    pub fn dw_over_r(&self, r: f64) -> f64 {
        let q = r * self.inv_h;
        let s = self.sigma * self.inv_h * self.inv_h;
        if q < 1.0 {
            s * (-3.0 + 2.25 * q)
        } else if q < 2.0 {
            let t = 2.0 - q;
            -0.75 * s * t * t / q
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ W dA = 1 and the gradient equals the finite difference of W.
    #[test]
    fn normalised_and_consistent() {
        let k = CubicSpline::new(1.5e-5);
        let n = 4000;
        let dr = k.radius() / n as f64;
        let integral: f64 = (0..n)
            .map(|i| {
                let r = (i as f64 + 0.5) * dr;
                2.0 * std::f64::consts::PI * r * k.w(r) * dr
            })
            .sum();
        assert!((integral - 1.0).abs() < 1e-6, "{integral}");
        for r in [0.3e-5, 1.4e-5, 2.2e-5, 2.9e-5] {
            let fd = (k.w(r + 1e-10) - k.w(r - 1e-10)) / 2e-10;
            assert!((fd - k.dw_over_r(r) * r).abs() < 1e-6 * fd.abs(), "{r}");
        }
    }
}
