//! Refinement of adaptive tables ([`AdaptiveTable::refine`]).
//!
//! Start from a few uniform lines per axis (plus two lines one ulp apart at every jump the law
//! declares, [`FrictionLaw::breaks`], so a step costs no refinement). Then, each round,
//! measure |table − law| on a seeded set of random states (the law evaluated once) and at
//! every cell centre. Every cell where it exceeds [`AIM`] × the tolerance is split along the
//! axes whose edge error — the 1-D interpolation error |μ(x) − lerp(μ(x₀), μ(x₁))| along that
//! axis on the cell's edges, at the interval's midpoint (≈ h²/8 · ∂²μ/∂x²) and at the
//! coordinate of the cell's worst check state (which finds kinks off the middle) — is at
//! least half the cell's largest; all axes when no edge error reaches a quarter of the aim
//! (the error is a cross term). Insertion is by bisection of the interval. It stops when no
//! check state exceeds the aim, and fails with an error naming the cap when the grid would
//! need more than `max_nodes` nodes, or when 64 rounds do not reach the aim.

use crate::adaptive::AdaptiveTable;
use crate::exact_table::deviation;
use crate::lines::lerp;
use greybox_core::law::Range;
use greybox_core::{ContactState, Error, FrictionLaw, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::{BTreeMap, BTreeSet};

/// Refinement rounds before giving up (each halves the cells it splits).
const MAX_ROUNDS: usize = 64;
/// The refinement aims for this fraction of the tolerance on its check set, so that states
/// it never saw (between check points, near kinks) stay within the tolerance.
pub const AIM: f64 = 0.5;

/// What [`AdaptiveTable::refine`] aims for and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefineOptions {
    /// Box: pressure, Pa.
    pub pressure_pa: Range,
    /// Box: sliding speed, m/s.
    pub velocity_m_s: Range,
    /// Box: temperature, K (`None`: μ(p, v) at `reference_temperature_k`).
    pub temperature_k: Option<Range>,
    pub reference_temperature_k: f64,
    /// Max |table − law| on the check set.
    pub tolerance: f64,
    /// Random check states (the cell centres come on top).
    pub check_points: usize,
    pub seed: u64,
    /// Uniform lines per axis to start from (≥ 2).
    pub initial_lines: usize,
    /// Cap on the number of nodes.
    pub max_nodes: usize,
}

impl RefineOptions {
    /// Defaults over a law's validity domain: tolerance 1e-4, 100 000 random check states,
    /// 9 initial lines, at most 4 Mi nodes.
    pub fn over_domain(law: &dyn FrictionLaw) -> Result<Self> {
        let d = law.domain().ok_or_else(|| {
            Error::invalid(
                "adaptive table",
                format!("{} has no validity domain: give the box", law.name()),
            )
        })?;
        Ok(Self::over(
            d.pressure_pa,
            d.sliding_velocity_m_s,
            d.temperature_k,
        ))
    }
    /// Defaults over a box.
    pub fn over(p: Range, v: Range, t: Option<Range>) -> Self {
        RefineOptions {
            pressure_pa: p,
            velocity_m_s: v,
            temperature_k: t,
            reference_temperature_k: ContactState::ROOM_TEMPERATURE_K,
            tolerance: 1e-4,
            check_points: 100_000,
            seed: 1,
            initial_lines: 9,
            max_nodes: 1 << 22,
        }
    }
    fn validate(&self) -> Result<()> {
        let mut rules = greybox_core::rules::Rules::new("adaptive table");
        for (name, r) in [
            ("pressure range", Some(self.pressure_pa)),
            ("velocity range", Some(self.velocity_m_s)),
            ("temperature range", self.temperature_k),
        ] {
            if let Some(r) = r {
                rules.relation(
                    r.min.is_finite() && r.max.is_finite() && r.max > r.min,
                    format!("{name} needs finite min < max, got {}..{}", r.min, r.max),
                );
            }
        }
        rules
            .relation(
                self.velocity_m_s.min >= 0.0,
                "velocity range must be ≥ 0 (tables see the sliding speed |v|)",
            )
            .positive("tolerance", self.tolerance)
            .finite("reference_temperature_K", self.reference_temperature_k)
            .at_least("initial_lines", self.initial_lines as u64, 2)
            .at_least("max_nodes", self.max_nodes as u64, 4);
        rules.finish()
    }
    fn ranges(&self) -> [Option<Range>; 3] {
        [
            Some(self.pressure_pa),
            Some(self.velocity_m_s),
            self.temperature_k,
        ]
    }
}

/// `n` uniform lines over `r`, plus both sides of every jump strictly inside it.
fn initial_axis(r: Range, n: usize, jumps: &[f64]) -> Vec<f64> {
    let mut l: Vec<f64> = (0..n)
        .map(|i| r.min + (r.max - r.min) * i as f64 / (n - 1) as f64)
        .collect();
    l[n - 1] = r.max;
    for &b in jumps {
        if b >= r.min && b.next_up() <= r.max {
            l.extend([b, b.next_up()]);
        }
    }
    l.sort_by(f64::total_cmp);
    l.dedup();
    l
}

impl AdaptiveTable {
    /// Refine a table of `law` over the box of `o` until its max deviation on the check set
    /// is ≤ `o.tolerance` (see the module docs).
    pub fn refine(law: &dyn FrictionLaw, o: &RefineOptions) -> Result<Self> {
        o.validate()?;
        let breaks = law.breaks().map(|b| b.normalize()).unwrap_or_default();
        let mut axes: [Vec<f64>; 3] = std::array::from_fn(|a| match o.ranges()[a] {
            Some(r) => initial_axis(r, o.initial_lines, breaks.axis(a)),
            None => vec![o.reference_temperature_k],
        });
        let checks = random_states(o, o.check_points);
        let truth: Vec<f64> = checks.iter().map(|s| law.mu(s)).collect();
        for round in 0.. {
            greybox_core::interrupt::check()?;
            let table = Self::bake(law, &axes, o.tolerance)?;
            let mut bad = BadCells::new();
            let mut worst = (0.0f64, checks.first().copied());
            let mut judge = |s: &ContactState, mu: f64, bad: &mut BadCells| {
                let e = deviation(table.mu(s), mu);
                if e > worst.0 {
                    worst = (e, Some(*s));
                }
                if e > AIM * o.tolerance {
                    let x = [s.pressure_pa, s.sliding_velocity_m_s.abs(), s.temperature_k];
                    let w = bad.entry(table.cell_at(s)).or_insert((e, x));
                    if e > w.0 {
                        *w = (e, x);
                    }
                }
            };
            for (s, &mu) in checks.iter().zip(&truth) {
                judge(s, mu, &mut bad);
            }
            let centres = table.cell_centres();
            for s in &centres {
                judge(s, law.mu(s), &mut bad);
            }
            if bad.is_empty() {
                let mut table = table;
                table.max_deviation = Some(worst.0);
                table.check_points = Some(checks.len() + centres.len());
                return Ok(table);
            }
            let splits = table.choose_splits(law, &bad);
            let fail = |why: &str| refine_error(why, table.shape(), round, worst, o.tolerance);
            if splits.iter().all(|s| s.is_empty()) || round + 1 >= MAX_ROUNDS {
                return Err(fail("refinement stalls (a jump the law does not declare?)"));
            }
            for (a, s) in splits.iter().enumerate() {
                let mids: Vec<f64> = s
                    .iter()
                    .map(|&j| 0.5 * axes[a][j] + 0.5 * axes[a][j + 1])
                    .collect();
                axes[a].extend(mids);
                axes[a].sort_by(f64::total_cmp);
                axes[a].dedup();
            }
            if axes.iter().map(Vec::len).product::<usize>() > o.max_nodes {
                return Err(fail(&format!(
                    "the table would need more than the cap of {} nodes",
                    o.max_nodes
                )));
            }
        }
        unreachable!("the refinement loop returns")
    }

    /// Centres of the cells wider than one ulp on every axis they span.
    fn cell_centres(&self) -> Vec<ContactState> {
        let mids = |a: usize| -> Vec<f64> {
            let l = self.axis(a);
            if l.len() == 1 {
                return l.to_vec();
            }
            l.windows(2)
                .map(|w| 0.5 * w[0] + 0.5 * w[1])
                .filter(|&m| l.binary_search_by(|x| x.total_cmp(&m)).is_err())
                .collect()
        };
        let (mp, mv, mt) = (mids(0), mids(1), mids(2));
        let mut out = Vec::with_capacity(mp.len() * mv.len() * mt.len());
        for &t in &mt {
            for &v in &mv {
                for &p in &mp {
                    out.push(ContactState {
                        pressure_pa: p,
                        sliding_velocity_m_s: v,
                        temperature_k: t,
                    });
                }
            }
        }
        out
    }

    /// Per axis, the intervals to bisect for the cells in `bad` (see the module docs).
    fn choose_splits(&self, law: &dyn FrictionLaw, bad: &BadCells) -> [BTreeSet<usize>; 3] {
        let mut out: [BTreeSet<usize>; 3] = Default::default();
        let dims = if self.temperature_k.len() > 1 { 3 } else { 2 };
        for (cell, (_, at)) in bad {
            let mut err = [0.0f64; 3];
            let mut splittable = [false; 3];
            for a in 0..dims {
                let (l, j) = (self.axis(a), cell[a]);
                let mid = 0.5 * l[j] + 0.5 * l[j + 1];
                splittable[a] = mid > l[j] && mid < l[j + 1];
                if splittable[a] {
                    let inside = at[a].clamp(l[j], l[j + 1]);
                    err[a] = self
                        .edge_error(law, cell, a, mid)
                        .max(self.edge_error(law, cell, a, inside));
                }
            }
            let top = err.iter().copied().fold(0.0, f64::max);
            for a in (0..dims).filter(|&a| splittable[a]) {
                if err[a] >= 0.5 * top || top < 0.25 * AIM * self.tolerance {
                    out[a].insert(cell[a]);
                }
            }
        }
        out
    }

    /// Largest 1-D interpolation error at `x` along axis `a` on the cell's edges in that
    /// direction (over the corners of the other axes).
    fn edge_error(&self, law: &dyn FrictionLaw, cell: &[usize; 3], a: usize, x: f64) -> f64 {
        let mut worst: f64 = 0.0;
        let last = |b: usize| self.axis(b).len() - 1;
        let dims = if self.temperature_k.len() > 1 { 3 } else { 2 };
        let l = self.axis(a);
        let f = (x - l[cell[a]]) / (l[cell[a] + 1] - l[cell[a]]);
        for corner in 0..1usize << (dims - 1) {
            let mut idx = *cell;
            for (bit, b) in (0..3).filter(|&b| b != a).enumerate() {
                idx[b] = (cell[b] + ((corner >> bit) & 1)).min(last(b));
            }
            let node = |k: usize| {
                let mut i = idx;
                i[a] = k;
                self.at(i[0], i[1], i[2])
            };
            let (lo, hi) = (node(cell[a]), node(cell[a] + 1));
            let mut p = [0.0; 3];
            for (b, pb) in p.iter_mut().enumerate() {
                *pb = if b == a { x } else { self.axis(b)[idx[b]] };
            }
            let s = ContactState {
                pressure_pa: p[0],
                sliding_velocity_m_s: p[1],
                temperature_k: p[2],
            };
            worst = worst.max(deviation(law.mu(&s), lerp(lo, hi, f)));
        }
        worst
    }
}

/// Cells over the aim, each with its largest error and where (p, |v|, T).
type BadCells = BTreeMap<[usize; 3], (f64, [f64; 3])>;

/// The error of a refinement that cannot reach its tolerance.
fn refine_error(
    why: &str,
    shape: [usize; 3],
    round: usize,
    worst: (f64, Option<ContactState>),
    tolerance: f64,
) -> Error {
    let at = worst.1.map_or(String::new(), |s| {
        format!(
            " at p = {:.6e} Pa, v = {:.6e} m/s, T = {} K",
            s.pressure_pa, s.sliding_velocity_m_s, s.temperature_k
        )
    });
    Error::invalid(
        "adaptive table",
        format!(
            "{why}: {} × {} × {} nodes after {round} rounds, max deviation still {:.3e}{at} (tolerance {tolerance:.1e}); raise the size cap (`max_table_size`) or the tolerance (`tolerance`), or tabulate a smaller box",
            shape[0], shape[1], shape[2], worst.0
        ),
    )
}

/// `n` seeded random states in the box of `o`.
fn random_states(o: &RefineOptions, n: usize) -> Vec<ContactState> {
    let mut rng = ChaCha8Rng::seed_from_u64(o.seed);
    (0..n)
        .map(|_| ContactState {
            pressure_pa: rng.gen_range(o.pressure_pa.min..=o.pressure_pa.max),
            sliding_velocity_m_s: rng.gen_range(o.velocity_m_s.min..=o.velocity_m_s.max),
            temperature_k: o
                .temperature_k
                .map_or(o.reference_temperature_k, |t| rng.gen_range(t.min..=t.max)),
        })
        .collect()
}
