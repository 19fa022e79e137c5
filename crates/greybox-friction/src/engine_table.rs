//! The table an export writes, in the engine's units: its axes as written, μ at every node,
//! exact step lines for tree ensembles, and its max deviation from the law.
//!
//! **What the engine does with the table.** Abaqus (`*FRICTION` with slip-rate, pressure and
//! temperature dependence), LS-DYNA (`*DEFINE_TABLE` of `*DEFINE_CURVE`s) and DEFORM
//! (`FRCFAC` FricDefType 5) interpolate linearly between the table's points and hold μ at
//! the nearest edge outside it (as their manuals describe tabular data; check your release).
//! The check here emulates exactly that — multilinear interpolation in the engine's units,
//! clamped — and compares it with the law at the SI state the engine's numbers denote,
//! on a dense set inside the grid: seeded random points, every cell centre, and every axis
//! value's neighbouring floats.
//!
//! **Exact steps.** A piecewise-constant law ([`Breaks`] with `constant_between`, a tree
//! ensemble) steps at each threshold b (SI). Restated in the engine's unit,
//! b_e = [`last_true`]`(x ↦ to_si(x) ≤ b)`, so x_e ≤ b_e ⟺ the law's left side. Two points,
//! b_e and its next float b_e⁺, represent the step exactly for a linearly interpolating
//! engine: no number lies between them, and on either side μ is constant. With every
//! threshold inside the grid written this way (plus the grid's ends), the export's deviation
//! is 0. Numbers are written in Rust's shortest round-trip form, so an engine that reads
//! them as f64 gets b_e and b_e⁺ bit for bit; an engine that reads single precision merges
//! each pair into one abscissa (a vertical step), which is still exact away from the step.

use crate::exact_table::deviation;
use crate::grid::Grid;
use crate::lines::multilinear;
use greybox_core::boundary::last_true;
use greybox_core::physics::Quantity;
use greybox_core::rules::Compact;
use greybox_core::units::{PressureUnit, TemperatureUnit, VelocityUnit};
use greybox_core::{Breaks, ContactState, Error, FrictionLaw, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Most cell centres a check visits.
const MAX_CENTRES: usize = 1 << 21;

/// Where an export puts its grid lines.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StepLines {
    /// `On` for piecewise-constant laws (tree ensembles), `Off` otherwise.
    #[default]
    Auto,
    /// Two points per jump the law declares (b_e, b_e⁺ in the engine's unit) inside the
    /// grid. A piecewise-constant law keeps only the grid's ends besides them (its table is
    /// exact); any other law keeps the given grid too.
    On,
    /// The given grid only.
    Off,
}

greybox_core::choice!(StepLines, "steps", [Auto => "auto", On => "on", Off => "off"]);

/// How an export builds and checks its table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TableOptions {
    pub steps: StepLines,
    /// Random points of the deviation check (0: no check).
    pub check_points: usize,
    pub seed: u64,
}

impl Default for TableOptions {
    fn default() -> Self {
        TableOptions {
            steps: StepLines::Auto,
            check_points: 100_000,
            seed: 42,
        }
    }
}

/// The unit of an engine axis and its map to SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AxisUnit {
    Speed(VelocityUnit),
    Pressure(PressureUnit),
    Temperature(TemperatureUnit),
}

impl AxisUnit {
    /// The SI value (m/s, Pa, K) an engine number denotes.
    pub fn to_si(self, x: f64) -> f64 {
        match self {
            AxisUnit::Speed(u) => u.to_m_s(x),
            AxisUnit::Pressure(u) => u.to_pa(x),
            AxisUnit::Temperature(u) => u.to_k(x),
        }
    }
    /// The engine number written for an SI value.
    pub fn from_si(self, x: f64) -> f64 {
        match self {
            AxisUnit::Speed(u) => x * u.per_m_s(),
            AxisUnit::Pressure(u) => x * u.per_pa(),
            AxisUnit::Temperature(u) => u.from_k(x),
        }
    }
}

/// One axis of an exported table.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineAxis {
    pub unit: AxisUnit,
    /// The numbers written, ascending.
    pub written: Vec<f64>,
    /// The SI value μ is evaluated at for each.
    pub si: Vec<f64>,
}

impl EngineAxis {
    /// The given SI values, written in `unit` (μ evaluated at the given values).
    fn given(unit: AxisUnit, si: &[f64]) -> Self {
        EngineAxis {
            unit,
            written: si.iter().map(|&x| unit.from_si(x)).collect(),
            si: si.to_vec(),
        }
    }
    /// Step lines b_e, b_e⁺ for the SI `breaks` inside the written range, plus the range's
    /// ends (and, unless `only_ends`, every given value); μ is evaluated at to_si(written).
    fn stepped(&self, breaks: &[f64], only_ends: bool) -> Self {
        let (lo, hi) = (self.written[0], self.written[self.written.len() - 1]);
        let mut w: Vec<f64> = if only_ends {
            vec![lo, hi]
        } else {
            self.written.clone()
        };
        for &b in breaks {
            let Some(be) = last_true(|x| self.unit.to_si(x) <= b) else {
                continue;
            };
            if be.is_finite() && be >= lo && be.next_up() <= hi {
                w.extend([be, be.next_up()]);
            }
        }
        w.sort_by(f64::total_cmp);
        w.dedup();
        EngineAxis {
            unit: self.unit,
            si: w.iter().map(|&x| self.unit.to_si(x)).collect(),
            written: w,
        }
    }
}

/// The largest deviation of an exported table from its law, and where.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Deviation {
    /// max |μ_table − μ_law| on the check set.
    pub max: f64,
    /// Points checked.
    pub points: usize,
    /// The state of the largest deviation (SI).
    pub at: Option<ContactState>,
}

/// An exported table: μ on the tensor grid of its axes.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineTable {
    pub speed: EngineAxis,
    pub pressure: EngineAxis,
    /// Absent: evaluated at room temperature, no temperature column.
    pub temperature: Option<EngineAxis>,
    /// μ at node (speed iv, pressure ip, temperature it): `mu[(it·np + ip)·nv + iv]`.
    pub mu: Vec<f64>,
    /// Whether the axes carry the law's step lines.
    pub exact_steps: bool,
    /// μ outside its usual range ([`greybox_core::physics`]): the first node's line and how
    /// many more; the exports write it into their header.
    pub unusual: Option<String>,
}

impl EngineTable {
    /// Evaluate `law` on `grid` (SI) written in `units` (speed, pressure, temperature), with
    /// step lines as `steps` says. Every μ must be finite and ≥ 0.
    pub fn build(
        law: &dyn FrictionLaw,
        grid: &Grid,
        units: (VelocityUnit, PressureUnit, TemperatureUnit),
        steps: StepLines,
    ) -> Result<Self> {
        grid.validate()?;
        let mut speed = EngineAxis::given(AxisUnit::Speed(units.0), &grid.velocity_m_s);
        let mut pressure = EngineAxis::given(AxisUnit::Pressure(units.1), &grid.pressure_pa);
        let mut temperature = grid
            .temperature_k
            .as_deref()
            .map(|t| EngineAxis::given(AxisUnit::Temperature(units.2), t));
        let breaks: Option<Breaks> = match steps {
            StepLines::Off => None,
            StepLines::On => law.breaks(),
            StepLines::Auto => law.breaks().filter(|b| b.constant_between),
        };
        let exact_steps = breaks.is_some();
        if let Some(b) = breaks.map(Breaks::normalize) {
            let ends = b.constant_between;
            speed = speed.stepped(&b.sliding_velocity_m_s, ends);
            pressure = pressure.stepped(&b.pressure_pa, ends);
            temperature = temperature.map(|t| t.stepped(&b.temperature_k, ends));
        }
        let temps = temperature
            .as_ref()
            .map_or(vec![ContactState::ROOM_TEMPERATURE_K], |t| t.si.clone());
        let mut mu = Vec::with_capacity(temps.len() * pressure.si.len() * speed.si.len());
        let (mut first_unusual, mut unusual_count) = (None, 0usize);
        for &t in &temps {
            for &p in &pressure.si {
                for &v in &speed.si {
                    let (m, flag) = mu_flagged(
                        law,
                        &ContactState {
                            pressure_pa: p,
                            sliding_velocity_m_s: v,
                            temperature_k: t,
                        },
                    )?;
                    if let Some(f) = flag {
                        unusual_count += 1;
                        first_unusual.get_or_insert(f);
                    }
                    mu.push(m);
                }
            }
        }
        let unusual = first_unusual.map(|f| match unusual_count {
            1 => f,
            2 => format!("{f} (and 1 more node)"),
            n => format!("{f} (and {} more nodes)", n - 1),
        });
        Ok(EngineTable {
            speed,
            pressure,
            temperature,
            mu,
            exact_steps,
            unusual,
        })
    }

    /// μ at node (speed iv, pressure ip, temperature it).
    pub fn at(&self, iv: usize, ip: usize, it: usize) -> f64 {
        self.mu[(it * self.pressure.si.len() + ip) * self.speed.si.len() + iv]
    }

    /// Nodes per axis: speed, pressure, temperature (1 without).
    pub fn shape(&self) -> [usize; 3] {
        [
            self.speed.si.len(),
            self.pressure.si.len(),
            self.temperature.as_ref().map_or(1, |t| t.si.len()),
        ]
    }

    fn axes(&self) -> [Option<&EngineAxis>; 3] {
        [
            Some(&self.speed),
            Some(&self.pressure),
            self.temperature.as_ref(),
        ]
    }

    /// The SI state of engine coordinates (speed, pressure, temperature).
    fn state(&self, x: [f64; 3]) -> ContactState {
        ContactState {
            sliding_velocity_m_s: self.speed.unit.to_si(x[0]),
            pressure_pa: self.pressure.unit.to_si(x[1]),
            temperature_k: self
                .temperature
                .as_ref()
                .map_or(ContactState::ROOM_TEMPERATURE_K, |t| t.unit.to_si(x[2])),
        }
    }

    /// What a linearly interpolating engine reads at engine coordinates `x`.
    pub fn interpolate(&self, x: [f64; 3]) -> f64 {
        let room = [0.0];
        let axes = self.axes().map(|a| a.map_or(&room[..], |a| &a.written[..]));
        multilinear(axes, &self.mu, x)
    }

    /// Max |interpolated − law| on `n` seeded random points in the grid, every cell centre,
    /// and every axis value's neighbouring floats inside the grid (random elsewhere).
    pub fn check(&self, law: &dyn FrictionLaw, n: usize, seed: u64) -> Deviation {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let axes = self.axes();
        let span = |a: usize| {
            axes[a].map_or((0.0, 0.0), |ax| {
                (ax.written[0], ax.written[ax.written.len() - 1])
            })
        };
        let spans = [span(0), span(1), span(2)];
        let random = |rng: &mut ChaCha8Rng| {
            spans.map(|(lo, hi)| if hi > lo { rng.gen_range(lo..=hi) } else { lo })
        };
        let mut points: Vec<[f64; 3]> = (0..n).map(|_| random(&mut rng)).collect();
        let mids = |a: usize| -> Vec<f64> {
            match axes[a] {
                Some(ax) if ax.written.len() > 1 => ax
                    .written
                    .windows(2)
                    .map(|w| 0.5 * w[0] + 0.5 * w[1])
                    .collect(),
                _ => vec![spans[a].0],
            }
        };
        let (m0, m1, m2) = (mids(0), mids(1), mids(2));
        let centres = if m0.len() * m1.len() * m2.len() <= MAX_CENTRES {
            &m2[..]
        } else {
            &[] // a huge table: random points and the lines' neighbours only
        };
        for &z in centres {
            for &y in &m1 {
                points.extend(m0.iter().map(|&x| [x, y, z]));
            }
        }
        for (a, ax) in axes.iter().enumerate() {
            let Some(ax) = ax else { continue };
            for &x in &ax.written {
                for y in [x.next_down(), x.next_up()] {
                    if y >= spans[a].0 && y <= spans[a].1 {
                        let mut p = random(&mut rng);
                        p[a] = y;
                        points.push(p);
                    }
                }
            }
        }
        let mut worst = Deviation {
            max: 0.0,
            points: points.len(),
            at: None,
        };
        for x in points {
            let s = self.state(x);
            let d = deviation(self.interpolate(x), law.mu(&s));
            if d > worst.max || worst.at.is_none() {
                worst.max = worst.max.max(d);
                worst.at = Some(s);
            }
        }
        worst
    }
}

/// μ at a state, which must be finite and ≥ 0 for a table.
pub fn mu_checked(law: &dyn FrictionLaw, s: &ContactState) -> Result<f64> {
    Ok(mu_flagged(law, s)?.0)
}

/// [`mu_checked`] with the physics table's flag ([`greybox_core::physics`]): μ outside the
/// possible range 0..3 refused, outside the usual range returned with its line.
pub fn mu_flagged(law: &dyn FrictionLaw, s: &ContactState) -> Result<(f64, Option<String>)> {
    let mu = law.mu(s);
    let at = format!(
        "the law at p = {} Pa, v = {} m/s, T = {} K",
        Compact(s.pressure_pa),
        Compact(s.sliding_velocity_m_s),
        Compact(s.temperature_k)
    );
    match greybox_core::physics::check(Quantity::Mu, mu, &at) {
        Ok(flag) => Ok((mu, flag.map(|f| f.text))),
        Err(e) => Err(Error::invalid("export", e)),
    }
}
