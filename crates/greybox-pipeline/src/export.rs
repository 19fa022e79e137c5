//! A friction law as tables for FE engines (Abaqus, DEFORM, LS-DYNA, CSV), or as a
//! surrogate table with its measured deviation from the law.

use crate::output::provenance;
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::outputs::check_file_output;
use greybox_friction::export::{
    self, DeformWindow, Grid, PressureUnit, SpeedUnit, TempUnit, Units,
};
use greybox_friction::spec::load_law;
use greybox_friction::table::{Axis, TabulatedLaw};
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
    /// A greybox surrogate table (JSON) with its maximum deviation from the law.
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
    /// Surrogate table: random points of the deviation check.
    pub check_points: usize,
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

/// Export; returns a one-line description.
pub fn export(a: &ExportOptions) -> Result<String> {
    let mut inputs = vec![("--law", a.law.as_path())];
    if let Some(w) = &a.deform_windows {
        inputs.push(("--deform-windows", w.as_path()));
    }
    check_file_output(&a.out, "--out", &inputs)?;
    let law = load_law(&a.law)?;
    let grid = &a.grid;
    grid.validate()?;
    let (text, note) = match a.format {
        ExportFormat::Abaqus => (
            export::abaqus(law.as_ref(), grid, a.units, a.taumax_pa)?,
            String::new(),
        ),
        ExportFormat::Lsdyna => (
            export::lsdyna(law.as_ref(), grid, a.units, a.lsdyna_table_id)?,
            String::new(),
        ),
        ExportFormat::Csv => (export::csv(law.as_ref(), grid)?, String::new()),
        ExportFormat::Deform => {
            let windows: Vec<DeformWindow> = match &a.deform_windows {
                Some(p) => serde_json::from_str(
                    &std::fs::read_to_string(p)
                        .with_context(|| format!("cannot read {}", p.display()))?,
                )
                .with_context(|| format!("{}: expected a JSON list of windows", p.display()))?,
                None => Vec::new(),
            };
            (
                export::deform(
                    law.as_ref(),
                    grid,
                    a.deform_reference_velocity_m_s,
                    &windows,
                    a.deform_objects,
                )?,
                format!(", {} windows", windows.len()),
            )
        }
        ExportFormat::Table => {
            let axis = |v: &[f64], what: &str| -> Result<Axis> {
                let n = v.len();
                let ax = Axis::new(v[0], v[n - 1], n)?;
                if v.iter()
                    .enumerate()
                    .any(|(i, x)| (x - ax.value(i)).abs() > 1e-9 * x.abs().max(1.0))
                {
                    bail!("{what}: a surrogate table needs equidistant values (MIN:MAX:N)");
                }
                Ok(ax)
            };
            let t_axis = grid
                .temperature_k
                .as_deref()
                .map(|t| axis(t, "--temperature-K"))
                .transpose()?;
            let mut t = TabulatedLaw::bake(
                law.as_ref(),
                axis(&grid.pressure_pa, "--pressure-MPa")?,
                axis(&grid.velocity_m_s, "--velocity-m-per-min")?,
                t_axis,
            );
            let dev = t.check(law.as_ref(), a.check_points, 42);
            (
                serde_json::to_string(&t)?,
                format!(
                    ", max deviation from the law {dev:.3e} on {} random points",
                    a.check_points
                ),
            )
        }
    };
    write_string_atomic(&a.out, &text)?;
    provenance(&inputs)?.write_beside(&a.out)?;
    Ok(format!(
        "exported {} as {:?} to {}{note}",
        law.name(),
        a.format,
        a.out.display()
    ))
}
