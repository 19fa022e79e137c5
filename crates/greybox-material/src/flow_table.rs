//! A tabulated flow stress σ_y(ε_p, ε̇_p, T) built from measured flow curves, so that
//! measured curves (including anomalies a Johnson–Cook law cannot follow, such as the
//! blue-brittleness band of plain carbon steels that `material fit` flags) drive the
//! simulation directly.
//!
//! The curves come in the `material fit` format (`strain,stress_MPa,temperature_C` or
//! `temperature_K`, `strain_rate_per_s`; one row per point). Points with the same strain
//! rate and temperature form one curve σ(ε); the curves must cover every combination of
//! their distinct rates and temperatures (a full grid, e.g. 7 temperatures × 1 rate).
//!
//! Evaluation: each curve is linear in ε between its points and constant beyond its ends
//! (perfectly plastic past the largest measured strain); the curves are interpolated
//! linearly in ln ε̇ and in T. Outside the tabulated ranges:
//! * below the lowest rate or temperature the nearest curve holds;
//! * above the highest rate the flow stress grows as 1 + C ln(ε̇/ε̇_max) with
//!   `rate_sensitivity_c` (0: constant), so quasi-static curves can be combined with a
//!   cutting-rate sensitivity;
//! * above the highest temperature it falls linearly to 0 at `melt_temperature_k`.

use crate::fit::{read_flow_points, FlowPoint};
use crate::Table1d;
use greybox_core::{Error, Result, SourcePos};
use serde::{Deserialize, Serialize};
use std::path::Path;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlowTable {
    /// The flow-curve CSV (relative to the set-up file); read by [`FlowTable::load`], which
    /// fills the fields below.
    #[serde(default)]
    pub file: Option<String>,
    /// Melting temperature, K: the flow stress reaches 0 there.
    pub melt_temperature_k: f64,
    /// Rate sensitivity above the highest tabulated strain rate.
    #[serde(default)]
    pub rate_sensitivity_c: f64,
    /// Distinct strain rates, 1/s, increasing.
    #[serde(default)]
    pub strain_rates_per_s: Vec<f64>,
    /// Distinct temperatures, K, increasing.
    #[serde(default)]
    pub temperatures_k: Vec<f64>,
    /// σ(ε) in Pa for rate k and temperature j at `curves[k · temperatures + j]`.
    #[serde(default)]
    pub curves: Vec<Table1d>,
}

/// Groups of equal values: values within this relative distance are one level.
const SAME_LEVEL: f64 = 1e-9;

fn levels(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut v: Vec<f64> = values.collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() <= SAME_LEVEL * b.abs().max(1.0));
    v
}

fn level_of(levels: &[f64], x: f64) -> usize {
    levels
        .iter()
        .position(|&l| (l - x).abs() <= SAME_LEVEL * l.abs().max(1.0))
        .expect("level of a tabulated value")
}

/// Linear interpolation weights of x in increasing `axis`: (lower index, weight of the
/// upper), clamped at the ends.
fn bracket(axis: &[f64], x: f64) -> (usize, f64) {
    let n = axis.len();
    if n == 1 || x <= axis[0] {
        return (0, 0.0);
    }
    if x >= axis[n - 1] {
        return (n - 2, 1.0);
    }
    let k = axis.partition_point(|&v| v <= x) - 1;
    (k, (x - axis[k]) / (axis[k + 1] - axis[k]))
}

impl FlowTable {
    /// Builds the table from flow-curve points (`source` names them in errors).
    pub fn from_points(
        points: &[FlowPoint],
        melt_temperature_k: f64,
        rate_sensitivity_c: f64,
        source: &str,
    ) -> Result<Self> {
        let rates = levels(points.iter().map(|p| p.strain_rate));
        let temps = levels(points.iter().map(|p| p.temperature_k));
        let mut curves: Vec<Vec<(f64, f64)>> = vec![Vec::new(); rates.len() * temps.len()];
        for p in points {
            let k =
                level_of(&rates, p.strain_rate) * temps.len() + level_of(&temps, p.temperature_k);
            curves[k].push((p.strain, p.stress_pa));
        }
        let mut tables = Vec::with_capacity(curves.len());
        for (k, mut c) in curves.into_iter().enumerate() {
            let (rate, temp) = (rates[k / temps.len()], temps[k % temps.len()]);
            if c.is_empty() {
                return Err(Error::input(
                    SourcePos::file(source),
                    format!(
                        "no flow curve at strain rate {rate} 1/s and {:.1} K: a flow-stress table needs a curve for every combination of its {} strain rates and {} temperatures",
                        temp,
                        rates.len(),
                        temps.len()
                    ),
                ));
            }
            c.sort_by(|a, b| a.0.total_cmp(&b.0));
            c.dedup_by(|a, b| a.0 == b.0);
            let (x, y) = c.into_iter().unzip();
            tables.push(Table1d::new(x, y)?);
        }
        let t = FlowTable {
            file: None,
            melt_temperature_k,
            rate_sensitivity_c,
            strain_rates_per_s: rates,
            temperatures_k: temps,
            curves: tables,
        };
        t.validate()?;
        Ok(t)
    }

    /// Reads `file` (relative to `base`) into the table; a table without a file is kept.
    pub fn load(&mut self, base: &Path) -> Result<()> {
        let Some(f) = &self.file else {
            return Ok(());
        };
        let path = base.join(f);
        let points = read_flow_points(&path)?;
        let source = path.display().to_string();
        if points.is_empty() {
            return Err(Error::input(
                SourcePos::file(&source),
                "no flow-curve points",
            ));
        }
        let built = Self::from_points(
            &points,
            self.melt_temperature_k,
            self.rate_sensitivity_c,
            &source,
        )?;
        *self = FlowTable {
            file: self.file.clone(),
            ..built
        };
        Ok(())
    }

    /// Flow stress σ_y(ε_p, ε̇_p, T), Pa.
    pub fn flow_stress(&self, eps_p: f64, strain_rate: f64, temperature_k: f64) -> f64 {
        let nt = self.temperatures_k.len();
        let rates = &self.strain_rates_per_s;
        let t_max = self.temperatures_k[nt - 1];
        let t = temperature_k.min(t_max);
        let (jt, wt) = bracket(&self.temperatures_k, t);
        let r = strain_rate.max(rates[0]).min(rates[rates.len() - 1]);
        // Linear in ln ε̇: the weight of the upper rate is ln(ε̇/ε̇_k) / ln(ε̇_k+1/ε̇_k).
        let (kr, wr) = match bracket(rates, r) {
            (k, w) if w > 0.0 && w < 1.0 => {
                (k, (r / rates[k]).ln() / (rates[k + 1] / rates[k]).ln())
            }
            kw => kw,
        };
        let at = |k: usize, j: usize| self.curves[k * nt + j].eval(eps_p.max(0.0));
        let along_t = |k: usize| {
            if nt == 1 {
                at(k, 0)
            } else {
                (1.0 - wt) * at(k, jt) + wt * at(k, jt + 1)
            }
        };
        let mut sigma = if rates.len() == 1 {
            along_t(0)
        } else {
            (1.0 - wr) * along_t(kr) + wr * along_t(kr + 1)
        };
        let r_max = rates[rates.len() - 1];
        if strain_rate > r_max {
            sigma *= 1.0 + self.rate_sensitivity_c * (strain_rate / r_max).ln();
        }
        if temperature_k > t_max {
            sigma *= ((self.melt_temperature_k - temperature_k)
                / (self.melt_temperature_k - t_max))
                .clamp(0.0, 1.0);
        }
        sigma
    }

    /// Checks the grid: loaded, increasing axes, one curve per node, positive stresses.
    pub fn validate(&self) -> Result<()> {
        let what = match &self.file {
            Some(f) => format!("flow-stress table {f}"),
            None => "flow-stress table".to_string(),
        };
        if self.curves.is_empty() {
            return Err(Error::invalid(
                what,
                "no curves: give `file` (flow curves in the `material fit` CSV format) and read the set-up through greybox, which loads it",
            ));
        }
        let increasing =
            |v: &[f64]| v.iter().all(|x| x.is_finite()) && v.windows(2).all(|w| w[1] > w[0]);
        let t_max = self.temperatures_k.last().copied().unwrap_or(f64::NAN);
        greybox_core::rules::Rules::new(what.clone())
            .non_negative("rate_sensitivity_c", self.rate_sensitivity_c)
            .relation(
                !self.strain_rates_per_s.is_empty()
                    && increasing(&self.strain_rates_per_s)
                    && self.strain_rates_per_s[0] > 0.0,
                "strain_rates_per_s must be positive and increasing",
            )
            .relation(
                !self.temperatures_k.is_empty()
                    && increasing(&self.temperatures_k)
                    && self.temperatures_k[0] > 0.0,
                "temperatures_k must be positive and increasing",
            )
            .relation(
                self.curves.len() == self.strain_rates_per_s.len() * self.temperatures_k.len(),
                format!(
                    "expected one curve per strain rate and temperature ({} × {}), got {}",
                    self.strain_rates_per_s.len(),
                    self.temperatures_k.len(),
                    self.curves.len()
                ),
            )
            .relation(
                self.melt_temperature_k.is_finite() && self.melt_temperature_k > t_max,
                format!(
                    "melt_temperature_k ({}) must exceed the highest tabulated temperature ({t_max} K)",
                    self.melt_temperature_k
                ),
            )
            .finish()?;
        for c in &self.curves {
            c.validate()?;
            if c.y.iter().any(|&s| s <= 0.0) || c.x.iter().any(|&e| e < 0.0) {
                return Err(Error::invalid(
                    what,
                    "expected plastic strains ≥ 0 and flow stresses > 0",
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::JohnsonCook;

    fn jc_points(
        jc: &JohnsonCook,
        strains: &[f64],
        rates: &[f64],
        temps: &[f64],
    ) -> Vec<FlowPoint> {
        let mut v = Vec::new();
        for &r in rates {
            for &t in temps {
                for &e in strains {
                    v.push(FlowPoint {
                        strain: e,
                        stress_pa: jc.flow_stress(e, r, t),
                        temperature_k: t,
                        strain_rate: r,
                    });
                }
            }
        }
        v
    }

    /// Tabulated from J-C, the table reproduces J-C: exactly at the nodes, and between them
    /// within the linear-interpolation error (J-C is linear in ln ε̇ and nearly linear in T
    /// for m ≈ 1, so the error comes from the strain axis).
    #[test]
    fn reproduces_johnson_cook_when_tabulated_from_it() {
        let jc = JohnsonCook::aisi1045_article();
        let strains: Vec<f64> = (0..=40).map(|k| 0.05 * k as f64).collect();
        let rates: Vec<f64> = (0..=9).map(|k| 4e-3 * 10f64.powi(k)).collect();
        let temps: Vec<f64> = (0..=12).map(|k| 293.15 + 100.0 * k as f64).collect();
        let table = FlowTable::from_points(
            &jc_points(&jc, &strains, &rates, &temps),
            jc.melt_temperature_k,
            0.0,
            "test",
        )
        .unwrap();
        for (e, r, t) in [(0.5, 4e-1, 593.15), (1.0, 4e3, 1093.15)] {
            assert!((table.flow_stress(e, r, t) / jc.flow_stress(e, r, t) - 1.0).abs() < 1e-12);
        }
        let mut worst: f64 = 0.0;
        for k in 0..200 {
            let e = 0.1 + 1.8 * ((k * 37) % 200) as f64 / 200.0;
            let r = 4e-3 * 10f64.powf(9.0 * ((k * 53) % 200) as f64 / 200.0);
            let t = 293.15 + 1200.0 * ((k * 71) % 200) as f64 / 200.0;
            worst = worst.max((table.flow_stress(e, r, t) / jc.flow_stress(e, r, t) - 1.0).abs());
        }
        assert!(worst < 0.01, "worst relative difference {worst}");
        // Beyond the table: constant in strain, linear to zero at the melting point.
        assert_eq!(
            table.flow_stress(5.0, 4.0, 593.15),
            table.flow_stress(2.0, 4.0, 593.15)
        );
        assert_eq!(table.flow_stress(0.5, 4.0, 1773.0), 0.0);
    }

    /// Quasi-static curves plus a rate sensitivity: above the highest rate σ × (1 + C ln(ε̇/ε̇_max)).
    #[test]
    fn rate_sensitivity_beyond_the_highest_rate() {
        let jc = JohnsonCook::aisi1045_article();
        let pts = jc_points(&jc, &[0.0, 0.5, 1.0], &[4e-3], &[293.15, 773.15]);
        let table = FlowTable::from_points(&pts, 1773.0, 0.045, "test").unwrap();
        let want = jc.flow_stress(0.5, 4e-3, 293.15) * (1.0 + 0.045 * (1e4f64 / 4e-3).ln());
        assert!((table.flow_stress(0.5, 1e4, 293.15) / want - 1.0).abs() < 1e-12);
    }

    /// A missing (rate, temperature) combination is named.
    #[test]
    fn an_incomplete_grid_is_refused_with_the_missing_curve() {
        let jc = JohnsonCook::aisi1045_article();
        let mut pts = jc_points(&jc, &[0.0, 0.5], &[1.0, 10.0], &[293.15, 773.15]);
        pts.retain(|p| !(p.strain_rate == 10.0 && p.temperature_k == 773.15));
        let e = FlowTable::from_points(&pts, 1773.0, 0.0, "curves.csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("curves.csv") && e.contains("strain rate 10") && e.contains("773.1"),
            "{e}"
        );
    }

    /// The CSV of `material fit` loads into a table relative to the set-up's folder.
    #[test]
    fn loads_flow_curves_from_a_file() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("curves.csv"),
            "strain,stress_MPa,temperature_C,strain_rate_per_s\n0,400,20,0.004\n0.5,700,20,0.004\n0,300,500,0.004\n0.5,500,500,0.004\n",
        )
        .unwrap();
        let mut t = FlowTable {
            file: Some("curves.csv".into()),
            melt_temperature_k: 1773.0,
            rate_sensitivity_c: 0.0,
            strain_rates_per_s: vec![],
            temperatures_k: vec![],
            curves: vec![],
        };
        assert!(t.validate().is_err());
        t.load(dir.path()).unwrap();
        // ε = 0.25: 550 MPa at 20 °C, 400 MPa at 500 °C; 260 °C is half-way.
        assert!((t.flow_stress(0.25, 0.004, 533.15) - 475e6).abs() < 1.0);
    }
}
