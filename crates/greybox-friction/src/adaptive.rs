//! Adaptive tables for smooth laws (SVR, MLP, grey-box compositions, any law): a
//! tensor-product grid with non-uniform axes over a (p, |v|[, T]) box, evaluated by bilinear
//! (trilinear with T) interpolation and clamped at the box edges, refined where the law
//! curves until the max deviation on a dense check set is within a tolerance (aiming for
//! [`AIM`] × the tolerance there, so that unseen states stay within it).
//!
//! The refinement is [`crate::adaptive_refine`]; this module holds the table and its lookup.

use crate::lines::Lines;
use crate::table_schema::TableKind;
use greybox_core::law::{Range, ValidityDomain};
use greybox_core::{ContactState, Error, FrictionLaw, Result};
use serde::{Deserialize, Serialize};

/// A law on a non-uniform tensor grid. `values[(it·nv + iv)·np + ip]`, pressure fastest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AdaptiveTable {
    /// [`crate::table_schema::TABLE_SCHEMA`].
    pub schema: String,
    pub schema_version: u32,
    /// [`TableKind::Adaptive`].
    pub kind: TableKind,
    /// Name of the law it was built from.
    pub source: String,
    /// Pressure nodes, Pa (≥ 2).
    #[serde(rename = "pressure_Pa")]
    pub pressure_pa: Vec<f64>,
    /// Sliding-speed nodes |v|, m/s (≥ 2).
    #[serde(rename = "sliding_velocity_m_per_s")]
    pub velocity_m_s: Vec<f64>,
    /// Temperature nodes, K (one node: μ(p, v) at that temperature, constant in T).
    #[serde(rename = "temperature_K")]
    pub temperature_k: Vec<f64>,
    /// μ per node.
    pub values: Vec<f64>,
    /// The max deviation the refinement aimed for.
    pub tolerance: f64,
    /// Largest |table − source| on the refinement's check set, and its size.
    #[serde(default)]
    pub max_deviation: Option<f64>,
    #[serde(default)]
    pub check_points: Option<usize>,
    #[serde(skip)]
    index: [Lines; 3],
    /// Per axis, 1 / (l[j+1] − l[j]) (capped at f64::MAX).
    #[serde(skip)]
    inv_width: [Vec<f64>; 3],
}

impl AdaptiveTable {
    /// Evaluate `law` at every node of `axes`.
    pub(crate) fn bake(
        law: &dyn FrictionLaw,
        axes: &[Vec<f64>; 3],
        tolerance: f64,
    ) -> Result<Self> {
        let mut values = Vec::with_capacity(axes.iter().map(Vec::len).product());
        for &t in &axes[2] {
            for &v in &axes[1] {
                for &p in &axes[0] {
                    let s = ContactState {
                        pressure_pa: p,
                        sliding_velocity_m_s: v,
                        temperature_k: t,
                    };
                    let mu = law.mu(&s);
                    if !mu.is_finite() {
                        return Err(Error::invalid(
                            "adaptive table",
                            format!(
                                "{} gives μ = {mu} at p = {p} Pa, v = {v} m/s, T = {t} K",
                                law.name()
                            ),
                        ));
                    }
                    values.push(mu);
                }
            }
        }
        AdaptiveTable {
            schema: crate::table_schema::TABLE_SCHEMA.into(),
            schema_version: crate::table_schema::TABLE_SCHEMA_VERSION,
            kind: TableKind::Adaptive,
            source: law.name(),
            pressure_pa: axes[0].clone(),
            velocity_m_s: axes[1].clone(),
            temperature_k: axes[2].clone(),
            values,
            tolerance,
            max_deviation: None,
            check_points: None,
            index: Default::default(),
            inv_width: Default::default(),
        }
        .prepare()
    }

    /// Validate a deserialised table and build its lookup index.
    pub fn prepare(mut self) -> Result<Self> {
        self.index = [
            Lines::new(&self.pressure_pa, "pressure_Pa")?,
            Lines::new(&self.velocity_m_s, "sliding_velocity_m_per_s")?,
            Lines::new(&self.temperature_k, "temperature_K")?,
        ];
        for (name, n, min) in [
            ("pressure_Pa", self.pressure_pa.len(), 2),
            ("sliding_velocity_m_per_s", self.velocity_m_s.len(), 2),
            ("temperature_K", self.temperature_k.len(), 1),
        ] {
            if n < min {
                return Err(Error::invalid(
                    name,
                    format!("needs at least {min} nodes, found {n}"),
                ));
            }
        }
        let n = self.shape().iter().product::<usize>();
        if self.values.len() != n {
            return Err(Error::invalid(
                "values",
                format!(
                    "expected {n} values (one per node), found {}",
                    self.values.len()
                ),
            ));
        }
        if let Some(i) = self.values.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "values",
                format!("value {} is not finite", i + 1),
            ));
        }
        self.inv_width = std::array::from_fn(|a| {
            let l = self.axis(a);
            let mut w: Vec<f64> = l
                .windows(2)
                .map(|w| (1.0 / (w[1] - w[0])).min(f64::MAX))
                .collect();
            w.push(0.0); // a one-node axis: fraction 0
            w
        });
        Ok(self)
    }

    /// Nodes per axis (pressure, velocity, temperature).
    pub fn shape(&self) -> [usize; 3] {
        [
            self.pressure_pa.len(),
            self.velocity_m_s.len(),
            self.temperature_k.len(),
        ]
    }

    pub(crate) fn axis(&self, a: usize) -> &[f64] {
        match a {
            0 => &self.pressure_pa,
            1 => &self.velocity_m_s,
            _ => &self.temperature_k,
        }
    }

    /// (cell, fraction) of `x` on axis `a`: the cell j with l[j] ≤ x < l[j+1] (the first or
    /// last cell outside), fraction (x − l[j]) / (l[j+1] − l[j]) clamped to [0, 1]. A node
    /// gets fraction 0 (its value exactly), except the last node of an axis (within an ulp).
    #[inline]
    fn cell(&self, a: usize, x: f64) -> (usize, f64) {
        let l = self.axis(a);
        let j = self.index[a].rank_le(x).clamp(1, l.len().max(2) - 1) - 1;
        let f = ((x - l[j]) * self.inv_width[a][j]).clamp(0.0, 1.0);
        (j, f)
    }

    /// (cell, fraction) per axis of a state.
    #[inline]
    fn locate(&self, s: &ContactState) -> [(usize, f64); 3] {
        [
            self.cell(0, s.pressure_pa),
            self.cell(1, s.sliding_velocity_m_s.abs()),
            self.cell(2, s.temperature_k),
        ]
    }

    pub(crate) fn cell_at(&self, s: &ContactState) -> [usize; 3] {
        self.locate(s).map(|(j, _)| j)
    }

    #[inline]
    pub(crate) fn at(&self, ip: usize, iv: usize, it: usize) -> f64 {
        self.values[(it * self.velocity_m_s.len() + iv) * self.pressure_pa.len() + ip]
    }

    #[inline]
    fn bilinear(&self, (ip, fp): (usize, f64), (iv, fv): (usize, f64), it: usize) -> f64 {
        let lo = fast_lerp(self.at(ip, iv, it), self.at(ip + 1, iv, it), fp);
        let hi = fast_lerp(self.at(ip, iv + 1, it), self.at(ip + 1, iv + 1, it), fp);
        fast_lerp(lo, hi, fv)
    }
}

/// a + f(b − a): exact at f = 0 and where a == b, within an ulp of b at f = 1.
#[inline]
fn fast_lerp(a: f64, b: f64, f: f64) -> f64 {
    a + f * (b - a)
}

impl FrictionLaw for AdaptiveTable {
    fn name(&self) -> String {
        format!("adaptive table of [{}]", self.source)
    }
    #[inline]
    fn mu(&self, s: &ContactState) -> f64 {
        let p = self.cell(0, s.pressure_pa);
        let v = self.cell(1, s.sliding_velocity_m_s.abs());
        if self.temperature_k.len() == 1 {
            self.bilinear(p, v, 0)
        } else {
            let (it, ft) = self.cell(2, s.temperature_k);
            fast_lerp(self.bilinear(p, v, it), self.bilinear(p, v, it + 1), ft)
        }
    }
    fn domain(&self) -> Option<ValidityDomain> {
        let r = |l: &[f64]| Range {
            min: l[0],
            max: l[l.len() - 1],
        };
        Some(ValidityDomain {
            pressure_pa: r(&self.pressure_pa),
            sliding_velocity_m_s: r(&self.velocity_m_s),
            temperature_k: (self.temperature_k.len() > 1).then(|| r(&self.temperature_k)),
        })
    }
}
