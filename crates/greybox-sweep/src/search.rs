//! The parameter search shared by every calibration (the sweep's calibration of a set-up
//! field, the validation suite's calibrated friction laws): golden-section search on one
//! field at a time (coordinate descent), each field over its bracket on a linear or a
//! logarithmic scale.
//!
//! Golden-section search needs no derivative and tolerates the small run-to-run noise of a
//! simulated objective; coordinate descent suits the few, weakly coupled parameters of a
//! calibration (a material constant and a friction scale; a friction law's level and its
//! exponents about a reference state in the middle of the data).

use anyhow::{bail, Result};
use serde::{Deserialize, Serialize};

/// One fitted field: a dotted path and its bracket.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FitField {
    /// Dotted path of the field (a configuration field, or a friction law's).
    pub field: String,
    /// The bracket searched, [low, high].
    pub range: [f64; 2],
    /// Search on ln x (for a positive quantity spanning decades), not on x.
    #[serde(default)]
    pub log: bool,
}

impl FitField {
    pub fn new(field: &str, range: [f64; 2], log: bool) -> Self {
        FitField {
            field: field.to_string(),
            range,
            log,
        }
    }

    /// An ordered bracket (positive on a log scale).
    pub fn check(&self) -> Result<()> {
        let [lo, hi] = self.range;
        if !(lo.is_finite() && hi.is_finite() && hi > lo) {
            bail!(
                "fit field '{}': range must be [low, high] with low < high, got [{lo}, {hi}]",
                self.field
            );
        }
        if self.log && lo.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            bail!(
                "fit field '{}': a logarithmic search needs low > 0, got {lo}",
                self.field
            );
        }
        Ok(())
    }

    fn to_search(&self, x: f64) -> f64 {
        if self.log {
            x.ln()
        } else {
            x
        }
    }

    fn of_search(&self, u: f64) -> f64 {
        if self.log {
            u.exp()
        } else {
            u
        }
    }

    /// The middle of the bracket on the search scale (geometric on a log scale).
    pub fn middle(&self) -> f64 {
        self.of_search(0.5 * (self.to_search(self.range[0]) + self.to_search(self.range[1])))
    }

    /// `x` moved into the bracket.
    pub fn clamp(&self, x: f64) -> f64 {
        x.clamp(self.range[0], self.range[1])
    }
}

/// Golden-section search of `f` over `field`'s bracket with `evaluations` evaluations (at
/// least 3); returns the best value seen and its objective.
pub fn golden(
    field: &FitField,
    evaluations: usize,
    f: &mut dyn FnMut(f64) -> Result<f64>,
) -> Result<(f64, f64)> {
    field.check()?;
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (
        field.to_search(field.range[0]),
        field.to_search(field.range[1]),
    );
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let (mut f1, mut f2) = (f(field.of_search(x1))?, f(field.of_search(x2))?);
    for _ in 2..evaluations.max(3) {
        if f1 <= f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - g * (b - a);
            f1 = f(field.of_search(x1))?;
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + g * (b - a);
            f2 = f(field.of_search(x2))?;
        }
    }
    Ok(if f1 <= f2 {
        (field.of_search(x1), f1)
    } else {
        (field.of_search(x2), f2)
    })
}

/// Coordinate descent: `passes` passes over `fields`, each a golden-section search of one
/// field with the others held, starting from `start` (clamped into the brackets; not itself
/// evaluated, as an evaluation can be a whole sweep of simulations). The first search's
/// result is taken; later ones are kept only where they lower the objective. Returns the
/// parameters and their objective.
pub fn coordinate_descent(
    fields: &[FitField],
    start: &[f64],
    passes: usize,
    evaluations: usize,
    f: &mut dyn FnMut(&[f64]) -> Result<f64>,
) -> Result<(Vec<f64>, f64)> {
    if fields.len() != start.len() || fields.is_empty() {
        bail!(
            "a search needs one start value per fitted field (got {} fields, {} values)",
            fields.len(),
            start.len()
        );
    }
    let mut x: Vec<f64> = fields.iter().zip(start).map(|(d, &s)| d.clamp(s)).collect();
    let mut best = f64::INFINITY;
    for _ in 0..passes.max(1) {
        for (k, field) in fields.iter().enumerate() {
            let mut trial = x.clone();
            let (v, fv) = golden(field, evaluations, &mut |v| {
                trial[k] = v;
                f(&trial)
            })?;
            if fv < best {
                x[k] = v;
                best = fv;
            }
        }
    }
    Ok((x, best))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn golden_section_finds_the_minimum_on_either_scale() {
        let lin = FitField::new("b", [-1.0, 1.0], false);
        let (x, _) = golden(&lin, 40, &mut |x| Ok((x - 0.3f64).powi(2))).unwrap();
        assert!((x - 0.3).abs() < 1e-6, "{x}");
        let log = FitField::new("c", [1e-3, 1.0], true);
        let (x, _) = golden(&log, 40, &mut |x| Ok((x.ln() - 0.02f64.ln()).powi(2))).unwrap();
        assert!((x / 0.02 - 1.0).abs() < 1e-5, "{x}");
        assert!(golden(&FitField::new("c", [0.0, 1.0], true), 5, &mut |_| Ok(0.0)).is_err());
    }

    #[test]
    fn a_second_pass_moves_coupled_parameters_towards_their_joint_best() {
        // f = (x + y − 1)² + 0.1 (x − y − 0.4)²: the best is x = 0.7, y = 0.3; each
        // parameter's best moves with the other's value, as the flow stress's and the
        // friction's do through the forces
        let fields = [
            FitField::new("x", [-1.0, 2.0], false),
            FitField::new("y", [-1.0, 2.0], false),
        ];
        let mut f = |p: &[f64]| Ok((p[0] + p[1] - 1.0).powi(2) + 0.1 * (p[0] - p[1] - 0.4).powi(2));
        let miss = |x: &[f64]| ((x[0] - 0.7f64).powi(2) + (x[1] - 0.3f64).powi(2)).sqrt();
        let (one, _) = coordinate_descent(&fields, &[0.5, 0.5], 1, 40, &mut f).unwrap();
        let (two, _) = coordinate_descent(&fields, &[0.5, 0.5], 2, 40, &mut f).unwrap();
        assert!(miss(&one) > 0.05, "{one:?}");
        assert!(miss(&two) < 0.8 * miss(&one), "{one:?} {two:?}");
    }

    #[test]
    fn coordinate_descent_fits_two_decoupled_parameters() {
        // ln μ = ln 0.4 + b ln(v/v_ref) at v/v_ref = 0.5, 1, 2, "measured" with b = −0.3
        let data: Vec<(f64, f64)> = [0.5, 1.0, 2.0]
            .iter()
            .map(|&r: &f64| (r, 0.4 * r.powf(-0.3)))
            .collect();
        let fields = [
            FitField::new("mu_ref", [0.1, 1.0], true),
            FitField::new("b", [-1.0, 0.5], false),
        ];
        let (x, j) = coordinate_descent(&fields, &[0.5, 0.0], 4, 40, &mut |p| {
            Ok(data
                .iter()
                .map(|&(r, mu)| (p[0] * r.powf(p[1]) / mu - 1.0).powi(2))
                .sum())
        })
        .unwrap();
        assert!(
            (x[0] - 0.4).abs() < 1e-4 && (x[1] + 0.3).abs() < 1e-4,
            "{x:?} {j}"
        );
    }
}
