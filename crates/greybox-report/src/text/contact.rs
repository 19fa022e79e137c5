//! Plain text of wear (specific wear rates, the article's pin tests) and Hertzian contact.

use super::table::Table;
use greybox_core::dataset::PressureConvention;
use greybox_core::units::PA_PER_GPA;
use greybox_pipeline::hertz::HertzRow;
use greybox_pipeline::wear::{WearResult, WearTestRow};
use std::fmt::Write as _;

/// The article's wear tests re-derived.
pub fn wear_tests(rows: &[WearTestRow]) -> String {
    let mut text = String::new();
    let mut tab = Table::new(&[
        "pin",
        "s [m]",
        "V = k F s [mm3]",
        "k from V [1e-7 mm3/(N m)]",
        "k article",
    ]);
    for r in rows {
        tab.row(vec![
            r.pin.clone(),
            format!("{:.2}", r.sliding_distance_m),
            format!("{:.4e}", r.implied_volume_mm3),
            format!("{:.2}", r.k_back_1e_7),
            format!("{:.2}", r.k_article_1e_7),
        ]);
    }
    let _ = write!(text, "{}", tab.render());
    text
}

/// A specific wear rate with its volume and scar.
pub fn wear(r: &WearResult) -> String {
    let mut text = String::new();
    let k = r.k_mm3_per_nm;
    let _ = writeln!(
        text,
        "wear volume {:.4e} mm3 ({}), sliding distance {:.2} m",
        r.volume_mm3, r.volume_source, r.sliding_distance_m
    );
    let _ = writeln!(
        text,
        "Archard specific wear rate k = V/(F s) = {:.4e} mm3/(N m) = {:.3} x 1e-7 mm3/(N m)",
        k,
        k * 1e7
    );
    if let Some(kd) = r.k_dimensionless {
        let _ = writeln!(text, "dimensionless K = k H = {kd:.4e}");
    }
    if let Some(sc) = &r.scar {
        let _ = writeln!(text,
            "scar: mean depth {:.2} um, max depth {:.2} um, {:.3} x {:.3} mm, {} points, {} holes ({} filled), surface noise {:.3} um",
            sc.mean_depth_um, sc.max_depth_um, sc.length_mm, sc.width_mm, sc.scar_points, sc.holes, sc.holes_filled, sc.noise_um
        );
    }
    text
}

/// Hertzian contact per normal force.
pub fn hertz(e_star_pa: f64, rows: &[HertzRow], convention: PressureConvention) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "E* = {:.1} GPa", e_star_pa / PA_PER_GPA);
    let mut t = Table::new(&[
        "F [N]",
        "a or b [mm]",
        "p0 [MPa]",
        "p_mean [MPa]",
        "approach [um]",
        &format!("{} [MPa]", convention.name()),
    ]);
    for r in rows {
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
    let _ = write!(text, "{}", t.render());
    text
}
