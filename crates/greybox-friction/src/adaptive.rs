//! Adaptive tables for smooth laws (SVR, MLP, grey-box compositions, any law): a
//! tensor-product grid with non-uniform axes over a (p, |v|[, T]) box, evaluated by bilinear
//! (trilinear with T) interpolation and clamped at the box edges, refined where the law
//! curves until the max deviation on a dense check set is within a tolerance (aiming for
//! [`AIM`] × the tolerance there, so that unseen states stay within it).
//!
//! Refinement ([`AdaptiveTable::refine`]): start from a few uniform lines per axis (plus two
//! lines one ulp apart at every jump the law declares, [`FrictionLaw::breaks`], so a step
//! costs no refinement); then, each round, measure |table − law| on a seeded set of random
//! states (evaluated once) and at every cell centre. Every cell where it exceeds the
//! tolerance is split along the axes whose edge-midpoint error — the 1-D interpolation error
//! |μ(x_mid) − (μ(x₀) + μ(x₁))/2| along that axis, ≈ h²/8 · ∂²μ/∂x², or the same at the
//! coordinate of the cell's worst check state (which finds kinks off the middle) — is at
//! least half the cell's largest (all axes when no edge error reaches a quarter of the aim:
//! the error is a cross term). Insertion is by bisection of the interval. It stops when no check
//! state exceeds [`AIM`] × the tolerance, and fails with an error naming the cap when the grid would
//! need more than `max_nodes` nodes.

use crate::exact_table::deviation;
use crate::lines::{lerp, Lines};
use greybox_core::law::{Range, ValidityDomain};
use greybox_core::{ContactState, Error, FrictionLaw, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// Refinement rounds before giving up (each halves the cells it splits).
const MAX_ROUNDS: usize = 64;
/// The refinement aims for this fraction of the tolerance on its check set, so that states
/// it never saw (between check points, near kinks) stay within the tolerance.
pub const AIM: f64 = 0.5;

/// A law on a non-uniform tensor grid. `values[(it·nv + iv)·np + ip]`, pressure fastest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AdaptiveTable {
    /// [`crate::table_file::TABLE_SCHEMA`].
    pub schema: String,
    pub schema_version: u32,
    /// "adaptive".
    pub kind: String,
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

    /// Evaluate `law` at every node of `axes`.
    fn bake(law: &dyn FrictionLaw, axes: &[Vec<f64>; 3], tolerance: f64) -> Result<Self> {
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
            schema: crate::table_file::TABLE_SCHEMA.into(),
            schema_version: crate::table_file::TABLE_SCHEMA_VERSION,
            kind: "adaptive".into(),
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

    fn axis(&self, a: usize) -> &[f64] {
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

    fn cell_at(&self, s: &ContactState) -> [usize; 3] {
        self.locate(s).map(|(j, _)| j)
    }

    #[inline]
    fn at(&self, ip: usize, iv: usize, it: usize) -> f64 {
        self.values[(it * self.velocity_m_s.len() + iv) * self.pressure_pa.len() + ip]
    }

    #[inline]
    fn bilinear(&self, (ip, fp): (usize, f64), (iv, fv): (usize, f64), it: usize) -> f64 {
        let lo = fast_lerp(self.at(ip, iv, it), self.at(ip + 1, iv, it), fp);
        let hi = fast_lerp(self.at(ip, iv + 1, it), self.at(ip + 1, iv + 1, it), fp);
        fast_lerp(lo, hi, fv)
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

/// a + f(b − a): exact at f = 0 and where a == b, within an ulp of b at f = 1.
#[inline]
fn fast_lerp(a: f64, b: f64, f: f64) -> f64 {
    a + f * (b - a)
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
            "{why}: {} × {} × {} nodes after {round} rounds, max deviation still {:.3e}{at} (tolerance {tolerance:.1e}); raise the node cap (max_nodes, --max-table-nodes) or the tolerance (--tolerance)",
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
