//! A friction law as tables for FE engines (Abaqus, DEFORM, LS-DYNA, CSV), or as a
//! surrogate table; every table with its measured max deviation from the law.

mod options;

pub use options::*;

use crate::output::provenance;
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::choice::Choice;
use greybox_core::law::Range;
use greybox_core::outputs::check_file_output;
use greybox_friction::export::{self, DeformWindow, Deviation, Exported, Grid, TableOptions};
use greybox_friction::spec::LawFile;
use greybox_friction::surrogate::{self, SurrogateOptions};
use greybox_friction::table::Axis;
use greybox_friction::table_file::{AnyTable, TableKind};
use serde::Serialize;

/// What [`export()`] did.
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
}

/// `n` equidistant values from `min` to `max` (both included): `min + (max − min)·i/(n − 1)`;
/// `[min]` for n = 1, nothing for n = 0.
///
/// ```
/// use greybox_pipeline::export::equidistant;
/// assert_eq!(equidistant(20.0, 250.0, 3), [20.0, 135.0, 250.0]);
/// assert_eq!(equidistant(20.0, 250.0, 1), [20.0]);
/// assert!(equidistant(20.0, 250.0, 0).is_empty());
/// ```
pub fn equidistant(min: f64, max: f64, n: usize) -> Vec<f64> {
    if n < 2 {
        return vec![min; n];
    }
    (0..n)
        .map(|i| min + (max - min) * i as f64 / (n - 1) as f64)
        .collect()
}

/// Values from `MIN:MAX:N` (equidistant, both ends included) or a comma list; `what`
/// names the field in errors.
///
/// ```
/// use greybox_pipeline::export::parse_values;
/// assert_eq!(parse_values("0:1:3", "x").unwrap(), [0.0, 0.5, 1.0]);
/// assert_eq!(parse_values("2, 5", "x").unwrap(), [2.0, 5.0]);
/// assert!(parse_values("1:0:3", "pressure_MPa").unwrap_err().to_string().contains("pressure_MPa"));
/// ```
pub fn parse_values(text: &str, what: &str) -> Result<Vec<f64>> {
    let nums = |s: &str| -> Result<f64> {
        let v: f64 = s
            .trim()
            .parse()
            .with_context(|| format!("{what}: '{s}' is not a number"))?;
        if !v.is_finite() {
            bail!("{what}: '{s}' is not finite");
        }
        Ok(v)
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() == 3 {
        let (a, b) = (nums(parts[0])?, nums(parts[1])?);
        let n: AxisPoints = parts[2]
            .parse()
            .with_context(|| format!("{what}: the N of MIN:MAX:N"))?;
        if !(b > a) {
            bail!("{what}: MIN:MAX:N needs MIN < MAX");
        }
        return Ok(equidistant(a, b, n.get()));
    }
    text.split(',').map(nums).collect()
}

/// Export; returns what was written and its deviation from the law.
pub fn export(a: &ExportOptions) -> Result<ExportReport> {
    a.validate()?;
    // Read once: the outputs are checked against the law's inputs before the law (possibly
    // a model file of hundreds of MB) is built from the text read here.
    let law_file = LawFile::read(&a.law)?;
    let law_files = law_file.inputs();
    let mut inputs = vec![("law", a.law.as_path())];
    inputs.extend(
        law_files[1..]
            .iter()
            .map(|f| ("a file the law reads", f.as_path())),
    );
    if let Some(w) = a.engine.deform_windows() {
        inputs.push(("deform_windows", w.as_path()));
    }
    check_file_output(&a.out, "out", &inputs)?;
    let law = law_file.build()?;
    let refined;
    let grid = if a.adaptive_grid && a.format() != ExportFormat::Table {
        refined = adaptive_grid(law.as_ref(), a)?;
        &refined
    } else {
        &a.grid
    };
    let (text, report, note) = match &a.engine {
        Engine::Table { kind } => surrogate_table(law.as_ref(), a, *kind)?,
        engine => {
            check_table_size(grid_points(grid), a.max_table_size.get())?;
            engine_table(law.as_ref(), grid, engine, a)?
        }
    };
    check_table_size(report.shape.iter().product(), a.max_table_size.get())?;
    write_string_atomic(&a.out, &text)?;
    provenance(&inputs)?.write_beside(&a.out)?;
    let deviation = match report.max_deviation {
        Some(d) => format!(
            "; max deviation from the law {d:.3e} on {} points inside the grid",
            report.check_points
        ),
        None => String::new(),
    };
    let mut warnings = Vec::new();
    if text.len() > LARGE_TABLE_BYTES {
        warnings.push(format!(
            "{} is {:.1} MB ({} table values): engines read a table this size slowly; coarsen the grid{}",
            a.out.display(),
            text.len() as f64 / 1e6,
            report.shape.iter().product::<usize>(),
            if a.adaptive_grid || a.format() == ExportFormat::Table {
                " or loosen export.tolerance"
            } else {
                ""
            }
        ));
    }
    Ok(ExportReport {
        line: format!(
            "exported {} as {} to {}{note}{deviation}",
            law.name(),
            a.format().name(),
            a.out.display()
        ),
        bytes: text.len(),
        warnings,
        ..report
    })
}

/// A written table above this size (bytes) gets a warning.
pub const LARGE_TABLE_BYTES: usize = 16_000_000;

/// Points of an engine table on `grid` before any split-threshold lines.
fn grid_points(grid: &Grid) -> usize {
    grid.pressure_pa.len()
        * grid.velocity_m_s.len()
        * grid.temperature_k.as_ref().map_or(1, Vec::len)
}

/// Refuse a table of more than `max` values, with the size it would have.
fn check_table_size(values: usize, max: usize) -> Result<()> {
    if values > max {
        bail!(
            "export.max_table_size: the table would have {values} values (about {:.0} MB as text), more than the limit of {max}; coarsen the grid, loosen export.tolerance or raise export.max_table_size",
            values as f64 * 30.0 / 1e6
        );
    }
    Ok(())
}

/// An engine table (Abaqus, DEFORM, LS-DYNA, CSV) on `grid`: text, report and note.
fn engine_table(
    law: &dyn greybox_core::FrictionLaw,
    grid: &Grid,
    engine: &Engine,
    a: &ExportOptions,
) -> Result<(String, ExportReport, String)> {
    let o = TableOptions {
        steps: a.steps,
        check_points: a.check_points.get(),
        seed: 42,
    };
    Ok(match engine {
        Engine::Abaqus { taumax_pa, .. } => {
            let units = engine.units().expect("Abaqus has units");
            engine_report(export::abaqus_checked(law, grid, units, *taumax_pa, &o)?)
        }
        Engine::Lsdyna { table_id, .. } => {
            let units = engine.units().expect("LS-DYNA has units");
            engine_report(export::lsdyna_checked(law, grid, units, *table_id, &o)?)
        }
        Engine::Csv => engine_report(export::csv_checked(law, grid, &o)?),
        Engine::Deform {
            reference_velocity_m_s,
            objects,
            windows,
        } => {
            let windows = read_deform_windows(windows.as_deref())?;
            let (text, report, note) = engine_report(export::deform_checked(
                law,
                grid,
                *reference_velocity_m_s,
                &windows,
                *objects,
                &o,
            )?);
            (text, report, format!("{note}, {} windows", windows.len()))
        }
        Engine::Table { .. } => unreachable!("surrogate tables are not engine tables"),
    })
}

/// DEFORM windows from a JSON list (none without a file).
fn read_deform_windows(path: Option<&std::path::Path>) -> Result<Vec<DeformWindow>> {
    let Some(p) = path else {
        return Ok(Vec::new());
    };
    let text = greybox_core::budget::read_config(p, "DEFORM windows file")?;
    serde_json::from_str(&text)
        .with_context(|| format!("{}: expected a JSON list of windows", p.display()))
}

/// Text, report and note of an engine table.
fn engine_report(e: Exported) -> (String, ExportReport, String) {
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
    };
    (e.text, report, note)
}

/// The nodes of an adaptive table of `law` over the box of the grid (min and max per axis),
/// refined to `a.tolerance`, as the grid of an engine table.
fn adaptive_grid(law: &dyn greybox_core::FrictionLaw, a: &ExportOptions) -> Result<Grid> {
    let g = &a.grid;
    let range = |v: &[f64]| Range {
        min: v[0],
        max: v[v.len() - 1],
    };
    let mut so = SurrogateOptions::over(
        range(&g.pressure_pa),
        range(&g.velocity_m_s),
        g.temperature_k.as_deref().map(range),
    );
    so.kind = Some(TableKind::Adaptive);
    so.tolerance = a.tolerance;
    so.max_size = a.max_table_size.get();
    so.seed = 42;
    if g.pressure_pa.len() < 2 || g.velocity_m_s.len() < 2 {
        bail!("export.adaptive_grid: needs a range of pressures and of velocities (at least two of each)");
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

/// A surrogate table over the box of the grid: text, report and note.
fn surrogate_table(
    law: &dyn greybox_core::FrictionLaw,
    a: &ExportOptions,
    kind: Option<TableKind>,
) -> Result<(String, ExportReport, String)> {
    let grid = &a.grid;
    let range = |v: &[f64]| Range {
        min: v[0],
        max: v[v.len() - 1],
    };
    let mut so = SurrogateOptions::over(
        range(&grid.pressure_pa),
        range(&grid.velocity_m_s),
        grid.temperature_k.as_deref().map(range),
    );
    so.kind = kind;
    so.tolerance = a.tolerance;
    so.check_points = a.check_points.get();
    so.max_size = a.max_table_size.get();
    so.seed = 42;
    if so.kind.unwrap_or_else(|| surrogate::auto_kind(law)) == TableKind::Uniform {
        let axis = |v: &[f64], what: &str| -> Result<usize> {
            let n = v.len();
            let ax = Axis::new(v[0], v[n - 1], n)?;
            if v.iter()
                .enumerate()
                .any(|(i, x)| (x - ax.value(i)).abs() > 1e-9 * x.abs().max(1.0))
            {
                bail!("{what}: a uniform table needs equidistant values (MIN:MAX:N)");
            }
            Ok(n)
        };
        so.uniform_points = [
            axis(&grid.pressure_pa, "export.pressure_Pa")?,
            axis(&grid.velocity_m_s, "export.velocity_m_per_s")?,
            match grid.temperature_k.as_deref() {
                Some(t) => axis(t, "export.temperature_K")?,
                None => 1,
            },
        ];
    }
    let t = surrogate::build(law, &so)?;
    let (max_deviation, check_points) = match &t {
        AnyTable::Exact(e) => (e.max_deviation, e.check_points),
        AnyTable::Adaptive(e) => (e.max_deviation, e.check_points),
        AnyTable::Uniform(e) => (e.max_deviation, Some(a.check_points.get())),
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
        max_deviation: max_deviation.filter(|_| a.check_points.get() > 0),
        check_points: check_points.unwrap_or(0),
        shape,
        exact_steps: t.kind() == TableKind::Exact,
    };
    Ok((t.to_json()?, report, note))
}
