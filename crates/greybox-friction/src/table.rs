//! Tabulated surrogates: any law baked onto a uniform (p, v[, T]) grid and evaluated by
//! bilinear (trilinear) interpolation, clamped at the grid edges. Uniform axes make the cell
//! lookup a multiply and a truncation, so one evaluation costs a few nanoseconds. Exact tables
//! of tree ensembles are [`crate::exact_table`], tables refined to a tolerance
//! [`crate::adaptive`]; files of every kind are read by [`crate::table_file`].

use crate::table_schema::TableKind;
use greybox_core::law::{Range, ValidityDomain};
use greybox_core::{ContactState, Error, FrictionLaw, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// A uniform axis: `n` points from `min` to `max`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    pub n: usize,
}

impl Axis {
    pub fn new(min: f64, max: f64, n: usize) -> Result<Self> {
        if !(min.is_finite() && max.is_finite() && max > min) || n < 2 {
            return Err(Error::invalid(
                "table axis",
                format!("needs min < max and n ≥ 2, got {min}..{max}, n = {n}"),
            ));
        }
        Ok(Axis { min, max, n })
    }
    pub fn value(&self, i: usize) -> f64 {
        self.min + (self.max - self.min) * i as f64 / (self.n - 1) as f64
    }
    pub fn values(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.value(i)).collect()
    }
    /// Points per unit of x: (n − 1) / (max − min).
    pub fn inv_step(&self) -> f64 {
        (self.n - 1) as f64 / (self.max - self.min)
    }
    /// Cell index and fraction of x (clamped to the axis); `inv` is [`Axis::inv_step`].
    #[inline]
    fn locate(&self, x: f64, inv: f64) -> (usize, f64) {
        let u = ((x - self.min) * inv).clamp(0.0, (self.n - 1) as f64);
        let i = (u as usize).min(self.n - 2);
        (i, u - i as f64)
    }
}

/// A law on a grid. `values[(it * nv + iv) * np + ip]`: pressure fastest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TabulatedLaw {
    pub schema: String,
    /// 1 for files written before table kinds existed (no field), else 2.
    #[serde(default = "version_1")]
    pub schema_version: u32,
    /// [`TableKind::Uniform`] (absent from version-1 files).
    #[serde(default = "uniform")]
    pub kind: TableKind,
    pub source: String,
    /// Pressure, Pa.
    pub pressure: Axis,
    /// Sliding velocity, m/s.
    pub velocity: Axis,
    /// Temperature, K (absent: the law was baked at `temperature_k`).
    pub temperature: Option<Axis>,
    pub temperature_k: f64,
    pub values: Vec<f64>,
    /// Largest |table − source| on the check set, if checked.
    pub max_deviation: Option<f64>,
    /// Cached inverse grid steps (p, v, T); rebuilt by [`TabulatedLaw::prepare`].
    #[serde(skip)]
    inv: [f64; 3],
}

pub use crate::table_schema::TABLE_SCHEMA;

fn version_1() -> u32 {
    1
}
fn uniform() -> TableKind {
    TableKind::Uniform
}

impl TabulatedLaw {
    /// Evaluate `law` at every grid node.
    pub fn bake(
        law: &dyn FrictionLaw,
        pressure: Axis,
        velocity: Axis,
        temperature: Option<Axis>,
    ) -> Self {
        let tk = ContactState::ROOM_TEMPERATURE_K;
        let nt = temperature.map(|a| a.n).unwrap_or(1);
        let mut values = Vec::with_capacity(pressure.n * velocity.n * nt);
        for it in 0..nt {
            let t = temperature.map(|a| a.value(it)).unwrap_or(tk);
            for iv in 0..velocity.n {
                for ip in 0..pressure.n {
                    values.push(law.mu(&ContactState {
                        pressure_pa: pressure.value(ip),
                        sliding_velocity_m_s: velocity.value(iv),
                        temperature_k: t,
                    }));
                }
            }
        }
        TabulatedLaw {
            schema: TABLE_SCHEMA.into(),
            schema_version: crate::table_schema::TABLE_SCHEMA_VERSION,
            kind: uniform(),
            source: law.name(),
            pressure,
            velocity,
            temperature,
            temperature_k: tk,
            values,
            max_deviation: None,
            inv: [0.0; 3],
        }
        .prepare()
    }

    /// Validate the grid and cache the inverse steps (call after deserialising).
    pub fn prepare(mut self) -> Self {
        self.inv = [
            self.pressure.inv_step(),
            self.velocity.inv_step(),
            self.temperature.map(|a| a.inv_step()).unwrap_or(0.0),
        ];
        self
    }

    /// Check the deserialised table is consistent.
    pub fn validate(&self) -> Result<()> {
        for a in [Some(self.pressure), Some(self.velocity), self.temperature]
            .into_iter()
            .flatten()
        {
            Axis::new(a.min, a.max, a.n)?;
        }
        let n = self.pressure.n * self.velocity.n * self.temperature.map(|a| a.n).unwrap_or(1);
        if self.values.len() != n || self.values.iter().any(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "table",
                format!("expected {n} finite values, found {}", self.values.len()),
            ));
        }
        Ok(())
    }

    /// Largest |table − law| over `n` seeded random points inside the grid box; stored.
    pub fn check(&mut self, law: &dyn FrictionLaw, n: usize, seed: u64) -> f64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut worst: f64 = 0.0;
        for _ in 0..n {
            let s = ContactState {
                pressure_pa: rng.gen_range(self.pressure.min..=self.pressure.max),
                sliding_velocity_m_s: rng.gen_range(self.velocity.min..=self.velocity.max),
                temperature_k: self
                    .temperature
                    .map(|a| rng.gen_range(a.min..=a.max))
                    .unwrap_or(self.temperature_k),
            };
            worst = worst.max((self.mu(&s) - law.mu(&s)).abs());
        }
        self.max_deviation = Some(worst);
        worst
    }

    #[inline]
    fn at(&self, ip: usize, iv: usize, it: usize) -> f64 {
        self.values[(it * self.velocity.n + iv) * self.pressure.n + ip]
    }

    #[inline]
    fn bilinear(&self, ip: usize, fp: f64, iv: usize, fv: f64, it: usize) -> f64 {
        let a = self.at(ip, iv, it) + fp * (self.at(ip + 1, iv, it) - self.at(ip, iv, it));
        let b =
            self.at(ip, iv + 1, it) + fp * (self.at(ip + 1, iv + 1, it) - self.at(ip, iv + 1, it));
        a + fv * (b - a)
    }
}

impl FrictionLaw for TabulatedLaw {
    fn name(&self) -> String {
        format!("table of [{}]", self.source)
    }
    #[inline]
    fn mu(&self, s: &ContactState) -> f64 {
        let (ip, fp) = self.pressure.locate(s.pressure_pa, self.inv[0]);
        let (iv, fv) = self
            .velocity
            .locate(s.sliding_velocity_m_s.abs(), self.inv[1]);
        match self.temperature {
            None => self.bilinear(ip, fp, iv, fv, 0),
            Some(t) => {
                let (it, ft) = t.locate(s.temperature_k, self.inv[2]);
                let a = self.bilinear(ip, fp, iv, fv, it);
                let b = self.bilinear(ip, fp, iv, fv, it + 1);
                a + ft * (b - a)
            }
        }
    }
    fn domain(&self) -> Option<ValidityDomain> {
        Some(ValidityDomain {
            pressure_pa: Range {
                min: self.pressure.min,
                max: self.pressure.max,
            },
            sliding_velocity_m_s: Range {
                min: self.velocity.min,
                max: self.velocity.max,
            },
            temperature_k: self.temperature.map(|a| Range {
                min: a.min,
                max: a.max,
            }),
        })
    }
}
