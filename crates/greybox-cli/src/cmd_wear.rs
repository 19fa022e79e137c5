//! `greybox wear`: Archard specific wear rates from volumes, height maps or scar geometry.

use crate::output::print_json;
use anyhow::{bail, Result};
use greybox_pipeline::wear::{one_volume, wear_rate, wear_tests, WearInput};
use greybox_tribo::wear::Reference;
use std::path::PathBuf;

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RefArg {
    Sphere,
    Plane,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Wear tests CSV (pin, normal_force_N, velocity_m_per_min, duration_s, k_1e-7_mm3_per_Nm,
    /// mean_depth_um): implied volumes V = k F s and k back from V (examples/wear-tests.csv
    /// holds the article's five tests).
    #[arg(long)]
    pub tests: Option<PathBuf>,
    #[arg(long = "force-N")]
    pub force_n: Option<f64>,
    #[arg(long = "velocity-m-per-min")]
    pub velocity: Option<f64>,
    #[arg(long = "duration-s")]
    pub duration_s: Option<f64>,
    /// Measured wear volume, mm³.
    #[arg(long = "volume-mm3")]
    pub volume_mm3: Option<f64>,
    /// Height map of the worn pin: CSV x_mm,y_mm,z_um on a regular grid.
    #[arg(long)]
    pub height_map: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = RefArg::Sphere)]
    pub reference: RefArg,
    /// Pin tip radius for the sphere reference and the scar formula, mm.
    #[arg(long = "pin-radius-mm", default_value_t = 17.0)]
    pub pin_radius_mm: f64,
    /// Diameter of a flat wear scar on the spherical tip, mm.
    #[arg(long = "scar-diameter-mm")]
    pub scar_diameter_mm: Option<f64>,
    /// Hardness for the dimensionless K = k H, GPa.
    #[arg(long = "hardness-GPa")]
    pub hardness_gpa: Option<f64>,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    if let Some(t) = &a.tests {
        let rows = wear_tests(t)?;
        if a.json {
            return print_json(&rows);
        }
        print!("{}", greybox_report::text::wear_tests(&rows));
        return Ok(());
    }
    let (Some(f), Some(v), Some(t)) = (a.force_n, a.velocity, a.duration_s) else {
        bail!("give --force-N, --velocity-m-per-min and --duration-s (or --tests FILE)");
    };
    let reference = match a.reference {
        RefArg::Sphere => Reference::Sphere {
            radius_mm: a.pin_radius_mm,
        },
        RefArg::Plane => Reference::Plane,
    };
    let r = wear_rate(&WearInput {
        normal_force_n: f,
        velocity_m_per_min: v,
        duration_s: t,
        volume: one_volume(
            a.volume_mm3,
            a.height_map.clone().map(|p| (p, reference)),
            a.scar_diameter_mm,
        )?,
        pin_radius_mm: a.pin_radius_mm,
        hardness_gpa: a.hardness_gpa,
    })?;

    if a.json {
        return print_json(&r);
    }
    print!("{}", greybox_report::text::wear(&r));
    Ok(())
}
