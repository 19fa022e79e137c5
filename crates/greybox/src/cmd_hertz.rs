//! `greybox hertz`.

use crate::cmd_identify::ConventionArg;
use crate::output::{print_json, Table};
use anyhow::Result;
use greybox_core::dataset::PressureConvention;
use greybox_core::units::{M_PER_MM, PA_PER_GPA, PA_PER_MPA};
use greybox_tribo::hertz::{cylinder_on_flat, effective_modulus, Elastic, PinContact};
use serde::Serialize;

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
    #[arg(long, value_enum, default_value_t = ConventionArg::TextbookMax)]
    pub convention: ConventionArg,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct Row {
    force_n: f64,
    contact_half_width_mm: f64,
    max_pressure_mpa: f64,
    mean_pressure_mpa: f64,
    approach_um: Option<f64>,
    convention: String,
    convention_pressure_mpa: f64,
}

pub fn run(a: Args) -> Result<()> {
    let e_star = effective_modulus(
        Elastic::new(a.e1_gpa * PA_PER_GPA, a.nu1),
        Elastic::new(a.e2_gpa * PA_PER_GPA, a.nu2),
    )?;
    let conv: PressureConvention = a.convention.into();
    let mut rows = Vec::new();
    for &f in &a.force_n {
        let (h, pc) = match a.geometry {
            Geometry::Sphere => {
                let contact = PinContact {
                    pin_tip_radius_mm: a.radius_mm,
                    disk_youngs_modulus_gpa: a.e1_gpa,
                    disk_poisson_ratio: a.nu1,
                    pin_youngs_modulus_gpa: a.e2_gpa,
                    pin_poisson_ratio: a.nu2,
                    convention: conv,
                };
                (contact.solve(f)?, contact.pressure_pa(f)?)
            }
            Geometry::Cylinder => {
                let l = a
                    .length_mm
                    .ok_or_else(|| anyhow::anyhow!("--geometry cylinder needs --length-mm"))?;
                if conv == PressureConvention::ArticleEq7 {
                    anyhow::bail!("the article's convention is defined for a sphere only");
                }
                let h = cylinder_on_flat(f, l * M_PER_MM, a.radius_mm * M_PER_MM, e_star)?;
                let pc = if conv == PressureConvention::TextbookMean {
                    h.mean_pressure_pa
                } else {
                    h.max_pressure_pa
                };
                (h, pc)
            }
        };
        rows.push(Row {
            force_n: f,
            contact_half_width_mm: h.contact_half_width_m / M_PER_MM,
            max_pressure_mpa: h.max_pressure_pa / PA_PER_MPA,
            mean_pressure_mpa: h.mean_pressure_pa / PA_PER_MPA,
            approach_um: h.approach_m.map(|d| d * 1e6),
            convention: conv.name().into(),
            convention_pressure_mpa: pc / PA_PER_MPA,
        });
    }
    if a.json {
        return print_json(&rows);
    }
    println!("E* = {:.1} GPa", e_star / PA_PER_GPA);
    let mut t = Table::new(&[
        "F [N]",
        "a or b [mm]",
        "p0 [MPa]",
        "p_mean [MPa]",
        "approach [um]",
        &format!("{} [MPa]", conv.name()),
    ]);
    for r in &rows {
        t.row(vec![
            format!("{}", r.force_n),
            format!("{:.5}", r.contact_half_width_mm),
            format!("{:.1}", r.max_pressure_mpa),
            format!("{:.1}", r.mean_pressure_mpa),
            r.approach_um
                .map(|d| format!("{d:.3}"))
                .unwrap_or_else(|| "-".into()),
            format!("{:.1}", r.convention_pressure_mpa),
        ]);
    }
    print!("{}", t.render());
    Ok(())
}
