//! Calibration of a friction model on a material's calibration conditions: the constant
//! μ\* of Coulomb friction, generalised to a factor on any law's μ.
//!
//! Every friction model is a law shape times a factor s on its μ: Coulomb is μ = s (the
//! shape μ ≡ 1, s searched over `mu_bracket`); a law file is its own shape; a calibrated law
//! has shapes on a grid of its named numeric fields (e.g. the exponent b of μ(v) =
//! μ_ref (v/v_ref)^b), and its level is the factor.
//!
//! Per shape, the calibration conditions are cut at the two ends of the factor's bracket;
//! per condition the F'f error is interpolated linearly in s, and s\* is where the mean
//! signed error over the conditions is zero (the end of the bracket nearest to that, when
//! it lies outside). F'f is seldom linear in μ over a wide bracket, so a material may ask
//! for `refine` steps: the conditions are cut again at s\*, the errors become piecewise
//! linear through every factor cut, and s\* is found again (regula falsi). The shape kept is
//! the one whose interpolated errors at its s\* have the least mean square,
//! J = mean_i e_i(s\*)² — a shape that follows the trend of the measurements across speeds
//! and thicknesses, where a level alone cannot. Every condition is then cut with the kept
//! shape at its s\*, the calibration ones included, so that their errors are simulated,
//! not interpolated.
//!
//! Each step is one parallel batch of every model's cuts; the fitted fields are resolved
//! to their grid's spacing.

use super::cut::Cut;
use serde::Serialize;

/// The errors of the calibration conditions at the factors cut so far (the bracket ends and
/// any refinements), piecewise linear in the factor between them.
#[derive(Debug, Clone)]
pub struct FactorErrors {
    /// (factor, each condition's F'f error), sorted by factor.
    points: Vec<(f64, Vec<f64>)>,
}

impl FactorErrors {
    /// The errors at the bracket ends.
    pub fn new([lo, hi]: [f64; 2], at_lo: Vec<f64>, at_hi: Vec<f64>) -> Self {
        FactorErrors {
            points: vec![(lo, at_lo), (hi, at_hi)],
        }
    }

    /// Adds the errors at factor `s`.
    pub fn add(&mut self, s: f64, errors: Vec<f64>) {
        let k = self.points.partition_point(|p| p.0 < s);
        self.points.insert(k, (s, errors));
    }

    fn mean(errors: &[f64]) -> f64 {
        errors.iter().sum::<f64>() / errors.len().max(1) as f64
    }

    /// s\*: where the mean error, piecewise linear in the factor, first crosses zero (the
    /// end of the bracket nearest to that, when it does not; the bracket's middle when the
    /// mean is flat).
    pub fn zero(&self) -> f64 {
        let means: Vec<(f64, f64)> = self
            .points
            .iter()
            .map(|(s, e)| (*s, Self::mean(e)))
            .collect();
        for w in means.windows(2) {
            let ((s0, m0), (s1, m1)) = (w[0], w[1]);
            if m0 == 0.0 {
                return s0;
            }
            if (m0 < 0.0) != (m1 < 0.0) || m1 == 0.0 {
                return s0 + (s1 - s0) * (0.0 - m0) / (m1 - m0);
            }
        }
        let (first, last) = (means[0], means[means.len() - 1]);
        if first.1 == last.1 {
            0.5 * (first.0 + last.0)
        } else if first.1.abs() < last.1.abs() {
            first.0
        } else {
            last.0
        }
    }

    /// J at `s`: the mean square of the conditions' errors, each piecewise linear in the
    /// factor.
    pub fn objective(&self, s: f64) -> f64 {
        let k = self
            .points
            .windows(2)
            .position(|w| s <= w[1].0)
            .unwrap_or(self.points.len() - 2);
        let ((s0, e0), (s1, e1)) = (&self.points[k], &self.points[k + 1]);
        let t = if s1 > s0 { (s - s0) / (s1 - s0) } else { 0.0 };
        e0.iter()
            .zip(e1)
            .map(|(a, b)| (a + t * (b - a)).powi(2))
            .sum::<f64>()
            / e0.len().max(1) as f64
    }

    /// Whether `s` was cut already (a refinement there adds nothing).
    pub fn has(&self, s: f64) -> bool {
        self.points
            .iter()
            .any(|p| (p.0 - s).abs() <= 1e-12 * s.abs().max(1.0))
    }
}

/// The relative F'f error of a cut against the measured feed force (N/mm).
pub fn feed_error(cut: &Cut, measured_n_per_mm: f64) -> f64 {
    cut.feed_force_n_per_mm / measured_n_per_mm - 1.0
}

/// One shape of a calibrated law: its fields' values, its s\* and interpolated J.
#[derive(Debug, Clone, Serialize)]
pub struct ShapeFit {
    pub values: Vec<f64>,
    pub factor: f64,
    pub objective: f64,
}

/// The shape of least J (the first of equal ones).
pub fn best_shape(shapes: &[ShapeFit]) -> Option<&ShapeFit> {
    shapes
        .iter()
        .reduce(|a, b| if b.objective < a.objective { b } else { a })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two(lo: [f64; 2], hi: [f64; 2]) -> FactorErrors {
        FactorErrors::new([0.2, 0.8], lo.to_vec(), hi.to_vec())
    }

    #[test]
    fn the_factor_is_where_the_mean_error_line_crosses_zero() {
        // Mean error −0.2 at 0.2 and +0.4 at 0.8: zero at 0.2 + 0.6 · 0.2/0.6 = 0.4.
        let f = two([-0.3, -0.1], [0.5, 0.3]);
        assert!((f.zero() - 0.4).abs() < 1e-15);
        // there the errors are −0.3 + 0.8/3 and −0.1 + 0.4/3: J = their mean square
        let (a, b) = (-0.3 + 0.8 / 3.0, -0.1 + 0.4 / 3.0);
        assert!((f.objective(0.4) - (a * a + b * b) / 2.0).abs() < 1e-15);
        // Outside the bracket: its nearer end; flat: its middle.
        assert_eq!(two([0.1, 0.1], [0.3, 0.3]).zero(), 0.2);
        assert_eq!(two([-0.5, -0.5], [-0.1, -0.1]).zero(), 0.8);
        assert_eq!(two([0.1, 0.1], [0.1, 0.1]).zero(), 0.5);
    }

    #[test]
    fn a_refinement_makes_the_errors_piecewise_linear_through_it() {
        // convex: mean −0.2 at 0.2, −0.1 at 0.4 (refined), +0.4 at 0.8
        let mut f = two([-0.3, -0.1], [0.5, 0.3]);
        f.add(0.4, vec![-0.15, -0.05]);
        assert!(f.has(0.4) && !f.has(0.5));
        // zero between 0.4 and 0.8: 0.4 + 0.4 · 0.1/0.5 = 0.48
        assert!((f.zero() - 0.48).abs() < 1e-12);
        let t = 0.2;
        let (a, b) = (-0.15 + t * 0.65, -0.05 + t * 0.35);
        assert!((f.objective(0.48) - (a * a + b * b) / 2.0).abs() < 1e-12);
    }

    #[test]
    fn the_best_shape_has_the_least_objective() {
        let s = |o: f64| ShapeFit {
            values: vec![o],
            factor: 1.0,
            objective: o,
        };
        let shapes = [s(0.3), s(0.1), s(0.1), s(0.2)];
        assert_eq!(best_shape(&shapes).unwrap().values, vec![0.1]);
        assert!(best_shape(&[]).is_none());
    }
}
