//! `greybox export`: a friction law as tables for FE engines, or as a surrogate table. The
//! options and their defaults are the library's ([`ExportOptions`]); a flag only overrides.

use crate::output::emit;
use anyhow::Result;
use greybox_core::choice::clap_parsers::choice;
use greybox_core::units::{m_per_min_to_m_per_s, mpa_to_pa};
use greybox_friction::export::{StepLines, TempUnit};
use greybox_friction::grid::UnitSystem;
use greybox_friction::table_file::TableKind;
use greybox_pipeline::export::{export, ExportFormat, ExportOptions, ExportOverrides};
use std::path::PathBuf;

/// Two object numbers, `TOOL,WORKPIECE`.
fn object_pair(s: &str) -> Result<[u32; 2], String> {
    let n: Vec<u32> = s
        .split(',')
        .map(|x| {
            x.trim()
                .parse()
                .map_err(|_| format!("'{x}' is not an object number"))
        })
        .collect::<Result<_, _>>()?;
    <[u32; 2]>::try_from(n).map_err(|_| "expected two object numbers, TOOL,WORKPIECE".into())
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Law file, model file from `greybox fit`, or table.
    #[arg(long)]
    pub law: PathBuf,
    #[arg(long, value_parser = choice::<ExportFormat>())]
    pub format: ExportFormat,
    /// Output file.
    #[arg(long)]
    pub out: PathBuf,
    /// Pressures, MPa: MIN:MAX:N (equidistant) or a comma list [default: 500:2500:21].
    #[arg(long = "pressure-MPa")]
    pub pressure_mpa: Option<String>,
    /// Sliding velocities, m/min: MIN:MAX:N or a comma list [default: 10:300:30].
    #[arg(long = "velocity-m-per-min")]
    pub velocity: Option<String>,
    /// Temperatures, K: MIN:MAX:N or a comma list (omit for μ(p, v) only).
    #[arg(long = "temperature-K")]
    pub temperature: Option<String>,
    /// Abaqus/LS-DYNA: the model's consistent unit system (pressure and slip-rate units
    /// follow from it) [default: MPa-mm-s].
    #[arg(long, value_parser = choice::<UnitSystem>())]
    pub units: Option<UnitSystem>,
    /// Abaqus/LS-DYNA temperature unit [default: C].
    #[arg(long, value_parser = choice::<TempUnit>())]
    pub temperature_unit: Option<TempUnit>,
    /// Abaqus TAUMAX (limiting shear stress), MPa.
    #[arg(long = "taumax-MPa")]
    pub taumax_mpa: Option<f64>,
    /// DEFORM: JSON list of windows {points_mm, pressure_mpa, velocity_m_per_min, temperature_k}.
    #[arg(long)]
    pub deform_windows: Option<PathBuf>,
    /// DEFORM: sliding velocity at which the FRCFAC p-T table is evaluated, m/min
    /// [default: 150].
    #[arg(long)]
    pub deform_reference_velocity_m_per_min: Option<f64>,
    /// DEFORM: object numbers TOOL,WORKPIECE [default: 2,1].
    #[arg(long, value_parser = object_pair)]
    pub deform_objects: Option<[u32; 2]>,
    /// LS-DYNA table id (curves take the following ids) [default: 1000].
    #[arg(long)]
    pub lsdyna_table_id: Option<u32>,
    /// Random points of the deviation check of every format (cell centres and the
    /// neighbours of every grid line come on top); 0: no check [default: 100000].
    #[arg(long)]
    pub check_points: Option<greybox_pipeline::export::CheckPoints>,
    /// Engine tables: grid lines at the split thresholds of tree ensembles, two points one
    /// float apart per threshold (exact for engines that interpolate linearly); auto: for
    /// tree-ensemble laws [default: auto].
    #[arg(long, value_parser = choice::<StepLines>())]
    pub steps: Option<StepLines>,
    /// Surrogate table (--format table): exact, adaptive (over the box of the grid) or
    /// uniform (the grid itself, equidistant) [default: exact for tree ensembles, adaptive
    /// otherwise].
    #[arg(long, value_parser = choice::<TableKind>())]
    pub table_kind: Option<TableKind>,
    /// Engine tables: grid lines of an adaptive table over the box of the grid, refined to
    /// --tolerance, instead of the given values.
    #[arg(long)]
    pub adaptive_grid: bool,
    /// Adaptive table or grid: max deviation from the law on its check set [default: 1e-4].
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Largest table in values (engine-table points, surrogate cells or nodes); a bigger
    /// one is refused with its size [default: 4194304].
    #[arg(long = "max-table-size")]
    pub max_table_size: Option<greybox_pipeline::export::TableSize>,
    /// Print the export report as JSON.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// The library's options: its defaults, with the fields these flags set.
    pub fn options(&self) -> Result<ExportOptions> {
        let overrides = ExportOverrides {
            units: self.units,
            temperature_unit: self.temperature_unit,
            taumax_Pa: self.taumax_mpa.map(mpa_to_pa),
            deform_reference_velocity_m_per_s: self
                .deform_reference_velocity_m_per_min
                .map(m_per_min_to_m_per_s),
            deform_objects: self.deform_objects,
            deform_windows: self.deform_windows.clone(),
            lsdyna_table_id: self.lsdyna_table_id,
            table_kind: self.table_kind,
            check_points: self.check_points,
            steps: self.steps,
            adaptive_grid: self.adaptive_grid.then_some(true),
            tolerance: self.tolerance,
            max_table_size: self.max_table_size,
            ..Default::default()
        }
        .with_edge_grid(
            self.pressure_mpa.as_deref(),
            self.velocity.as_deref(),
            self.temperature.as_deref(),
        )?;
        ExportOptions::new(self.law.clone(), self.format, self.out.clone()).overridden(&overrides)
    }
}

pub fn run(a: Args) -> Result<()> {
    let report = export(&a.options()?)?;
    for w in &report.warnings {
        eprintln!("warning: {}", crate::flags::shown(w));
    }
    emit(a.json, &report, |r| format!("{}\n", r.line))
}
