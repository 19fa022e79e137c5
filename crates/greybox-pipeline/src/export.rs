//! A friction law as tables for FE engines (Abaqus, DEFORM, LS-DYNA, CSV), or as a
//! surrogate table; every table with its measured max deviation from the law.

use crate::output::provenance;
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::law::Range;
use greybox_core::outputs::check_file_output;
use greybox_friction::export::{
    self, DeformWindow, Deviation, Exported, Grid, PressureUnit, SpeedUnit, StepLines,
    TableOptions, TempUnit, Units,
};
use greybox_friction::spec::{law_inputs, load_law};
use greybox_friction::surrogate::{self, SurrogateOptions};
use greybox_friction::table::Axis;
use greybox_friction::table_file::{AnyTable, TableKind};
use serde::Serialize;
use std::path::PathBuf;

/// The exported form.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// Abaqus *FRICTION data lines.
    Abaqus,
    /// DEFORM FRCFAC / FRCWIN keyword blocks.
    Deform,
    /// LS-DYNA *DEFINE_TABLE + *DEFINE_CURVE.
    Lsdyna,
    /// The grid as CSV.
    Csv,
    /// A greybox surrogate table (JSON): exact for tree ensembles, adaptive otherwise (see
    /// [`ExportOptions::table_kind`]).
    Table,
}

impl ExportFormat {
    pub const ALL: [ExportFormat; 5] = [
        ExportFormat::Abaqus,
        ExportFormat::Deform,
        ExportFormat::Lsdyna,
        ExportFormat::Csv,
        ExportFormat::Table,
    ];
    /// The name on the command line and in the Python API.
    pub fn name(self) -> &'static str {
        match self {
            ExportFormat::Abaqus => "abaqus",
            ExportFormat::Deform => "deform",
            ExportFormat::Lsdyna => "lsdyna",
            ExportFormat::Csv => "csv",
            ExportFormat::Table => "table",
        }
    }
    pub fn parse(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// Options of [`export()`].
#[derive(Debug, Clone)]
pub struct ExportOptions {
    /// Law file, model file or table.
    pub law: PathBuf,
    pub format: ExportFormat,
    /// Output file.
    pub out: PathBuf,
    /// Pressures, sliding velocities (and temperatures) of the table, SI.
    pub grid: Grid,
    /// Units of the Abaqus/LS-DYNA tables.
    pub units: Units,
    /// Abaqus TAUMAX (limiting shear stress), Pa.
    pub taumax_pa: Option<f64>,
    /// DEFORM: JSON list of windows {points_mm, pressure_mpa, velocity_m_per_min, temperature_k}.
    pub deform_windows: Option<PathBuf>,
    /// DEFORM: sliding velocity at which the FRCFAC p-T table is evaluated, m/s.
    pub deform_reference_velocity_m_s: f64,
    /// DEFORM: object numbers (tool, workpiece).
    pub deform_objects: (u32, u32),
    /// LS-DYNA table id (curves take the following ids).
    pub lsdyna_table_id: u32,
    /// Random points of the deviation check (every format; 0: no check).
    pub check_points: usize,
    /// Engine tables: grid lines at a tree ensemble's split thresholds (two points one float
    /// apart, so that the table is exact for linear interpolation); `Auto`: for
    /// piecewise-constant laws.
    pub steps: StepLines,
    /// Surrogate table kind; `None`: exact for tree ensembles, adaptive otherwise. An
    /// adaptive table covers the box of `grid` (min and max per axis); a uniform one needs
    /// equidistant values.
    pub table_kind: Option<TableKind>,
    /// Adaptive table: max deviation on its check set.
    pub tolerance: f64,
    /// Surrogate table: most cells (exact) or nodes (adaptive).
    pub max_table_size: usize,
    /// Engine tables: take the grid lines of an adaptive table refined to `tolerance` over
    /// the box of `grid` (its values only set the box), so that a smooth law's table is
    /// within the tolerance under the engine's linear interpolation too.
    pub adaptive_grid: bool,
}

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
/// assert!(parse_values("1:0:3", "--pressure-MPa").unwrap_err().to_string().contains("--pressure-MPa"));
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
        let n: usize = parts[2]
            .trim()
            .parse()
            .with_context(|| format!("{what}: count '{}' is not an integer", parts[2]))?;
        if n < 2 || !(b > a) {
            bail!("{what}: MIN:MAX:N needs MIN < MAX and N ≥ 2");
        }
        return Ok(equidistant(a, b, n));
    }
    text.split(',').map(nums).collect()
}

/// Table units by their names: pressure "Pa" or "MPa"; speed "m/s", "mm/s" or "m/min";
/// temperature "K" or "C".
pub fn units_by_name(pressure: &str, speed: &str, temperature: &str) -> Result<Units> {
    Ok(Units {
        pressure: match pressure {
            "Pa" => PressureUnit::Pa,
            "MPa" => PressureUnit::MPa,
            o => bail!("unknown pressure unit '{o}'; expected Pa or MPa"),
        },
        speed: match speed {
            "m/s" => SpeedUnit::MPerS,
            "mm/s" => SpeedUnit::MmPerS,
            "m/min" => SpeedUnit::MPerMin,
            o => bail!("unknown speed unit '{o}'; expected m/s, mm/s or m/min"),
        },
        temperature: match temperature {
            "K" => TempUnit::K,
            "C" => TempUnit::C,
            o => bail!("unknown temperature unit '{o}'; expected K or C"),
        },
    })
}

/// Export; returns what was written and its deviation from the law.
pub fn export(a: &ExportOptions) -> Result<ExportReport> {
    let law_files = law_inputs(&a.law)?;
    let mut inputs = vec![("--law", a.law.as_path())];
    inputs.extend(
        law_files[1..]
            .iter()
            .map(|f| ("a file the law --law reads", f.as_path())),
    );
    if let Some(w) = &a.deform_windows {
        inputs.push(("--deform-windows", w.as_path()));
    }
    check_file_output(&a.out, "--out", &inputs)?;
    let law = load_law(&a.law)?;
    a.grid.validate()?;
    let refined;
    let grid = if a.adaptive_grid && a.format != ExportFormat::Table {
        refined = adaptive_grid(law.as_ref(), a)?;
        &refined
    } else {
        &a.grid
    };
    let o = TableOptions {
        steps: a.steps,
        check_points: a.check_points,
        seed: 42,
    };
    let (text, report, note) = match a.format {
        ExportFormat::Abaqus => engine(export::abaqus_checked(
            law.as_ref(),
            grid,
            a.units,
            a.taumax_pa,
            &o,
        )?),
        ExportFormat::Lsdyna => engine(export::lsdyna_checked(
            law.as_ref(),
            grid,
            a.units,
            a.lsdyna_table_id,
            &o,
        )?),
        ExportFormat::Csv => engine(export::csv_checked(law.as_ref(), grid, &o)?),
        ExportFormat::Deform => {
            let windows: Vec<DeformWindow> = match &a.deform_windows {
                Some(p) => serde_json::from_str(
                    &std::fs::read_to_string(p)
                        .with_context(|| format!("cannot read {}", p.display()))?,
                )
                .with_context(|| format!("{}: expected a JSON list of windows", p.display()))?,
                None => Vec::new(),
            };
            let (text, report, _) = engine(export::deform_checked(
                law.as_ref(),
                grid,
                a.deform_reference_velocity_m_s,
                &windows,
                a.deform_objects,
                &o,
            )?);
            (text, report, format!(", {} windows", windows.len()))
        }
        ExportFormat::Table => surrogate_table(law.as_ref(), a)?,
    };
    write_string_atomic(&a.out, &text)?;
    provenance(&inputs)?.write_beside(&a.out)?;
    let deviation = match report.max_deviation {
        Some(d) => format!(
            "; max deviation from the law {d:.3e} on {} points inside the grid",
            report.check_points
        ),
        None => String::new(),
    };
    Ok(ExportReport {
        line: format!(
            "exported {} as {:?} to {}{note}{deviation}",
            law.name(),
            a.format,
            a.out.display()
        ),
        ..report
    })
}

/// Text, report and note of an engine table.
fn engine(e: Exported) -> (String, ExportReport, String) {
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
    so.max_size = a.max_table_size;
    so.seed = 42;
    if g.pressure_pa.len() < 2 || g.velocity_m_s.len() < 2 {
        bail!("--adaptive-grid needs a range of pressures and of velocities (MIN:MAX:N)");
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
    so.kind = a.table_kind;
    so.tolerance = a.tolerance;
    so.check_points = a.check_points;
    so.max_size = a.max_table_size;
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
            axis(&grid.pressure_pa, "--pressure-MPa")?,
            axis(&grid.velocity_m_s, "--velocity-m-per-min")?,
            match grid.temperature_k.as_deref() {
                Some(t) => axis(t, "--temperature-K")?,
                None => 1,
            },
        ];
    }
    let t = surrogate::build(law, &so)?;
    let (max_deviation, check_points) = match &t {
        AnyTable::Exact(e) => (e.max_deviation, e.check_points),
        AnyTable::Adaptive(e) => (e.max_deviation, e.check_points),
        AnyTable::Uniform(e) => (e.max_deviation, Some(a.check_points)),
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
        max_deviation: max_deviation.filter(|_| a.check_points > 0),
        check_points: check_points.unwrap_or(0),
        shape,
        exact_steps: t.kind() == TableKind::Exact,
    };
    Ok((t.to_json()?, report, note))
}
