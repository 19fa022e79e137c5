//! `greybox hertz`.

use crate::output::print_json;
use anyhow::Result;
use greybox_core::choice::clap_parsers::choice;
use greybox_core::dataset::PressureConvention;
use greybox_pipeline::hertz::{hertz, Geometry as HertzGeometry, HertzOptions};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// Sphere (pin tip) on a flat: circular contact.
    Sphere,
    /// Cylinder on a flat: line contact (needs --length-mm).
    Cylinder,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Normal force(s), N.
    #[arg(long = "force-N", num_args = 1.., required = true)]
    pub force_n: Vec<f64>,
    /// Sphere or cylinder radius, mm (article pin: 17).
    #[arg(long = "radius-mm", default_value_t = 17.0)]
    pub radius_mm: f64,
    #[arg(long, value_enum, default_value_t = Geometry::Sphere)]
    pub geometry: Geometry,
    /// Cylinder length, mm.
    #[arg(long = "length-mm")]
    pub length_mm: Option<f64>,
    /// Young's modulus of body 1 (disk), GPa; 'inf' for rigid.
    #[arg(long = "e1-GPa", default_value_t = 210.0)]
    pub e1_gpa: f64,
    /// Poisson's ratio of body 1.
    #[arg(long = "nu1", default_value_t = 0.3)]
    pub nu1: f64,
    /// Young's modulus of body 2 (pin), GPa; 'inf' for rigid.
    #[arg(long = "e2-GPa", default_value_t = 650.0)]
    pub e2_gpa: f64,
    /// Poisson's ratio of body 2.
    #[arg(long = "nu2", default_value_t = 0.3)]
    pub nu2: f64,
    /// Also report this convention's pressure (sphere only).
    #[arg(long, value_parser = choice::<PressureConvention>(), default_value = "textbook-max")]
    pub convention: PressureConvention,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let conv = a.convention;
    let geometry = match a.geometry {
        Geometry::Sphere => HertzGeometry::Sphere,
        Geometry::Cylinder => HertzGeometry::Cylinder {
            length_mm: a
                .length_mm
                .ok_or_else(|| anyhow::anyhow!("--geometry cylinder needs --length-mm"))?,
        },
    };
    let (e_star, rows) = hertz(
        &HertzOptions {
            geometry,
            radius_mm: a.radius_mm,
            e1_gpa: a.e1_gpa,
            nu1: a.nu1,
            e2_gpa: a.e2_gpa,
            nu2: a.nu2,
            convention: conv,
        },
        &a.force_n,
    )?;
    if a.json {
        return print_json(&rows);
    }
    print!("{}", greybox_pipeline::text::hertz(e_star, &rows, conv));
    Ok(())
}
