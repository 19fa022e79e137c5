//! One table of a law as its engine's text: the dispatch from a [`TableSpec`] to the writer
//! of its format (engine tables on the grid, or on an adaptive grid; surrogate tables over the
//! grid's box), with the table's size limit and what was written ([`ExportReport`]).
//!
//! ```
//! use greybox_friction::classical::Coulomb;
//! use greybox_friction::export::engine::{ExportFormat, TableSpec};
//! use greybox_friction::export::write::table_text;
//! let spec = TableSpec::new(ExportFormat::Csv).validated()?;
//! let written = table_text(&Coulomb { mu: 0.3 }, &spec)?;
//! assert!(written.text.starts_with("pressure_MPa,sliding_velocity_m_per_min"));
//! assert_eq!(written.report.shape, [30, 21, 1]); // velocities, pressures, temperatures
//! assert_eq!(written.report.max_deviation, Some(0.0));
//! # Ok::<(), greybox_core::Error>(())
//! ```

use super::engine::{invalid, Engine, TableSpec, ValidTableSpec};
use super::{DeformWindow, Deviation, Exported, Grid, TableOptions};
use crate::surrogate::{self, SurrogateOptions};
use crate::table::Axis;
use crate::table_file::{AnyTable, TableKind};
use greybox_core::law::Range;
use greybox_core::{FrictionLaw, Result};
use serde::Serialize;

/// What an export wrote.
#[derive(Debug, Clone, Serialize)]
pub struct ExportReport {
    /// One-line description, with the deviation.
    pub line: String,
    /// Max deviation of the table from the law inside the grid (engine tables: under the
    /// engine's linear interpolation) and the points checked; `None`: not checked.
    pub max_deviation: Option<f64>,
    pub check_points: usize,
    /// Table points per axis: engine tables (speed, pressure, temperature); surrogate tables
    /// (pressure, velocity, temperature).
    pub shape: [usize; 3],
    /// Whether the grid lines sit at the law's split thresholds (engine tables), or the
    /// surrogate table's kind is exact.
    pub exact_steps: bool,
    /// Bytes written.
    pub bytes: usize,
    /// What the user should know (a table too big for an engine to read quickly).
    pub warnings: Vec<String>,
    /// The grid against the law's validity domain (`None`: the law has none, a classical
    /// law); points outside it are the law's extrapolation, and said as a note.
    pub domain: Option<super::domain::GridAgainstDomain>,
}

/// A table as text with its report (`line`, `bytes` and `warnings` left for the caller,
/// which knows the file) and a note on its shape for the report's line.
#[derive(Debug, Clone)]
pub struct TableText {
    pub text: String,
    pub report: ExportReport,
    pub note: String,
}

/// The table `spec` asks for, of `law`, as text, refused above `spec.max_table_size`
/// values with the size it would have.
pub fn table_text(law: &dyn FrictionLaw, spec: &ValidTableSpec) -> Result<TableText> {
    let spec: &TableSpec = spec;
    let written = match &spec.engine {
        Engine::Table { kind } => surrogate_table(law, spec, *kind)?,
        engine => {
            let refined;
            let grid = if spec.adaptive_grid {
                refined = adaptive_grid(law, spec)?;
                &refined
            } else {
                &spec.grid
            };
            check_table_size(grid_points(grid), spec.max_table_size.get())?;
            engine_table(law, grid, engine, spec)?
        }
    };
    check_table_size(
        written.report.shape.iter().product(),
        spec.max_table_size.get(),
    )?;
    let mut written = written;
    written.report.domain = super::domain::check_grid(law, &spec.grid);
    Ok(written)
}

/// Points of an engine table on `grid` before any split-threshold lines.
fn grid_points(grid: &Grid) -> usize {
    grid.pressure_pa.len()
        * grid.velocity_m_s.len()
        * grid.temperature_k.as_ref().map_or(1, Vec::len)
}

/// Refuse a table of more than `max` values, with the size it would have (about 30 bytes
/// of text a value).
fn check_table_size(values: usize, max: usize) -> Result<()> {
    if values > max {
        return Err(invalid(
            "max_table_size",
            format!(
                "the table would have {values} values (about {:.0} MB as text), more than the limit of {max}; coarsen the grid, loosen `tolerance` or raise `max_table_size`",
                values as f64 * 30.0 / 1e6
            ),
        ));
    }
    Ok(())
}

/// An engine table (Abaqus, DEFORM, LS-DYNA, CSV) on `grid`.
fn engine_table(
    law: &dyn FrictionLaw,
    grid: &Grid,
    engine: &Engine,
    spec: &TableSpec,
) -> Result<TableText> {
    let o = TableOptions {
        steps: spec.steps,
        check_points: spec.check_points.get(),
        seed: 42,
    };
    Ok(match engine {
        Engine::Abaqus { taumax_pa, .. } => {
            let units = engine.units().expect("Abaqus has units");
            engine_report(super::abaqus_checked(law, grid, units, *taumax_pa, &o)?)
        }
        Engine::Lsdyna { table_id, .. } => {
            let units = engine.units().expect("LS-DYNA has units");
            engine_report(super::lsdyna_checked(law, grid, units, *table_id, &o)?)
        }
        Engine::Csv => engine_report(super::csv_checked(law, grid, &o)?),
        Engine::Deform {
            reference_velocity_m_s,
            objects,
            windows,
        } => {
            let windows = read_deform_windows(windows.as_deref())?;
            let mut t = engine_report(super::deform_checked(
                law,
                grid,
                *reference_velocity_m_s,
                &windows,
                *objects,
                &o,
            )?);
            t.note = format!("{}, {} windows", t.note, windows.len());
            t
        }
        Engine::Table { .. } => unreachable!("surrogate tables are not engine tables"),
    })
}

/// DEFORM windows from a JSON list (none without a file).
fn read_deform_windows(path: Option<&std::path::Path>) -> Result<Vec<DeformWindow>> {
    let Some(p) = path else {
        return Ok(Vec::new());
    };
    let text = greybox_core::input::read_config(p, "DEFORM windows file")?;
    serde_json::from_str(&text).map_err(|e| {
        invalid(
            "deform_windows",
            format!("{}: expected a JSON list of windows: {e}", p.display()),
        )
    })
}

/// Text, report and note of an engine table.
fn engine_report(e: Exported) -> TableText {
    let shape = e.table.shape();
    let mut note = format!(
        ", {} pressures x {} velocities{}",
        shape[1],
        shape[0],
        if e.table.temperature.is_some() {
            format!(" x {} temperatures", shape[2])
        } else {
            String::new()
        }
    );
    if e.table.exact_steps {
        note += " (grid lines at the law's split thresholds)";
    }
    let report = ExportReport {
        line: String::new(),
        bytes: 0,
        warnings: Vec::new(),
        max_deviation: e.deviation.map(|d: Deviation| d.max),
        check_points: e.deviation.map_or(0, |d| d.points),
        shape,
        exact_steps: e.table.exact_steps,
        domain: None,
    };
    TableText {
        text: e.text,
        report,
        note,
    }
}

/// The box of one grid axis (its first and last value).
fn range(v: &[f64]) -> Range {
    Range {
        min: v[0],
        max: v[v.len() - 1],
    }
}

/// Surrogate options over the box of the spec's grid, with its tolerance and size limit.
fn surrogate_options(spec: &TableSpec, kind: Option<TableKind>) -> SurrogateOptions {
    let g = &spec.grid;
    let mut so = SurrogateOptions::over(
        range(&g.pressure_pa),
        range(&g.velocity_m_s),
        g.temperature_k.as_deref().map(range),
    );
    so.kind = kind;
    so.tolerance = spec.tolerance;
    so.max_size = spec.max_table_size.get();
    so.seed = 42;
    so
}

/// The nodes of an adaptive table of `law` over the box of the grid (min and max per axis),
/// refined to `spec.tolerance`, as the grid of an engine table.
fn adaptive_grid(law: &dyn FrictionLaw, spec: &TableSpec) -> Result<Grid> {
    let g = &spec.grid;
    let so = surrogate_options(spec, Some(TableKind::Adaptive));
    if g.pressure_pa.len() < 2 || g.velocity_m_s.len() < 2 {
        return Err(invalid(
            "adaptive_grid",
            "needs a range of pressures and of velocities (at least two of each)".into(),
        ));
    }
    let AnyTable::Adaptive(t) = surrogate::build(law, &so)? else {
        unreachable!("an adaptive table was asked for")
    };
    Ok(Grid {
        pressure_pa: t.pressure_pa,
        velocity_m_s: t.velocity_m_s,
        temperature_k: g.temperature_k.as_ref().map(|_| t.temperature_k),
    })
}

/// A surrogate table over the box of the grid.
fn surrogate_table(
    law: &dyn FrictionLaw,
    spec: &TableSpec,
    kind: Option<TableKind>,
) -> Result<TableText> {
    let grid = &spec.grid;
    let mut so = surrogate_options(spec, kind);
    so.check_points = spec.check_points.get();
    if so.kind.unwrap_or_else(|| surrogate::auto_kind(law)) == TableKind::Uniform {
        so.uniform_points = [
            uniform_axis(&grid.pressure_pa, "pressure_Pa")?,
            uniform_axis(&grid.velocity_m_s, "velocity_m_per_s")?,
            match grid.temperature_k.as_deref() {
                Some(t) => uniform_axis(t, "temperature_K")?,
                None => 1,
            },
        ];
    }
    let t = surrogate::build(law, &so)?;
    let (max_deviation, check_points) = match &t {
        AnyTable::Exact(e) => (e.max_deviation, e.check_points),
        AnyTable::Adaptive(e) => (e.max_deviation, e.check_points),
        AnyTable::Uniform(e) => (e.max_deviation, Some(spec.check_points.get())),
    };
    let shape = t.shape();
    let note = format!(
        ", {} table of {} values ({} x {}{})",
        t.kind().name(),
        t.len(),
        shape[0],
        shape[1],
        if shape[2] > 1 {
            format!(" x {}", shape[2])
        } else {
            String::new()
        }
    );
    let report = ExportReport {
        line: String::new(),
        bytes: 0,
        warnings: Vec::new(),
        max_deviation: max_deviation.filter(|_| spec.check_points.get() > 0),
        check_points: check_points.unwrap_or(0),
        shape,
        exact_steps: t.kind() == TableKind::Exact,
        domain: None,
    };
    Ok(TableText {
        text: t.to_json()?,
        report,
        note,
    })
}

/// The number of values of an equidistant axis `v` (a uniform table's axis); `what` names
/// the field of values that are not equidistant.
fn uniform_axis(v: &[f64], what: &str) -> Result<usize> {
    let n = v.len();
    let ax = Axis::new(v[0], v[n - 1], n)?;
    if v.iter()
        .enumerate()
        .any(|(i, x)| (x - ax.value(i)).abs() > 1e-9 * x.abs().max(1.0))
    {
        return Err(invalid(
            what,
            "a uniform table needs equidistant values (MIN:MAX:N)".into(),
        ));
    }
    Ok(n)
}
