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
//!
//! **How sure the calibration is.** Every calibration cut's F'f carries its standard error
//! (the batch means of its steady state, [`greybox_sim::steady`]). The calibration is
//! repeated on [`DRAWS`] parametric-bootstrap replicates (Efron & Tibshirani 1993, §6.5):
//! each error drawn from a normal around it with its cut's standard error, the cuts
//! independent of each other, a fixed seed. The 2.5 and 97.5 % quantiles of the replicates'
//! s\* are each shape's factor interval, and the share of replicates in which a shape has
//! the least J says whether the shape kept is decided by the cuts or by their scatter.

use super::cut::Cut;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::Serialize;

/// Parametric-bootstrap replicates of a calibration.
pub const DRAWS: usize = 2000;
/// Their seed (the same calibration gives the same intervals).
const SEED: u64 = 0x6772_6579_626f_78;

/// The F'f errors of the calibration conditions at one factor, with their standard errors
/// (`None`: the cut could not say how sure it is).
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorsAt {
    pub errors: Vec<f64>,
    pub se: Vec<Option<f64>>,
}

/// The errors of the calibration conditions at the factors cut so far (the bracket ends and
/// any refinements), piecewise linear in the factor between them.
#[derive(Debug, Clone)]
pub struct FactorErrors {
    /// (factor, the errors there), sorted by factor.
    points: Vec<(f64, ErrorsAt)>,
}

impl FactorErrors {
    /// The errors at the bracket ends.
    pub fn new([lo, hi]: [f64; 2], at_lo: ErrorsAt, at_hi: ErrorsAt) -> Self {
        FactorErrors {
            points: vec![(lo, at_lo), (hi, at_hi)],
        }
    }

    /// Adds the errors at factor `s`.
    pub fn add(&mut self, s: f64, errors: ErrorsAt) {
        let k = self.points.partition_point(|p| p.0 < s);
        self.points.insert(k, (s, errors));
    }

    /// One replicate: every error drawn from a normal around it with its standard error
    /// (`None` when one is unknown).
    fn replicate(&self, rng: &mut ChaCha8Rng) -> Option<FactorErrors> {
        let mut points = Vec::with_capacity(self.points.len());
        for (s, at) in &self.points {
            let mut errors = Vec::with_capacity(at.errors.len());
            for (e, se) in at.errors.iter().zip(&at.se) {
                let z: f64 = StandardNormal.sample(rng);
                errors.push(e + (*se)? * z);
            }
            points.push((
                *s,
                ErrorsAt {
                    errors,
                    se: at.se.clone(),
                },
            ));
        }
        Some(FactorErrors { points })
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
            .map(|(s, e)| (*s, Self::mean(&e.errors)))
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
        let (e0, e1) = (&e0.errors, &e1.errors);
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

/// One shape of a calibrated law: its fields' values, its s\* and interpolated J, and how
/// sure they are.
#[derive(Debug, Clone, Serialize)]
pub struct ShapeFit {
    pub values: Vec<f64>,
    pub factor: f64,
    pub objective: f64,
    /// The 95 % interval of s\* from the bootstrap replicates (`None`: a calibration cut
    /// could not say how sure it is).
    pub factor_ci95: Option<[f64; 2]>,
    /// The share of replicates in which this shape has the least J.
    pub kept_share: Option<f64>,
}

/// Every shape fitted at its s\*, with the bootstrap's intervals and kept shares
/// (module docs).
pub fn fit_shapes(shapes: &[Vec<f64>], searches: &[FactorErrors]) -> Vec<ShapeFit> {
    let mut fits: Vec<ShapeFit> = shapes
        .iter()
        .zip(searches)
        .map(|(values, f)| {
            let factor = f.zero();
            ShapeFit {
                values: values.clone(),
                factor,
                objective: f.objective(factor),
                factor_ci95: None,
                kept_share: None,
            }
        })
        .collect();
    let mut rng = ChaCha8Rng::seed_from_u64(SEED);
    let mut factors: Vec<Vec<f64>> = vec![Vec::with_capacity(DRAWS); searches.len()];
    let mut kept = vec![0usize; searches.len()];
    for _ in 0..DRAWS {
        let Some(replicates) = searches
            .iter()
            .map(|f| f.replicate(&mut rng))
            .collect::<Option<Vec<_>>>()
        else {
            return fits;
        };
        let zeros: Vec<f64> = replicates.iter().map(FactorErrors::zero).collect();
        let best = replicates
            .iter()
            .zip(&zeros)
            .map(|(f, z)| f.objective(*z))
            .enumerate()
            .reduce(|a, b| if b.1 < a.1 { b } else { a })
            .map_or(0, |b| b.0);
        kept[best] += 1;
        for (k, z) in zeros.into_iter().enumerate() {
            factors[k].push(z);
        }
    }
    for ((fit, mut f), n) in fits.iter_mut().zip(factors).zip(kept) {
        f.sort_by(f64::total_cmp);
        let q = |p: f64| f[((f.len() - 1) as f64 * p).round() as usize];
        fit.factor_ci95 = Some([q(0.025), q(0.975)]);
        fit.kept_share = Some(n as f64 / DRAWS as f64);
    }
    fits
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

    fn at(e: &[f64], se: f64) -> ErrorsAt {
        ErrorsAt {
            errors: e.to_vec(),
            se: vec![Some(se); e.len()],
        }
    }

    fn two(lo: [f64; 2], hi: [f64; 2]) -> FactorErrors {
        FactorErrors::new([0.2, 0.8], at(&lo, 0.0), at(&hi, 0.0))
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
        f.add(0.4, at(&[-0.15, -0.05], 0.0));
        assert!(f.has(0.4) && !f.has(0.5));
        // zero between 0.4 and 0.8: 0.4 + 0.4 · 0.1/0.5 = 0.48
        assert!((f.zero() - 0.48).abs() < 1e-12);
        let t = 0.2;
        let (a, b) = (-0.15 + t * 0.65, -0.05 + t * 0.35);
        assert!((f.objective(0.48) - (a * a + b * b) / 2.0).abs() < 1e-12);
    }

    #[test]
    fn the_factor_interval_follows_the_scatter_of_the_cuts() {
        // mean error m0 = −0.2 at 0.2 and m1 = +0.4 at 0.8 (s* = 0.4); each error ±0.03 (one
        // σ), two conditions: each mean ±0.03/√2. s* = (s0 m1 − s1 m0)/(m1 − m0), so
        // ∂s*/∂m0 = −m1 Δs/Δm² = −2/3, ∂s*/∂m1 = m0 Δs/Δm² = −1/3, σ(s*) = 0.0158 and the
        // 95 % interval ≈ 0.4 ± 0.031 (delta method)
        let f = FactorErrors::new([0.2, 0.8], at(&[-0.3, -0.1], 0.03), at(&[0.5, 0.3], 0.03));
        let fits = fit_shapes(&[vec![]], &[f]);
        let [lo, hi] = fits[0].factor_ci95.expect("an interval");
        assert!((fits[0].factor - 0.4).abs() < 1e-12);
        assert!(
            (lo - 0.369).abs() < 0.006 && (hi - 0.431).abs() < 0.006,
            "{lo} {hi}"
        );
        assert_eq!(fits[0].kept_share, Some(1.0));
        // without standard errors: no interval
        let g = two([-0.3, -0.1], [0.5, 0.3]);
        let mut unknown = g.clone();
        unknown.points[0].1.se[0] = None;
        assert_eq!(fit_shapes(&[vec![]], &[unknown])[0].factor_ci95, None);
        // two shapes whose J differ by less than the scatter share the replicates
        let near = FactorErrors::new([0.2, 0.8], at(&[-0.31, -0.1], 0.05), at(&[0.5, 0.31], 0.05));
        let fits = fit_shapes(&[vec![0.0], vec![1.0]], &[f_again(), near]);
        let shares: Vec<f64> = fits.iter().map(|f| f.kept_share.unwrap()).collect();
        assert!(shares.iter().all(|s| *s > 0.2), "{shares:?}");
        assert!((shares.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }

    fn f_again() -> FactorErrors {
        FactorErrors::new([0.2, 0.8], at(&[-0.3, -0.1], 0.05), at(&[0.5, 0.3], 0.05))
    }

    #[test]
    fn the_best_shape_has_the_least_objective() {
        let s = |o: f64| ShapeFit {
            values: vec![o],
            factor: 1.0,
            objective: o,
            factor_ci95: None,
            kept_share: None,
        };
        let shapes = [s(0.3), s(0.1), s(0.1), s(0.2)];
        assert_eq!(best_shape(&shapes).unwrap().values, vec![0.1]);
        assert!(best_shape(&[]).is_none());
    }
}
