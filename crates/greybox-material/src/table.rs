//! A piecewise-linear table y(x), held constant outside its range.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Table1d {
    /// Strictly increasing abscissae.
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

impl Table1d {
    pub fn constant(y: f64) -> Self {
        Table1d {
            x: vec![0.0],
            y: vec![y],
        }
    }

    /// Builds a table, checking lengths, finiteness and strictly increasing x.
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> greybox_core::Result<Self> {
        let t = Table1d { x, y };
        t.validate()?;
        Ok(t)
    }

    pub fn validate(&self) -> greybox_core::Result<()> {
        let ok = !self.x.is_empty()
            && self.x.len() == self.y.len()
            && self.x.iter().chain(&self.y).all(|v| v.is_finite())
            && self.x.windows(2).all(|w| w[1] > w[0]);
        if ok {
            Ok(())
        } else {
            Err(greybox_core::Error::invalid(
                "table",
                "expected equal-length, finite columns with strictly increasing x",
            ))
        }
    }

    /// Linear interpolation, constant extrapolation.
    #[inline]
    pub fn eval(&self, x: f64) -> f64 {
        let n = self.x.len();
        if n == 1 || x <= self.x[0] {
            return self.y[0];
        }
        if x >= self.x[n - 1] {
            return self.y[n - 1];
        }
        let k = self.x.partition_point(|&v| v <= x) - 1;
        let t = (x - self.x[k]) / (self.x[k + 1] - self.x[k]);
        self.y[k] + t * (self.y[k + 1] - self.y[k])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_clamps() {
        let t = Table1d::new(vec![0.0, 10.0, 20.0], vec![1.0, 3.0, 2.0]).unwrap();
        assert_eq!(t.eval(-5.0), 1.0);
        assert_eq!(t.eval(5.0), 2.0);
        assert_eq!(t.eval(15.0), 2.5);
        assert_eq!(t.eval(25.0), 2.0);
        assert!(Table1d::new(vec![0.0, 0.0], vec![1.0, 2.0]).is_err());
    }
}
