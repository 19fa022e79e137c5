//! `greybox export`: a friction law as tables for FE engines, or as a surrogate table.

use anyhow::{bail, Result};
use greybox_friction::export::{Grid, StepLines};
use greybox_pipeline::export::{export, parse_values, units_by_name, ExportFormat, ExportOptions};
use std::path::PathBuf;

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Abaqus *FRICTION data lines.
    Abaqus,
    /// DEFORM FRCFAC / FRCWIN keyword blocks.
    Deform,
    /// LS-DYNA *DEFINE_TABLE + *DEFINE_CURVE.
    Lsdyna,
    /// The grid as CSV.
    Csv,
    /// A greybox surrogate table (JSON): exact for tree ensembles, adaptive otherwise
    /// (--table-kind).
    Table,
}

/// Grid lines at a tree ensemble's split thresholds (engine tables).
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Steps {
    /// On for tree-ensemble laws (piecewise constant): the table is exact.
    Auto,
    /// Two points per split threshold inside the grid for any law that declares steps
    /// (a grey-box law around trees keeps the given grid too).
    On,
    /// The given grid only.
    Off,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Law file, model file from `greybox fit`, or table.
    #[arg(long)]
    pub law: PathBuf,
    #[arg(long, value_enum)]
    pub format: Format,
    /// Output file.
    #[arg(long)]
    pub out: PathBuf,
    /// Pressures, MPa: MIN:MAX:N (equidistant) or a comma list.
    #[arg(long = "pressure-MPa", default_value = "500:2500:21")]
    pub pressure_mpa: String,
    /// Sliding velocities, m/min: MIN:MAX:N or a comma list.
    #[arg(long = "velocity-m-per-min", default_value = "10:300:30")]
    pub velocity: String,
    /// Temperatures, K: MIN:MAX:N or a comma list (omit for μ(p, v) only).
    #[arg(long = "temperature-K")]
    pub temperature: Option<String>,
    /// Abaqus/LS-DYNA pressure unit (Pa or MPa).
    #[arg(long, default_value = "MPa")]
    pub pressure_unit: String,
    /// Abaqus slip-rate / LS-DYNA velocity unit (m/s, mm/s, m/min).
    #[arg(long, default_value = "mm/s")]
    pub speed_unit: String,
    /// Abaqus temperature unit (K or C).
    #[arg(long, default_value = "C")]
    pub temperature_unit: String,
    /// Abaqus TAUMAX (limiting shear stress), MPa.
    #[arg(long = "taumax-MPa")]
    pub taumax_mpa: Option<f64>,
    /// DEFORM: JSON list of windows {points_mm, pressure_mpa, velocity_m_per_min, temperature_k}.
    #[arg(long)]
    pub deform_windows: Option<PathBuf>,
    /// DEFORM: sliding velocity at which the FRCFAC p-T table is evaluated, m/min.
    #[arg(long, default_value_t = 150.0)]
    pub deform_reference_velocity_m_per_min: f64,
    /// DEFORM: object numbers (tool, workpiece).
    #[arg(long, value_delimiter = ',', default_value = "2,1")]
    pub deform_objects: Vec<u32>,
    /// LS-DYNA table id (curves take the following ids).
    #[arg(long, default_value_t = 1000)]
    pub lsdyna_table_id: u32,
    /// Random points of the deviation check of every format (cell centres and the
    /// neighbours of every grid line come on top); 0: no check.
    #[arg(long, default_value_t = 100_000)]
    pub check_points: usize,
    /// Engine tables: grid lines at the split thresholds of tree ensembles, restated in the
    /// engine's units, two points one float apart per threshold (exact for engines that
    /// interpolate linearly: Abaqus, LS-DYNA, DEFORM); only the grid's ends are kept besides.
    #[arg(long, value_enum, default_value = "auto")]
    pub steps: Steps,
    /// Surrogate table (--format table): auto (exact for tree ensembles, adaptive otherwise),
    /// exact, adaptive (over the box of the grid) or uniform (the grid itself, equidistant).
    #[arg(long, value_enum, default_value = "auto")]
    pub table_kind: crate::cmd_bench::TableKindArg,
    /// Engine tables (abaqus, lsdyna, deform, csv): grid lines of an adaptive table over the
    /// box of --pressure-MPa, --velocity-m-per-min (and --temperature-K), refined to
    /// --tolerance, instead of the given values.
    #[arg(long)]
    pub adaptive_grid: bool,
    /// Adaptive table or grid: max deviation from the law on its check set.
    #[arg(long, default_value_t = 1e-4)]
    pub tolerance: f64,
    /// Surrogate table: most cells (exact) or nodes (adaptive).
    #[arg(long = "max-table-size", default_value_t = 1 << 22)]
    pub max_table_size: usize,
}

impl Args {
    /// The library's options for these flags.
    pub fn options(&self) -> Result<ExportOptions> {
        if self.deform_objects.len() != 2 {
            bail!("--deform-objects takes two object numbers");
        }
        Ok(ExportOptions {
            law: self.law.clone(),
            format: self.format.into(),
            out: self.out.clone(),
            grid: Grid {
                pressure_pa: parse_values(&self.pressure_mpa, "--pressure-MPa")?
                    .iter()
                    .map(|p| p * 1e6)
                    .collect(),
                velocity_m_s: parse_values(&self.velocity, "--velocity-m-per-min")?
                    .iter()
                    .map(|v| v / 60.0)
                    .collect(),
                temperature_k: self
                    .temperature
                    .as_deref()
                    .map(|t| parse_values(t, "--temperature-K"))
                    .transpose()?,
            },
            units: units_by_name(
                &self.pressure_unit,
                &self.speed_unit,
                &self.temperature_unit,
            )?,
            taumax_pa: self.taumax_mpa.map(|t| t * 1e6),
            deform_windows: self.deform_windows.clone(),
            deform_reference_velocity_m_s: self.deform_reference_velocity_m_per_min / 60.0,
            deform_objects: (self.deform_objects[0], self.deform_objects[1]),
            lsdyna_table_id: self.lsdyna_table_id,
            check_points: self.check_points,
            steps: match self.steps {
                Steps::Auto => StepLines::Auto,
                Steps::On => StepLines::On,
                Steps::Off => StepLines::Off,
            },
            table_kind: self.table_kind.into(),
            tolerance: self.tolerance,
            max_table_size: self.max_table_size,
            adaptive_grid: self.adaptive_grid,
        })
    }
}

impl From<Format> for ExportFormat {
    fn from(f: Format) -> Self {
        match f {
            Format::Abaqus => ExportFormat::Abaqus,
            Format::Deform => ExportFormat::Deform,
            Format::Lsdyna => ExportFormat::Lsdyna,
            Format::Csv => ExportFormat::Csv,
            Format::Table => ExportFormat::Table,
        }
    }
}

pub fn run(a: Args) -> Result<()> {
    println!("{}", export(&a.options()?)?.line);
    Ok(())
}
