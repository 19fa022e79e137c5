//! `greybox adhesive`: the ploughing correction μ_adh = μ_app − μ_plough.

use crate::output::print_json;
use anyhow::{Context, Result};
use greybox_pipeline::adhesive::{
    adhesive, correction_path, track_widths, AdhesiveMethod, AdhesiveOptions, SimulationOptions,
};
use greybox_tribo::ploughing::{correct_analytic, TrackWidth};
use std::path::PathBuf;

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Bowden–Tabor sphere ploughing with measured track widths.
    Analytic,
    /// Inverse pin-sliding simulation with the built-in SPH solver (the article's method).
    Simulation,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Friction dataset CSV from `greybox identify`.
    #[arg(long)]
    pub data: PathBuf,
    #[arg(long, value_enum, default_value_t = Method::Analytic)]
    pub method: Method,
    /// Pin tip radius, mm.
    #[arg(long = "pin-radius-mm", default_value_t = 17.0)]
    pub pin_radius_mm: f64,
    /// Measured track width as FORCE_N:WIDTH_um (repeatable); default: the article's Table 3.
    #[arg(long = "track-width")]
    pub track_width: Vec<String>,
    /// CSV of measured track widths with columns normal_force_N, track_width_um.
    #[arg(long = "track-widths-csv")]
    pub track_widths_csv: Option<PathBuf>,
    /// Output dataset with the cof_adhesive column (the correction goes beside it as .correction.json).
    #[arg(long, default_value = "dataset_adhesive.csv")]
    pub out: PathBuf,
    #[arg(long)]
    pub json: bool,
    /// Simulation: number of highest distinct loads simulated (the share is fitted against load
    /// and applied to all loads, as in the article).
    #[arg(long = "sim-loads", default_value_t = 3)]
    pub sim_loads: usize,
    /// Simulation: particle spacing, µm.
    #[arg(long = "sim-spacing-um", default_value_t = 10.0)]
    pub sim_spacing_um: f64,
    /// Simulation: slide length, mm.
    #[arg(long = "sim-slide-mm", default_value_t = 1.5)]
    pub sim_slide_mm: f64,
    /// Simulation: workpiece height, mm (the article's FE model: 1 mm).
    #[arg(long = "sim-height-mm", default_value_t = 1.0)]
    pub sim_height_mm: f64,
    /// Simulation: stop when |simulated F_t/F_N − μ_app| ≤ this.
    #[arg(long = "sim-tolerance", default_value_t = 0.002)]
    pub sim_tolerance: f64,
    /// Simulation: maximum runs per load.
    #[arg(long = "sim-max-runs", default_value_t = 5)]
    pub sim_max_runs: usize,
}

impl Args {
    /// The library's options for these flags.
    pub fn options(&self) -> Result<AdhesiveOptions> {
        let mut track_widths = Vec::new();
        for t in &self.track_width {
            let (f, x) = t
                .split_once(':')
                .with_context(|| format!("--track-width '{t}': expected FORCE_N:WIDTH_um"))?;
            let parse = |s: &str| {
                s.trim()
                    .parse::<f64>()
                    .with_context(|| format!("--track-width '{t}': '{s}' is not a number"))
            };
            track_widths.push(TrackWidth {
                normal_force_n: parse(f)?,
                width_um: parse(x)?,
            });
        }
        Ok(AdhesiveOptions {
            data: self.data.clone(),
            method: match self.method {
                Method::Analytic => AdhesiveMethod::Analytic,
                Method::Simulation => AdhesiveMethod::Simulation(SimulationOptions {
                    loads: self.sim_loads,
                    spacing_um: self.sim_spacing_um,
                    slide_mm: self.sim_slide_mm,
                    height_mm: self.sim_height_mm,
                    tolerance: self.sim_tolerance,
                    max_runs: self.sim_max_runs,
                }),
            },
            pin_radius_mm: self.pin_radius_mm,
            track_widths,
            track_widths_csv: self.track_widths_csv.clone(),
            out: self.out.clone(),
        })
    }
}

pub fn run(a: Args) -> Result<()> {
    let options = a.options()?;
    let (ds, c) = adhesive(&options)?;
    if a.json {
        return print_json(&c);
    }
    print!("{}", greybox_pipeline::text::correction(&c));
    if a.method == Method::Simulation {
        // The analytic Bowden–Tabor correction beside it, for comparison.
        let mut twin = ds.clone();
        let bt = correct_analytic(
            &mut twin,
            greybox_core::units::mm_to_m(a.pin_radius_mm),
            &track_widths(&options)?,
        )?;
        println!(
            "  analytic Bowden-Tabor (sphere) for comparison: mean reduction {:.2} %",
            bt.mean_reduction_percent
        );
    }
    println!(
        "wrote {} and {}",
        a.out.display(),
        correction_path(&a.out).display()
    );
    Ok(())
}
