//! Friction tables for FE engines, evaluated from any law on a (p, v[, T]) grid.
//!
//! * Abaqus `*FRICTION` data lines (μ, slip rate, contact pressure[, temperature]); first
//!   variable fastest, all ascending (Abaqus keyword reference, `*FRICTION`). Abaqus has no
//!   unit system: the units are the user's choice and are stated in the header.
//! * DEFORM `FRCFAC` (FricType 2 Coulomb, FricDefType 5: μ(pressure, temperature, stretch),
//!   pressure fastest) at a reference velocity, and one `FRCWIN` per friction window with the
//!   window's μ as a constant (FricDefType 0) — the syntax of the DEFORM v14 manual
//!   (shared/docs/research/fe-engine-interfaces.md §3.1).
//! * LS-DYNA `*DEFINE_TABLE` (abscissa: sliding velocity) with one `*DEFINE_CURVE` per velocity
//!   (μ against contact pressure), for `*CONTACT_..._SURFACE_TO_SURFACE` with FS = 2, FD = table.
//! * CSV of the grid itself.
//!
//! Every table is built as an [`EngineTable`] in the engine's units: μ at the SI state each
//! written number denotes, grid lines at a tree ensemble's split thresholds (two points one
//! float apart per threshold, [`StepLines`]), and — in the `*_checked` forms — its max
//! deviation from the law under the engine's linear interpolation ([`Deviation`]; 0 for
//! tree ensembles with step lines). See [`crate::engine_table`] for how each engine reads
//! the table.
//!
//! The formats and their options are registered in [`engine`] (one list, with the defaults);
//! [`write::table_text`] dispatches a table's spec to its writer below, so that an export from
//! the pipeline walks down once, to here.
//!
//! Any [`FrictionLaw`] goes to an engine this way — here a Coulomb law as Abaqus lines in
//! the tonne–mm–s–MPa system (slip rates in mm/s), checked against the law:
//!
//! ```
//! use greybox_friction::classical::Coulomb;
//! use greybox_core::units::TemperatureUnit;
//! use greybox_friction::export::{abaqus_checked, Grid, TableOptions, Units};
//! use greybox_friction::grid::UnitSystem;
//! let grid = Grid {
//!     pressure_pa: vec![500e6, 1000e6],
//!     velocity_m_s: vec![1.0, 2.0],
//!     temperature_k: None,
//! };
//! let units = Units::of(UnitSystem::MpaMmS, TemperatureUnit::C);
//! let e = abaqus_checked(&Coulomb { mu: 0.3 }, &grid, units, None, &TableOptions::default())?;
//! assert!(e.text.contains("*FRICTION"));
//! assert!(e.text.contains(" 0.3, 1000.0, 500.0")); // μ, slip rate (mm/s), pressure (MPa)
//! assert_eq!(e.deviation.unwrap().max, 0.0);
//! # Ok::<(), greybox_core::Error>(())
//! ```

pub mod domain;
pub mod engine;
pub mod write;

use crate::engine_table::mu_checked;
pub use crate::engine_table::{Deviation, EngineTable, StepLines, TableOptions};
pub use crate::grid::{Grid, Units};
use greybox_core::escape::deck_comment;
use greybox_core::units::{PressureUnit, TemperatureUnit, VelocityUnit};
use greybox_core::{ContactState, Error, FrictionLaw, Result, SourcePos};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

fn num(x: f64) -> String {
    // shortest representation that round-trips, always with a decimal point (Fortran-friendly)
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.")
    }
}

/// An exported table: the text, the table it writes, and its deviation from the law.
#[derive(Debug, Clone, PartialEq)]
pub struct Exported {
    pub text: String,
    pub table: EngineTable,
    /// Max deviation of the engine's (linear) interpolation from the law inside the grid;
    /// `None` when not checked (`check_points` 0).
    pub deviation: Option<Deviation>,
}

impl Exported {
    fn new(law: &dyn FrictionLaw, table: EngineTable, o: &TableOptions) -> Self {
        let deviation = (o.check_points > 0).then(|| table.check(law, o.check_points, o.seed));
        Exported {
            text: String::new(),
            table,
            deviation,
        }
    }
    /// Header comment lines (after `prefix`) on the grid and the check.
    fn notes(&self, prefix: &str) -> String {
        let mut s = String::new();
        if let Some(u) = &self.table.unusual {
            let _ = writeln!(s, "{prefix} unusual: {}", deck_comment(u));
        }
        if self.table.exact_steps {
            let _ = writeln!(s, "{prefix} grid lines at the law's steps: two points one float apart per split threshold (b, b+), exact for linear interpolation");
        }
        if let Some(d) = &self.deviation {
            let _ = writeln!(
                s,
                "{prefix} max deviation of this table (linear interpolation) from the law: {:e} on {} points inside the grid",
                d.max, d.points
            );
        }
        s
    }
}

/// Abaqus `*FRICTION` table. `taumax_pa`: optional limiting shear stress. Grid lines at the
/// steps of a tree-ensemble law ([`StepLines::Auto`]), not checked; see [`abaqus_checked`].
pub fn abaqus(
    law: &dyn FrictionLaw,
    grid: &Grid,
    u: Units,
    taumax_pa: Option<f64>,
) -> Result<String> {
    let o = TableOptions {
        check_points: 0,
        ..TableOptions::default()
    };
    Ok(abaqus_checked(law, grid, u, taumax_pa, &o)?.text)
}

/// Abaqus `*FRICTION` table with step lines and deviation check as `o` says. Abaqus
/// interpolates the table linearly in slip rate, pressure and temperature and holds μ
/// constant outside it.
pub fn abaqus_checked(
    law: &dyn FrictionLaw,
    grid: &Grid,
    u: Units,
    taumax_pa: Option<f64>,
    o: &TableOptions,
) -> Result<Exported> {
    if let Some(t) = taumax_pa {
        if !(t > 0.0) {
            return Err(Error::invalid("export", "TAUMAX must be positive"));
        }
    }
    let table = EngineTable::build(law, grid, (u.speed, u.pressure, u.temperature), o.steps)?;
    let mut out = Exported::new(law, table, o);
    let mut s = String::new();
    let with_t = grid.temperature_k.is_some();
    let _ = writeln!(s, "** greybox export: Abaqus *FRICTION table");
    let _ = writeln!(s, "** law: {}", deck_comment(&law.name()));
    let _ = writeln!(
        s,
        "** Abaqus has no unit system. This table uses: slip rate in {}, contact pressure in {}{}{}.",
        u.speed.name(),
        u.pressure.name(),
        if with_t { format!(", temperature in {}", u.temperature.name()) } else { String::new() },
        if taumax_pa.is_some() { format!(", TAUMAX in {}", u.pressure.name()) } else { String::new() }
    );
    let _ = writeln!(
        s,
        "** The model must use consistent units. Outside the table Abaqus holds mu constant."
    );
    let _ = writeln!(
        s,
        "** columns: mu, slip rate, contact pressure{}; slip rate varies fastest, then pressure{}",
        if with_t { ", temperature" } else { "" },
        if with_t { ", then temperature" } else { "" }
    );
    s.push_str(&out.notes("**"));
    let _ = write!(s, "*FRICTION");
    if let Some(t) = taumax_pa {
        let _ = write!(s, ", TAUMAX={}", num(t * u.pressure.per_pa()));
    }
    s.push('\n');
    let t = &out.table;
    let [nv, np, nt] = t.shape();
    for it in 0..nt {
        for ip in 0..np {
            for iv in 0..nv {
                let _ = write!(
                    s,
                    " {}, {}, {}",
                    num(t.at(iv, ip, it)),
                    num(t.speed.written[iv]),
                    num(t.pressure.written[ip])
                );
                if let Some(tt) = &t.temperature {
                    let _ = write!(s, ", {}", num(tt.written[it]));
                }
                s.push('\n');
            }
        }
    }
    out.text = s;
    Ok(out)
}

/// Data lines of the first `*FRICTION` block of an Abaqus input text.
pub fn parse_abaqus_friction(text: &str, source: &str) -> Result<Vec<Vec<f64>>> {
    let mut rows = Vec::new();
    let mut inside = false;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.starts_with("**") || t.is_empty() {
            continue;
        }
        if t.starts_with('*') {
            if inside {
                break;
            }
            inside = t.to_ascii_uppercase().starts_with("*FRICTION");
            continue;
        }
        if inside {
            let row = t
                .split(',')
                .map(|f| {
                    f.trim().parse::<f64>().map_err(|_| {
                        Error::input(
                            SourcePos::file(source).line(i as u64 + 1),
                            format!("expected a number, found '{}'", f.trim()),
                        )
                    })
                })
                .collect::<Result<Vec<f64>>>()?;
            rows.push(row);
        }
    }
    if rows.is_empty() {
        return Err(Error::input(
            SourcePos::file(source),
            "no *FRICTION data lines",
        ));
    }
    Ok(rows)
}

/// A friction window for DEFORM: a counter-clockwise polygon (m) and its representative state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeformWindow {
    /// Corner points, mm (counter-clockwise).
    pub points_mm: Vec<[f64; 2]>,
    pub pressure_mpa: f64,
    pub velocity_m_per_min: f64,
    #[serde(default = "room_k")]
    pub temperature_k: f64,
}

fn room_k() -> f64 {
    ContactState::ROOM_TEMPERATURE_K
}

/// DEFORM keyword blocks: a global `FRCFAC` μ(p, T) table at `reference_velocity_m_s` and one
/// `FRCWIN` per window (constant μ of the window's state; the window follows object
/// `objects.0`, the tool). Pressures in MPa, temperatures in °C (DEFORM's SI-mm convention).
/// Not checked; see [`deform_checked`].
pub fn deform(
    law: &dyn FrictionLaw,
    grid: &Grid,
    reference_velocity_m_s: f64,
    windows: &[DeformWindow],
    objects: (u32, u32),
) -> Result<String> {
    let o = TableOptions {
        check_points: 0,
        ..TableOptions::default()
    };
    Ok(deform_checked(law, grid, reference_velocity_m_s, windows, objects, &o)?.text)
}

/// [`deform`] with step lines and deviation check as `o` says. DEFORM interpolates the
/// FRCFAC table linearly in pressure and temperature; the check covers that table (at the
/// reference velocity), the windows are exact (μ of their own state).
pub fn deform_checked(
    law: &dyn FrictionLaw,
    grid: &Grid,
    reference_velocity_m_s: f64,
    windows: &[DeformWindow],
    objects: (u32, u32),
    o: &TableOptions,
) -> Result<Exported> {
    grid.validate()?;
    let at_reference = Grid {
        velocity_m_s: vec![reference_velocity_m_s],
        ..grid.clone()
    };
    let units = (VelocityUnit::MPerS, PressureUnit::MPa, TemperatureUnit::C);
    let table = EngineTable::build(law, &at_reference, units, o.steps)?;
    let mut out = Exported::new(law, table, o);
    let t = &out.table;
    let temps: Vec<f64> = match &t.temperature {
        Some(a) => a.written.clone(),
        None => vec![TemperatureUnit::C.from_k(ContactState::ROOM_TEMPERATURE_K)],
    };
    let (o1, o2) = objects;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "* greybox export: DEFORM inter-object friction (FRCFAC / FRCWIN)"
    );
    let _ = writeln!(s, "* law: {}", deck_comment(&law.name()));
    let _ = writeln!(s, "* FRCFAC: Coulomb (FricType 2), FricDefType 5 = f(pressure MPa, temperature C, stretch), pressure fastest,");
    let _ = writeln!(s, "* evaluated at the reference sliding velocity {} m/min (DEFORM tables cannot encode velocity)", reference_velocity_m_s * 60.0);
    s.push_str(&out.notes("*"));
    let join = |v: &[f64]| v.iter().map(|&x| num(x)).collect::<Vec<_>>().join(" ");
    let np = t.pressure.written.len();
    let _ = writeln!(s, "FRCFAC {o1} {o2} 2 5 {np} {} 1", temps.len());
    let _ = writeln!(s, "{}", join(&t.pressure.written));
    let _ = writeln!(s, "{}", join(&temps));
    let _ = writeln!(s, "0.");
    for it in 0..temps.len() {
        let row: Vec<f64> = (0..np).map(|ip| t.at(0, ip, it)).collect();
        let _ = writeln!(s, "{}", join(&row));
    }
    for (k, w) in windows.iter().enumerate() {
        s.push_str(&deform_window(law, k, w, objects)?);
    }
    out.text = s;
    Ok(out)
}

/// The comment and `FRCWIN` block of window `k` (0-based).
fn deform_window(
    law: &dyn FrictionLaw,
    k: usize,
    w: &DeformWindow,
    objects: (u32, u32),
) -> Result<String> {
    if w.points_mm.len() < 3 {
        return Err(Error::invalid(
            "DEFORM window",
            format!("window {} needs at least 3 points", k + 1),
        ));
    }
    let area2: f64 = (0..w.points_mm.len())
        .map(|i| {
            let (a, b) = (w.points_mm[i], w.points_mm[(i + 1) % w.points_mm.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    if area2 <= 0.0 {
        return Err(Error::invalid(
            "DEFORM window",
            format!("window {} is not counter-clockwise", k + 1),
        ));
    }
    let state = ContactState {
        pressure_pa: w.pressure_mpa * 1e6,
        sliding_velocity_m_s: w.velocity_m_per_min / 60.0,
        temperature_k: w.temperature_k,
    };
    let mu = mu_checked(law, &state)?;
    let mut s = format!(
        "* window {}: p = {} MPa, v = {} m/min, T = {} K\n",
        k + 1,
        w.pressure_mpa,
        w.velocity_m_per_min,
        w.temperature_k
    );
    s.push_str(&frcwin_block(k + 1, &w.points_mm, mu, objects));
    Ok(s)
}

/// One 2D `FRCWIN` block: Coulomb friction (FricType 2) with constant μ (FricDefType 0); the
/// window follows object `objects.0` (SpdType −n). Points counter-clockwise.
pub fn frcwin_block(number: usize, points: &[[f64; 2]], mu: f64, objects: (u32, u32)) -> String {
    let (o1, o2) = objects;
    let mut s = format!(
        "FRCWIN {o1} {o2} {number} {} 2 0 {} -{o1} 0. 0.\n",
        points.len(),
        num(mu)
    );
    for (i, p) in points.iter().enumerate() {
        let _ = writeln!(s, "{} {} {}", i + 1, num(p[0]), num(p[1]));
    }
    s
}

/// LS-DYNA keyword cards: `*DEFINE_TABLE` over velocity with one `*DEFINE_CURVE` (μ vs
/// pressure) per velocity. `table_id` and the following ids are used. Not checked; see
/// [`lsdyna_checked`].
pub fn lsdyna(law: &dyn FrictionLaw, grid: &Grid, u: Units, table_id: u32) -> Result<String> {
    let o = TableOptions {
        check_points: 0,
        ..TableOptions::default()
    };
    Ok(lsdyna_checked(law, grid, u, table_id, &o)?.text)
}

/// The largest id LS-DYNA reads: its keyword files hold ids in 10-character integer fields
/// read as 32-bit signed integers.
pub const LSDYNA_MAX_ID: u64 = i32::MAX as u64;

/// The last id of an LS-DYNA table `table_id` with one curve per speed (`table_id + curves`),
/// checked: ids start at 1 (0 means "none" in a keyword card) and the last must fit
/// [`LSDYNA_MAX_ID`] — never wrapped around.
pub fn lsdyna_ids(table_id: u32, curves: usize) -> Result<u64> {
    let last = u64::from(table_id) + curves as u64;
    if table_id == 0 || last > LSDYNA_MAX_ID {
        return Err(Error::invalid(
            "export.lsdyna_table_id",
            format!(
                "{table_id}: the table and its {curves} curves take the ids {table_id}..={last}, but LS-DYNA ids are 1..={LSDYNA_MAX_ID} (0 is \"none\"); choose a table id from 1 to {}",
                LSDYNA_MAX_ID.saturating_sub(curves as u64)
            ),
        ));
    }
    Ok(last)
}

/// [`lsdyna`] with step lines and deviation check as `o` says. LS-DYNA interpolates each
/// curve linearly in pressure and between the curves linearly in velocity.
pub fn lsdyna_checked(
    law: &dyn FrictionLaw,
    grid: &Grid,
    u: Units,
    table_id: u32,
    o: &TableOptions,
) -> Result<Exported> {
    grid.validate()?;
    if grid.temperature_k.is_some() {
        return Err(Error::invalid(
            "export",
            "the LS-DYNA table is μ(p, v) only; give no temperature axis",
        ));
    }
    let table = EngineTable::build(law, grid, (u.speed, u.pressure, u.temperature), o.steps)?;
    lsdyna_ids(table_id, table.speed.written.len())?;
    let mut out = Exported::new(law, table, o);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "$ greybox export: mu(pressure, sliding velocity) for LS-DYNA"
    );
    let _ = writeln!(s, "$ law: {}", deck_comment(&law.name()));
    let _ = writeln!(s, "$ Consumed by *CONTACT_SURFACE_TO_SURFACE or *CONTACT_ONE_WAY_SURFACE_TO_SURFACE with FS = 2 and");
    let _ = writeln!(s, "$ FD = {table_id}: table abscissa = relative sliding velocity, curve abscissa = contact pressure.");
    let _ = writeln!(s, "$ (FS = 2 semantics as recalled from the LS-DYNA Keyword Manual; check them in your release.)");
    let _ = writeln!(
        s,
        "$ Units: velocity in {}, pressure in {}; use a consistent unit system.",
        u.speed.name(),
        u.pressure.name()
    );
    s.push_str(&out.notes("$"));
    let _ = writeln!(s, "*DEFINE_TABLE");
    let _ = writeln!(s, "$     TBID       SFA      OFFA");
    let _ = writeln!(s, "{table_id:>10}");
    let t = &out.table;
    for &v in &t.speed.written {
        let _ = writeln!(s, "{:>20}", num(v));
    }
    for iv in 0..t.speed.written.len() {
        let _ = writeln!(s, "*DEFINE_CURVE");
        let _ = writeln!(
            s,
            "$     LCID      SIDR       SFA       SFO      OFFA      OFFO"
        );
        // ids table_id + 1 ..= table_id + curves, checked by `lsdyna_ids`
        let _ = writeln!(s, "{:>10}", u64::from(table_id) + 1 + iv as u64);
        for (ip, &p) in t.pressure.written.iter().enumerate() {
            let _ = writeln!(s, "{:>20}{:>20}", num(p), num(t.at(iv, ip, 0)));
        }
    }
    out.text = s;
    Ok(out)
}

/// The grid as CSV: `pressure_MPa,sliding_velocity_m_per_min,temperature_K,mu`. Not checked;
/// see [`csv_checked`].
pub fn csv(law: &dyn FrictionLaw, grid: &Grid) -> Result<String> {
    let o = TableOptions {
        check_points: 0,
        ..TableOptions::default()
    };
    Ok(csv_checked(law, grid, &o)?.text)
}

/// [`csv`] with step lines and deviation check as `o` says (the check assumes a reader that
/// interpolates linearly, as the engines do).
pub fn csv_checked(law: &dyn FrictionLaw, grid: &Grid, o: &TableOptions) -> Result<Exported> {
    let units = (VelocityUnit::MPerMin, PressureUnit::MPa, TemperatureUnit::K);
    let table = EngineTable::build(law, grid, units, o.steps)?;
    let mut out = Exported::new(law, table, o);
    let mut s = String::from("pressure_MPa,sliding_velocity_m_per_min,temperature_K,mu\n");
    let t = &out.table;
    let [nv, np, nt] = t.shape();
    for it in 0..nt {
        let temp = t
            .temperature
            .as_ref()
            .map_or(ContactState::ROOM_TEMPERATURE_K, |a| a.written[it]);
        for ip in 0..np {
            for iv in 0..nv {
                let _ = writeln!(
                    s,
                    "{},{},{},{}",
                    t.pressure.written[ip],
                    t.speed.written[iv],
                    temp,
                    t.at(iv, ip, it)
                );
            }
        }
    }
    out.text = s;
    Ok(out)
}

/// A parsed `FRCWIN` block: window number, points, constant μ.
#[derive(Debug, Clone, PartialEq)]
pub struct FrcWin {
    pub number: usize,
    pub points: Vec<[f64; 2]>,
    pub mu: f64,
}

/// Read the 2D `FRCWIN` blocks with constant friction (FricDefType 0) from keyword text.
pub fn parse_frcwin(text: &str, source: &str) -> Result<Vec<FrcWin>> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim();
        if !l.to_ascii_uppercase().starts_with("FRCWIN") {
            i += 1;
            continue;
        }
        let pos = || SourcePos::file(source).line(i as u64 + 1);
        let f: Vec<&str> = l
            .split(|c: char| c.is_whitespace() || c == ',')
            .filter(|s| !s.is_empty())
            .collect();
        if f.len() < 8 {
            return Err(Error::input(
                pos(),
                "FRCWIN needs Object1 Object2 WinNo Npoints FricType FricDefType Friction ...",
            ));
        }
        let num = |s: &str| {
            s.parse::<f64>()
                .map_err(|_| Error::input(pos(), format!("expected a number, found '{s}'")))
        };
        let n = num(f[4])? as usize;
        if num(f[6])? != 0.0 {
            return Err(Error::input(
                pos(),
                "only constant window friction (FricDefType 0) is read",
            ));
        }
        // one line a point: a count the text cannot hold allocates no more than its lines
        let mut points = Vec::with_capacity(n.min(lines.len().saturating_sub(i)));
        for k in 0..n {
            let line = lines
                .get(i + 1 + k)
                .ok_or_else(|| Error::input(pos(), "FRCWIN block ends before its points"))?;
            let p: Vec<&str> = line
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|s| !s.is_empty())
                .collect();
            if p.len() < 3 {
                return Err(Error::input(
                    SourcePos::file(source).line((i + 2 + k) as u64),
                    "a window point needs index, x, y",
                ));
            }
            points.push([num(p[1])?, num(p[2])?]);
        }
        out.push(FrcWin {
            number: num(f[3])? as usize,
            points,
            mu: num(f[7])?,
        });
        i += 1 + n;
    }
    Ok(out)
}

/// A parsed DEFORM `FRCFAC` block (Coulomb or shear friction, constant or a p–T–stretch table).
#[derive(Debug, Clone, PartialEq)]
pub struct FrcFac {
    pub objects: (u32, u32),
    pub fric_type: u32,
    /// Constant friction (FricDefType 0).
    pub constant: Option<f64>,
    /// FricDefType 5: pressures, temperatures, stretches and values (pressure fastest).
    pub pressures: Vec<f64>,
    pub temperatures: Vec<f64>,
    pub stretches: Vec<f64>,
    pub values: Vec<f64>,
}

/// Read the `FRCFAC` blocks (FricDefType 0 and 5) of DEFORM keyword text.
pub fn parse_frcfac(text: &str, source: &str) -> Result<Vec<FrcFac>> {
    let lines: Vec<&str> = text.lines().collect();
    let pos = |k: usize| SourcePos::file(source).line(k as u64 + 1);
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let f = keyword_fields(lines[i]);
        if f.first().is_none_or(|k| !k.eq_ignore_ascii_case("FRCFAC")) {
            i += 1;
            continue;
        }
        let num = |s: &str| keyword_number(s, pos(i));
        if f.len() < 5 {
            return Err(Error::input(
                pos(i),
                "FRCFAC needs Object1 Object2 FricType FricDefType ...",
            ));
        }
        let mut block = FrcFac {
            objects: (num(&f[1])? as u32, num(&f[2])? as u32),
            fric_type: num(&f[3])? as u32,
            constant: None,
            pressures: Vec::new(),
            temperatures: Vec::new(),
            stretches: Vec::new(),
            values: Vec::new(),
        };
        match num(&f[4])? as i64 {
            0 => {
                let v = f.get(5).ok_or_else(|| {
                    Error::input(pos(i), "constant FRCFAC needs the friction value")
                })?;
                block.constant = Some(num(v)?);
                i += 1;
            }
            5 => i = read_frcfac_table(&lines, i, &f, &mut block, &pos)?,
            other => {
                return Err(Error::input(
                    pos(i),
                    format!("FricDefType {other} is not read (0 and 5 are)"),
                ))
            }
        }
        out.push(block);
    }
    Ok(out)
}

/// The fields of a keyword line, split at white space and commas.
fn keyword_fields(l: &str) -> Vec<String> {
    l.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|s| !s.is_empty())
        .map(String::from)
        .collect()
}

/// A number of a keyword line at `pos`.
fn keyword_number(s: &str, pos: SourcePos) -> Result<f64> {
    s.parse::<f64>()
        .map_err(|_| Error::input(pos, format!("expected a number, found '{s}'")))
}

/// The p–T–stretch table of a FricDefType 5 `FRCFAC` whose keyword line `f` is line `i`:
/// NPres NTemp NStre on it, then pressures, temperatures, stretches and values (pressure
/// fastest) on the lines after it (comment lines skipped). Returns the line after the table.
fn read_frcfac_table(
    lines: &[&str],
    i: usize,
    f: &[String],
    block: &mut FrcFac,
    pos: &dyn Fn(usize) -> SourcePos,
) -> Result<usize> {
    if f.len() < 8 {
        return Err(Error::input(
            pos(i),
            "FricDefType 5 needs NPres NTemp NStre",
        ));
    }
    let count = |s: &str| keyword_number(s, pos(i)).map(|x| x as usize);
    let (np, nt, ns) = (count(&f[5])?, count(&f[6])?, count(&f[7])?);
    // the remaining numbers, in order: pressures, temperatures, stretches, values; memory is
    // reserved for what the text after the keyword can hold, not for what it claims
    let need = np
        .checked_mul(nt)
        .and_then(|x| x.checked_mul(ns))
        .and_then(|x| x.checked_add(np)?.checked_add(nt)?.checked_add(ns))
        .ok_or_else(|| {
            Error::input(
                pos(i),
                format!("FRCFAC table of {np} x {nt} x {ns} values: more than can be counted"),
            )
        })?;
    let rest: usize = lines[i + 1..].iter().map(|l| l.len() + 1).sum();
    let mut vals = Vec::with_capacity(need.min(rest / 2 + 1));
    let mut k = i + 1;
    while vals.len() < need {
        let l = lines.get(k).ok_or_else(|| {
            Error::input(
                pos(i),
                format!("FRCFAC table ends early: {} of {need} numbers", vals.len()),
            )
        })?;
        if !l.trim_start().starts_with('*') {
            for t in keyword_fields(l) {
                vals.push(keyword_number(&t, pos(k))?);
            }
        }
        k += 1;
    }
    if vals.len() != need {
        return Err(Error::input(
            pos(k - 1),
            format!("FRCFAC table has {} numbers, expected {need}", vals.len()),
        ));
    }
    block.pressures = vals[..np].to_vec();
    block.temperatures = vals[np..np + nt].to_vec();
    block.stretches = vals[np + nt..np + nt + ns].to_vec();
    block.values = vals[np + nt + ns..].to_vec();
    Ok(k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classical::Zorev;

    /// A law whose name is whatever a hostile model file, `--target` or hand edit made it.
    struct Named(String);

    impl FrictionLaw for Named {
        fn name(&self) -> String {
            self.0.clone()
        }
        fn mu(&self, _: &ContactState) -> f64 {
            0.3
        }
    }

    /// Names that would start a keyword line in each deck if written as they are.
    const HOSTILE: &[&str] = &[
        "cof\n*INCLUDE, INPUT=/etc/passwd",
        "cof\r\n*KEYWORD\n*INCLUDE\n/etc/passwd",
        "cof\nFRCFAC 1 2 2 0 1 1 1",
        "cof\u{2028}*INCLUDE\u{85}*END",
        "$(touch PWNED) <script>alert(1)</script> \"'",
    ];

    /// Issue 62: LS-DYNA ids never wrap and never start at 0.
    #[test]
    fn lsdyna_ids_are_bounded() {
        let grid = Grid {
            pressure_pa: vec![100e6, 200e6],
            velocity_m_s: vec![1.0, 2.0],
            temperature_k: None,
        };
        let law = Zorev {
            mu: 0.3,
            k_pa: 500e6,
        };
        let u = Units::of(crate::grid::UnitSystem::MpaMmS, TemperatureUnit::C);
        assert!(lsdyna(&law, &grid, u, 1000).is_ok());
        for bad in [0, u32::MAX, i32::MAX as u32 - 1] {
            let e = lsdyna(&law, &grid, u, bad).unwrap_err().to_string();
            assert!(
                e.contains("export.lsdyna_table_id") && e.contains("1..=2147483647"),
                "{e}"
            );
        }
        let last = lsdyna(&law, &grid, u, i32::MAX as u32 - 2).unwrap();
        assert!(last.contains("2147483647"), "{last}");
    }

    /// Every deck line is the writer's: the comment with the name is one line, and the
    /// keyword lines are exactly those of a plain name.
    #[test]
    fn hostile_law_names_stay_inside_their_comment_line() {
        let grid = Grid {
            pressure_pa: vec![100e6, 200e6],
            velocity_m_s: vec![1.0, 2.0],
            temperature_k: None,
        };
        let u = Units::of(crate::grid::UnitSystem::MpaMmS, TemperatureUnit::C);
        let decks = |name: &str| -> [(String, &str); 3] {
            let law = Named(name.to_string());
            [
                (abaqus(&law, &grid, u, None).unwrap(), "** law: "),
                (lsdyna(&law, &grid, u, 7).unwrap(), "$ law: "),
                (deform(&law, &grid, 1.0, &[], (2, 1)).unwrap(), "* law: "),
            ]
        };
        let plain = decks("plain");
        for name in HOSTILE {
            for ((text, prefix), (reference, _)) in decks(name).iter().zip(&plain) {
                assert_eq!(text.lines().count(), reference.lines().count(), "{text}");
                let law_lines: Vec<&str> = text.lines().filter(|l| l.starts_with(prefix)).collect();
                assert_eq!(law_lines.len(), 1, "{text}");
                assert_eq!(law_lines[0], format!("{prefix}{}", deck_comment(name)));
                for (l, r) in text.lines().zip(reference.lines()) {
                    if !r.starts_with(prefix) {
                        assert_eq!(l, r, "only the law's comment line differs");
                    }
                }
            }
        }
    }

    /// Counts a hostile deck states (a table of 10¹² values, a window of 10¹⁸ points) are
    /// refused or read as far as the text goes, with nothing allocated for them.
    #[test]
    fn hostile_counts_in_deform_blocks_allocate_nothing_for_them() {
        let e = parse_frcfac("FRCFAC 2 1 1 5 100000 100000 100 \n1 2 3\n", "d.key").unwrap_err();
        assert!(e.to_string().contains("ends early"), "{e}");
        let e = parse_frcfac("FRCFAC 2 1 1 5 1e19 1e19 1e19\n", "d.key").unwrap_err();
        assert!(e.to_string().contains("d.key"), "{e}");
        let e = parse_frcwin("FRCWIN 2 1 1 1000000000000000000 1 0 0.3\n1 0 0\n", "w.key");
        assert!(e.is_err());
    }

    #[test]
    fn deform_frcfac_round_trip() {
        let law = Zorev {
            mu: 0.4,
            k_pa: 500e6,
        };
        let grid = Grid {
            pressure_pa: vec![500e6, 1000e6, 1500e6],
            velocity_m_s: vec![1.0],
            temperature_k: Some(vec![293.15, 773.15]),
        };
        let text = deform(&law, &grid, 2.5, &[], (2, 1)).unwrap();
        let b = parse_frcfac(&text, "d.key").unwrap();
        assert_eq!(b.len(), 1);
        assert_eq!(b[0].objects, (2, 1));
        assert_eq!(b[0].pressures, vec![500.0, 1000.0, 1500.0]);
        assert_eq!(b[0].values.len(), 6);
        // Zorev: μ = 0.4 up to 1250 MPa, then k/p
        assert_eq!(b[0].values[0], 0.4);
        assert!((b[0].values[2] - 500.0 / 1500.0).abs() < 1e-15);
        let c = parse_frcfac("FRCFAC 2 1 2 0 0.35\n", "c.key").unwrap();
        assert_eq!(c[0].constant, Some(0.35));
        assert!(parse_frcfac("FRCFAC 2 1 2 5 3 1 1\n1 2\n", "bad.key")
            .unwrap_err()
            .to_string()
            .contains("ends early"));
    }
}
