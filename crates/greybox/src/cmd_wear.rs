//! `greybox wear`: Archard specific wear rates from volumes, height maps or scar geometry.

use crate::output::{print_json, Table};
use anyhow::{bail, Result};
use greybox_tribo::wear::{
    analyze_height_map, archard_dimensionless, archard_k, cap_volume_from_scar, read_height_map,
    read_wear_tests, Reference, WearScar,
};
use serde::Serialize;
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

#[derive(Serialize)]
struct WearResult {
    volume_mm3: f64,
    volume_source: String,
    sliding_distance_m: f64,
    /// mm³/(N·m)
    k_mm3_per_nm: f64,
    k_dimensionless: Option<f64>,
    scar: Option<WearScar>,
}

#[derive(Serialize)]
struct TestRow {
    pin: String,
    sliding_distance_m: f64,
    implied_volume_mm3: f64,
    k_back_1e_7: f64,
    k_article_1e_7: f64,
}

pub fn run(a: Args) -> Result<()> {
    if let Some(t) = &a.tests {
        let tests = read_wear_tests(t)?;
        let rows: Vec<TestRow> = tests
            .iter()
            .map(|w| {
                let v = w.implied_volume_mm3();
                Ok(TestRow {
                    pin: w.pin.clone(),
                    sliding_distance_m: w.distance_m(),
                    implied_volume_mm3: v,
                    k_back_1e_7: archard_k(v, w.normal_force_n, w.distance_m())? * 1e7,
                    k_article_1e_7: w.k_1e7,
                })
            })
            .collect::<Result<_>>()?;
        if a.json {
            return print_json(&rows);
        }
        let mut tab = Table::new(&[
            "pin",
            "s [m]",
            "V = k F s [mm3]",
            "k from V [1e-7 mm3/(N m)]",
            "k article",
        ]);
        for r in &rows {
            tab.row(vec![
                r.pin.clone(),
                format!("{:.2}", r.sliding_distance_m),
                format!("{:.4e}", r.implied_volume_mm3),
                format!("{:.2}", r.k_back_1e_7),
                format!("{:.2}", r.k_article_1e_7),
            ]);
        }
        print!("{}", tab.render());
        return Ok(());
    }
    let (Some(f), Some(v), Some(t)) = (a.force_n, a.velocity, a.duration_s) else {
        bail!("give --force-N, --velocity-m-per-min and --duration-s (or --tests FILE)");
    };
    let s = v / 60.0 * t;
    let (volume, source, scar) = match (a.volume_mm3, &a.height_map, a.scar_diameter_mm) {
        (Some(vol), None, None) => (vol, "measured".to_string(), None),
        (None, Some(p), None) => {
            let map = read_height_map(p)?;
            let reference = match a.reference {
                RefArg::Sphere => Reference::Sphere {
                    radius_mm: a.pin_radius_mm,
                },
                RefArg::Plane => Reference::Plane,
            };
            let sc = analyze_height_map(&map, reference)?;
            (
                sc.volume_mm3,
                format!("height map {}", p.display()),
                Some(sc),
            )
        }
        (None, None, Some(d)) => (
            cap_volume_from_scar(a.pin_radius_mm, d)?.0,
            format!("spherical cap, scar diameter {d} mm"),
            None,
        ),
        _ => bail!("give exactly one of --volume-mm3, --height-map, --scar-diameter-mm"),
    };
    let k = archard_k(volume, f, s)?;
    let r = WearResult {
        volume_mm3: volume,
        volume_source: source,
        sliding_distance_m: s,
        k_mm3_per_nm: k,
        k_dimensionless: a.hardness_gpa.map(|h| archard_dimensionless(k, h * 1e9)),
        scar,
    };
    if a.json {
        return print_json(&r);
    }
    println!(
        "wear volume {:.4e} mm3 ({}), sliding distance {:.2} m",
        r.volume_mm3, r.volume_source, r.sliding_distance_m
    );
    println!(
        "Archard specific wear rate k = V/(F s) = {:.4e} mm3/(N m) = {:.3} x 1e-7 mm3/(N m)",
        k,
        k * 1e7
    );
    if let Some(kd) = r.k_dimensionless {
        println!("dimensionless K = k H = {kd:.4e}");
    }
    if let Some(sc) = &r.scar {
        println!(
            "scar: mean depth {:.2} um, max depth {:.2} um, {:.3} x {:.3} mm, {} points, {} holes ({} filled), surface noise {:.3} um",
            sc.mean_depth_um, sc.max_depth_um, sc.length_mm, sc.width_mm, sc.scar_points, sc.holes, sc.holes_filled, sc.noise_um
        );
    }
    Ok(())
}
