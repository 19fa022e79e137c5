//! `greybox material`: Johnson–Cook parameters from compression flow curves (A, B, n, m) and
//! the rate sensitivity C from a measured cutting force (inverse cutting simulations).

use crate::output::print_json;
use anyhow::Result;
use greybox_material::fit::{FitOptions, JcFit};
use greybox_pipeline::material::{fit_flow_curves, fit_rate_sensitivity, RateSensitivityOptions};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    pub what: Material,
}

#[derive(clap::Subcommand, Debug)]
pub enum Material {
    /// Fit J-C A, B, n, m to flow curves (CSV: strain,stress_MPa,temperature_C,strain_rate_per_s).
    Fit(FitArgs),
    /// Find J-C C so that the simulated steady cutting force matches a measured one.
    FitC(FitCArgs),
}

#[derive(clap::Args, Debug)]
pub struct FitArgs {
    /// Flow-curve CSV.
    #[arg(long)]
    pub curves: PathBuf,
    /// Strain-rate sensitivity C held fixed (find it with `material fit-c`).
    #[arg(long, default_value_t = 0.0)]
    pub c: f64,
    /// Reference strain rate ε̇₀, 1/s (default: the lowest rate in the data).
    #[arg(long = "ref-strain-rate-per-s")]
    pub ref_strain_rate: Option<f64>,
    /// Room temperature of the J-C T*, °C (default: the lowest test temperature).
    #[arg(long = "room-temperature-c")]
    pub room_temperature_c: Option<f64>,
    /// Melting temperature, K (AISI 1045: 1773).
    #[arg(long = "melt-temperature-k", default_value_t = 1773.0)]
    pub melt_temperature_k: f64,
    /// Flag temperatures whose relative RMS misfit exceeds this.
    #[arg(long = "misfit-threshold", default_value_t = 0.05)]
    pub misfit_threshold: f64,
    /// Write the fit (parameters, residuals, warnings) as JSON here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args, Debug)]
pub struct FitCArgs {
    /// Cutting set-up TOML (its material's C is replaced in each run).
    #[arg(long)]
    pub config: PathBuf,
    /// Measured cutting force per unit width, N/mm.
    #[arg(long = "measured-force-n-per-mm")]
    pub measured_force_n_per_mm: f64,
    #[arg(long = "c-min", default_value_t = 0.0)]
    pub c_min: f64,
    #[arg(long = "c-max", default_value_t = 0.1)]
    pub c_max: f64,
    /// Stop when the force is matched within this, N/mm.
    #[arg(long = "tolerance-n-per-mm", default_value_t = 3.0)]
    pub tolerance_n_per_mm: f64,
    /// At most this many cutting simulations.
    #[arg(long = "max-runs", default_value_t = greybox_pipeline::material::CalibrationRuns::of(6))]
    pub max_runs: greybox_pipeline::material::CalibrationRuns,
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

/// Runs the flow-curve fit.
pub fn fit(a: &FitArgs) -> Result<JcFit> {
    let opts = FitOptions {
        c: a.c,
        ref_strain_rate: a.ref_strain_rate,
        room_temperature_k: a.room_temperature_c.map(|t| t + 273.15),
        melt_temperature_k: a.melt_temperature_k,
        misfit_threshold: a.misfit_threshold,
    };
    fit_flow_curves(&a.curves, &opts, a.out.as_deref())
}

pub fn run(a: Args) -> Result<()> {
    match a.what {
        Material::Fit(a) => {
            let f = fit(&a)?;
            if a.json {
                return print_json(&f);
            }
            print!("{}", greybox_pipeline::text::johnson_cook(&f));
            Ok(())
        }
        Material::FitC(a) => {
            let r = fit_rate_sensitivity(&RateSensitivityOptions {
                config: a.config.clone(),
                measured_force_n_per_m: greybox_core::units::per_mm_to_per_m(
                    a.measured_force_n_per_mm,
                ),
                c_range: (a.c_min, a.c_max),
                tolerance_n_per_m: greybox_core::units::per_mm_to_per_m(a.tolerance_n_per_mm),
                max_runs: a.max_runs,
                out: a.out.clone(),
            })?;
            if a.json {
                return print_json(&r);
            }
            print!("{}", greybox_pipeline::text::rate_sensitivity(&r));
            Ok(())
        }
    }
}
