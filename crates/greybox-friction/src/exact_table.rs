//! Exact tables of piecewise-constant laws (tree ensembles): one cell per region between the
//! law's split thresholds restated in SI ([`greybox_core::Breaks`] with `constant_between`),
//! looked up by cell, no interpolation.
//!
//! Along each axis with lines b₀ < … < bₙ₋₁ the cells are x ≤ b₀, b₀ < x ≤ b₁, …, x > bₙ₋₁
//! (pressure p in Pa, sliding speed |v| in m/s, temperature T in K). The law is constant on
//! every product cell, so the table holds μ of one point of each cell and equals the law
//! everywhere, bit for bit: max deviation 0 by construction, which [`ExactTable::check`]
//! confirms on random points and on every line and its neighbouring floats.

use crate::lines::Lines;
use crate::table_schema::TableKind;
use greybox_core::law::ValidityDomain;
use greybox_core::{Breaks, ContactState, Error, FrictionLaw, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

/// Largest exact table built unless told otherwise (32 MB of cells).
pub const DEFAULT_MAX_CELLS: usize = 1 << 22;

/// A piecewise-constant law as its cells. `values[(it·nv + iv)·np + ip]` with n = lines + 1
/// per axis (pressure fastest).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExactTable {
    /// [`crate::table_schema::TABLE_SCHEMA`].
    pub schema: String,
    pub schema_version: u32,
    /// [`TableKind::Exact`].
    pub kind: TableKind,
    /// Name of the law it was built from.
    pub source: String,
    /// Cell boundaries along the pressure, Pa.
    #[serde(rename = "pressure_Pa")]
    pub pressure_pa: Vec<f64>,
    /// Cell boundaries along the sliding speed |v|, m/s.
    #[serde(rename = "sliding_velocity_m_per_s")]
    pub velocity_m_s: Vec<f64>,
    /// Cell boundaries along the temperature, K (empty: μ does not depend on it).
    #[serde(rename = "temperature_K")]
    pub temperature_k: Vec<f64>,
    /// μ per cell.
    pub values: Vec<f64>,
    /// The source law's validity domain, if it has one.
    #[serde(default)]
    pub domain: Option<ValidityDomain>,
    /// Largest |table − source| found by [`ExactTable::check`] and on how many points.
    #[serde(default)]
    pub max_deviation: Option<f64>,
    #[serde(default)]
    pub check_points: Option<usize>,
    #[serde(skip)]
    index: [Lines; 3],
}

/// A state inside cell `c` of an axis with lines `l`: the cell's upper line, or just above
/// the last line for the last cell (`fallback` on an axis without lines).
fn inside(l: &[f64], c: usize, fallback: f64) -> f64 {
    match (l.get(c), l.last()) {
        (Some(&upper), _) => upper,
        (None, Some(&last)) => last.next_up(),
        (None, None) => fallback,
    }
}

impl ExactTable {
    /// Tabulate a piecewise-constant law ([`FrictionLaw::breaks`] with `constant_between`);
    /// an error when the law is not one, or when the table would have more than `max_cells`.
    pub fn build(law: &dyn FrictionLaw, max_cells: usize) -> Result<Self> {
        let breaks = match law.breaks() {
            Some(b) if b.constant_between => b.normalize(),
            _ => {
                return Err(Error::invalid(
                    "exact table",
                    format!(
                        "{} is not piecewise constant (exact tables are for tree ensembles); use an adaptive table",
                        law.name()
                    ),
                ))
            }
        };
        let cells = breaks.cells().filter(|&c| c <= max_cells).ok_or_else(|| {
            Error::invalid(
                "exact table",
                format!(
                    "{} × {} × {} cells (pressure × velocity × temperature lines + 1) exceed the cap of {max_cells} cells",
                    breaks.pressure_pa.len() + 1,
                    breaks.sliding_velocity_m_s.len() + 1,
                    breaks.temperature_k.len() + 1
                ),
            )
        })?;
        let domain = law.domain();
        let mid = |a: usize, dflt: f64| {
            domain
                .and_then(|d| match a {
                    0 => Some(d.pressure_pa),
                    1 => Some(d.sliding_velocity_m_s),
                    _ => d.temperature_k,
                })
                .map(|r| 0.5 * (r.min + r.max))
                .unwrap_or(dflt)
        };
        let fallback = [
            mid(0, 1e9),
            mid(1, 1.0),
            mid(2, ContactState::ROOM_TEMPERATURE_K),
        ];
        let n: Vec<usize> = (0..3).map(|a| breaks.axis(a).len() + 1).collect();
        let mut values = Vec::with_capacity(cells);
        for it in 0..n[2] {
            let t = inside(&breaks.temperature_k, it, fallback[2]);
            for iv in 0..n[1] {
                let v = inside(&breaks.sliding_velocity_m_s, iv, fallback[1]);
                for ip in 0..n[0] {
                    values.push(law.mu(&ContactState {
                        pressure_pa: inside(&breaks.pressure_pa, ip, fallback[0]),
                        sliding_velocity_m_s: v,
                        temperature_k: t,
                    }));
                }
            }
        }
        ExactTable {
            schema: crate::table_schema::TABLE_SCHEMA.into(),
            schema_version: crate::table_schema::TABLE_SCHEMA_VERSION,
            kind: TableKind::Exact,
            source: law.name(),
            pressure_pa: breaks.pressure_pa,
            velocity_m_s: breaks.sliding_velocity_m_s,
            temperature_k: breaks.temperature_k,
            values,
            domain,
            max_deviation: None,
            check_points: None,
            index: Default::default(),
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
        let cells = self
            .index
            .iter()
            .try_fold(1usize, |n, l| n.checked_mul(l.len() + 1));
        if cells != Some(self.values.len()) {
            return Err(Error::invalid(
                "values",
                format!(
                    "expected {} cells (Π (lines + 1)), found {}",
                    cells.map_or("too many".into(), |c| c.to_string()),
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
        Ok(self)
    }

    /// Cells per axis (lines + 1).
    pub fn shape(&self) -> [usize; 3] {
        [
            self.pressure_pa.len() + 1,
            self.velocity_m_s.len() + 1,
            self.temperature_k.len() + 1,
        ]
    }

    /// Largest |table − law| over `n` seeded random states in `bounds` (or the source's
    /// domain, or the span of the lines) and, for every line b of every axis, states at
    /// b.next_down(), b and b.next_up() on that axis (random elsewhere); stored.
    pub fn check(
        &mut self,
        law: &dyn FrictionLaw,
        n: usize,
        seed: u64,
        bounds: Option<ValidityDomain>,
    ) -> f64 {
        let states = exact_check_states(self, n, seed, bounds.or(self.domain));
        let worst = states
            .iter()
            .map(|s| deviation(self.mu(s), law.mu(s)))
            .fold(0.0, f64::max);
        self.max_deviation = Some(worst);
        self.check_points = Some(states.len());
        worst
    }
}

/// |a − b|, 0 for identical values (NaN included), ∞ when only one is NaN.
pub fn deviation(a: f64, b: f64) -> f64 {
    if a.to_bits() == b.to_bits() {
        0.0
    } else {
        let d = (a - b).abs();
        if d.is_nan() {
            f64::INFINITY
        } else {
            d
        }
    }
}

/// The check states of [`ExactTable::check`].
fn exact_check_states(
    t: &ExactTable,
    n: usize,
    seed: u64,
    bounds: Option<ValidityDomain>,
) -> Vec<ContactState> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let lines = [&t.pressure_pa, &t.velocity_m_s, &t.temperature_k];
    let span = |a: usize| -> (f64, f64) {
        let r = bounds.and_then(|d| match a {
            0 => Some(d.pressure_pa),
            1 => Some(d.sliding_velocity_m_s),
            _ => d.temperature_k,
        });
        match (r, lines[a].first(), lines[a].last()) {
            (Some(r), _, _) => (r.min, r.max),
            (None, Some(&lo), Some(&hi)) => {
                let pad = 0.05 * (hi - lo).max(lo.abs() * 1e-3).max(1e-9);
                (lo - pad, hi + pad)
            }
            _ => match a {
                0 => (0.0, 3e9),
                1 => (0.0, 5.0),
                _ => (
                    ContactState::ROOM_TEMPERATURE_K,
                    ContactState::ROOM_TEMPERATURE_K,
                ),
            },
        }
    };
    let spans = [span(0), span(1), span(2)];
    let random = |rng: &mut ChaCha8Rng| -> [f64; 3] {
        spans.map(|(lo, hi)| if hi > lo { rng.gen_range(lo..=hi) } else { lo })
    };
    let state = |x: [f64; 3]| ContactState {
        pressure_pa: x[0],
        sliding_velocity_m_s: x[1],
        temperature_k: x[2],
    };
    let mut out: Vec<ContactState> = (0..n).map(|_| state(random(&mut rng))).collect();
    for (a, l) in lines.iter().enumerate() {
        for &b in l.iter() {
            for x in [b.next_down(), b, b.next_up()] {
                let mut p = random(&mut rng);
                p[a] = x;
                out.push(state(p));
            }
        }
    }
    out
}

impl FrictionLaw for ExactTable {
    fn name(&self) -> String {
        format!("exact table of [{}]", self.source)
    }
    #[inline]
    fn mu(&self, s: &ContactState) -> f64 {
        let [ip, iv, it] = [
            self.index[0].rank(s.pressure_pa),
            self.index[1].rank(s.sliding_velocity_m_s.abs()),
            self.index[2].rank(s.temperature_k),
        ];
        let (np, nv) = (self.index[0].len() + 1, self.index[1].len() + 1);
        self.values[(it * nv + iv) * np + ip]
    }
    fn domain(&self) -> Option<ValidityDomain> {
        self.domain
    }
    fn breaks(&self) -> Option<Breaks> {
        Some(Breaks {
            pressure_pa: self.pressure_pa.clone(),
            sliding_velocity_m_s: self.velocity_m_s.clone(),
            temperature_k: self.temperature_k.clone(),
            constant_between: true,
        })
    }
}
