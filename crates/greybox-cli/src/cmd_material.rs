//! `greybox material`: Johnson–Cook parameters from compression flow curves (A, B, n, m) and
//! the rate sensitivity C from a measured cutting force (inverse cutting simulations).

use crate::output::print_json;
use anyhow::Result;
use greybox_material::fit::JcFit;
use greybox_pipeline::material::fit_rate_sensitivity;
use greybox_pipeline::settings::material::{FlowCurveSettings, RateSensitivitySettings};

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
    #[command(flatten)]
    pub settings: FlowCurveSettings,
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args, Debug)]
pub struct FitCArgs {
    #[command(flatten)]
    pub settings: RateSensitivitySettings,
    #[arg(long)]
    pub json: bool,
}

/// Runs the flow-curve fit.
pub fn fit(a: &FitArgs) -> Result<JcFit> {
    a.settings.run()
}

pub fn run(a: Args) -> Result<()> {
    match a.what {
        Material::Fit(a) => {
            let f = fit(&a)?;
            if a.json {
                return print_json(&f);
            }
            print!("{}", greybox_report::text::johnson_cook(&f));
            Ok(())
        }
        Material::FitC(a) => {
            let r = fit_rate_sensitivity(&a.settings.options()?)?;
            if a.json {
                return print_json(&r);
            }
            print!("{}", greybox_report::text::rate_sensitivity(&r));
            Ok(())
        }
    }
}
