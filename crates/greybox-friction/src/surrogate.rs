//! A surrogate table for any law: exact cells for piecewise-constant laws (tree ensembles),
//! an adaptive grid refined to a tolerance for every other law, or — on request — the
//! uniform grid of [`TabulatedLaw`]; and its deviation on states the build never saw.

use crate::adaptive::AdaptiveTable;
use crate::adaptive_refine::RefineOptions;
use crate::exact_table::{deviation, ExactTable};
use crate::table::{Axis, TabulatedLaw};
use crate::table_file::{AnyTable, TableKind};
use greybox_core::law::{Range, ValidityDomain};
use greybox_core::{ContactState, FrictionLaw, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What to build and over which box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurrogateOptions {
    /// `None`: [`auto_kind`].
    pub kind: Option<TableKind>,
    /// Box: pressure, Pa; sliding speed, m/s; temperature, K (`None`: μ(p, v) at room
    /// temperature). Exact tables cover every state; the box bounds their check.
    pub pressure_pa: Range,
    pub velocity_m_s: Range,
    pub temperature_k: Option<Range>,
    /// Uniform tables: points per axis (pressure, velocity, temperature).
    pub uniform_points: [usize; 3],
    /// Adaptive tables: max |table − law| on the check set.
    pub tolerance: f64,
    /// Random states of the build's check (adaptive: the refinement's check set).
    pub check_points: usize,
    pub seed: u64,
    /// Most cells (exact) or nodes (adaptive).
    pub max_size: usize,
}

/// The default tolerance of adaptive tables and grids: max |Δμ| on the check set.
///
/// 10⁻³, an order of magnitude below the repeatability of measured friction coefficients
/// (±0.01–0.02 between pin-on-disk tests, ASTM G99 §12), and affordable for the laws users
/// tabulate: a grey-box law has creases where its clamp, its shear cap or its power law's
/// bounds take over, and across a crease running diagonally through (p, v) bilinear
/// interpolation errs by about h·|Δ∇μ|/4 whatever the spacing elsewhere. A tensor-product
/// table must refine whole grid lines to shrink h there, so its size grows as the
/// tolerance's inverse square: the demo's law needs ≈ 7·10⁶ nodes for 10⁻⁴ and 7·10⁴ for
/// 10⁻³.
pub const DEFAULT_TOLERANCE: f64 = 1e-3;
/// The default number of random states of a table's deviation check.
pub const DEFAULT_CHECK_POINTS: usize = 100_000;
/// The default largest table, in values (cells or nodes).
pub const DEFAULT_MAX_SIZE: usize = 1 << 22;

impl SurrogateOptions {
    /// Defaults over a box: automatic kind, [`DEFAULT_TOLERANCE`], [`DEFAULT_CHECK_POINTS`]
    /// check states, [`DEFAULT_MAX_SIZE`] values at most, 201 points per axis for a uniform
    /// table.
    pub fn over(p: Range, v: Range, t: Option<Range>) -> Self {
        SurrogateOptions {
            kind: None,
            pressure_pa: p,
            velocity_m_s: v,
            temperature_k: t,
            uniform_points: [201, 201, 21],
            tolerance: DEFAULT_TOLERANCE,
            check_points: DEFAULT_CHECK_POINTS,
            seed: 1,
            max_size: DEFAULT_MAX_SIZE,
        }
    }
    /// Defaults over a law's validity domain.
    pub fn over_domain(d: &ValidityDomain) -> Self {
        Self::over(d.pressure_pa, d.sliding_velocity_m_s, d.temperature_k)
    }
    fn bounds(&self) -> ValidityDomain {
        ValidityDomain {
            pressure_pa: self.pressure_pa,
            sliding_velocity_m_s: self.velocity_m_s,
            temperature_k: self.temperature_k,
        }
    }
}

/// Exact for piecewise-constant laws ([`FrictionLaw::breaks`] with `constant_between`),
/// adaptive for every other.
pub fn auto_kind(law: &dyn FrictionLaw) -> TableKind {
    match law.breaks() {
        Some(b) if b.constant_between => TableKind::Exact,
        _ => TableKind::Adaptive,
    }
}

/// Build the table `o` asks for, with its build-time check recorded in it.
pub fn build(law: &dyn FrictionLaw, o: &SurrogateOptions) -> Result<AnyTable> {
    Ok(match o.kind.unwrap_or_else(|| auto_kind(law)) {
        TableKind::Exact => {
            let mut t = ExactTable::build(law, o.max_size)?;
            t.check(law, o.check_points, o.seed, Some(o.bounds()));
            AnyTable::Exact(t)
        }
        TableKind::Adaptive => {
            let mut r = RefineOptions::over(o.pressure_pa, o.velocity_m_s, o.temperature_k);
            r.tolerance = o.tolerance;
            r.check_points = o.check_points;
            r.seed = o.seed;
            r.max_nodes = o.max_size;
            AnyTable::Adaptive(AdaptiveTable::refine(law, &r)?)
        }
        TableKind::Uniform => {
            let axis = |r: Range, n: usize| Axis::new(r.min, r.max, n);
            let [np, nv, nt] = o.uniform_points;
            let temperature = o.temperature_k.map(|t| axis(t, nt)).transpose()?;
            let mut t = TabulatedLaw::bake(
                law,
                axis(o.pressure_pa, np)?,
                axis(o.velocity_m_s, nv)?,
                temperature,
            );
            t.check(law, o.check_points, o.seed);
            AnyTable::Uniform(t)
        }
    })
}

/// Max |table − law| and the number of states: `n` seeded random states in `bounds`, plus
/// for an exact table every line and its neighbouring floats (random elsewhere in `bounds`).
/// Use a seed the build did not use, so that the states are fresh.
pub fn fresh_deviation(
    table: &AnyTable,
    law: &dyn FrictionLaw,
    bounds: &ValidityDomain,
    n: usize,
    seed: u64,
) -> (f64, usize) {
    if let AnyTable::Exact(t) = table {
        let mut t = t.clone();
        let d = t.check(law, n, seed, Some(*bounds));
        return (d, t.check_points.unwrap_or(n));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut pick = |r: Range| rng.gen_range(r.min..=r.max);
    let tk = match table {
        AnyTable::Adaptive(a) => a.temperature_k[0],
        AnyTable::Uniform(u) => u.temperature_k,
        AnyTable::Exact(_) => ContactState::ROOM_TEMPERATURE_K,
    };
    let worst = (0..n)
        .map(|_| {
            let s = ContactState {
                pressure_pa: pick(bounds.pressure_pa),
                sliding_velocity_m_s: pick(bounds.sliding_velocity_m_s),
                temperature_k: bounds.temperature_k.map_or(tk, &mut pick),
            };
            deviation(table.law().mu(&s), law.mu(&s))
        })
        .fold(0.0, f64::max);
    (worst, n)
}
