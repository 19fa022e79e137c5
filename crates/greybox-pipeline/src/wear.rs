//! Archard specific wear rates from measured volumes, height maps of the worn pin, or the
//! scar geometry; and the article's wear tests (V = k F s and k back from V).

use anyhow::Result;
use greybox_contact::wear::{
    analyze_height_map, archard_dimensionless, archard_k, cap_volume_from_scar, read_height_map,
    read_wear_tests, Reference, WearScar, WearTest,
};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// How the wear volume is known.
#[derive(Debug, Clone)]
pub enum WearVolume {
    /// Measured, mm³.
    Measured(f64),
    /// From a height map of the worn pin (CSV x_mm, y_mm, z_um on a regular grid) against
    /// an unworn reference.
    HeightMap { path: PathBuf, reference: Reference },
    /// A spherical cap of a flat scar of this diameter, mm, on the pin's tip.
    ScarDiameter(f64),
}

/// One wear measurement.
#[derive(Debug, Clone)]
pub struct WearInput {
    pub normal_force_n: f64,
    pub velocity_m_per_min: f64,
    pub duration_s: f64,
    pub volume: WearVolume,
    /// Pin tip radius (scar formula), mm.
    pub pin_radius_mm: f64,
    /// Hardness for the dimensionless K = k H, GPa.
    pub hardness_gpa: Option<f64>,
}

/// The specific wear rate of one measurement.
#[derive(Debug, Clone, Serialize)]
pub struct WearResult {
    pub volume_mm3: f64,
    pub volume_source: String,
    pub sliding_distance_m: f64,
    /// mm³/(N·m)
    pub k_mm3_per_nm: f64,
    pub k_dimensionless: Option<f64>,
    pub scar: Option<WearScar>,
}

/// Archard's k = V/(F s) of one measurement.
///
/// ```
/// use greybox_pipeline::wear::{wear_rate, WearInput, WearVolume};
/// // 0.01 mm³ worn off under 100 N over 100 m (60 m/min for 100 s): k = 1e-6 mm³/(N m)
/// let r = wear_rate(&WearInput {
///     normal_force_n: 100.0,
///     velocity_m_per_min: 60.0,
///     duration_s: 100.0,
///     volume: WearVolume::Measured(0.01),
///     pin_radius_mm: 17.0,
///     hardness_gpa: None,
/// })
/// .unwrap();
/// assert!((r.sliding_distance_m - 100.0).abs() < 1e-12);
/// assert!((r.k_mm3_per_nm - 1e-6).abs() < 1e-18);
/// ```
pub fn wear_rate(w: &WearInput) -> Result<WearResult> {
    let s = w.velocity_m_per_min / 60.0 * w.duration_s;
    let (volume, source, scar) = match &w.volume {
        WearVolume::Measured(vol) => (*vol, "measured".to_string(), None),
        WearVolume::HeightMap { path, reference } => {
            let map = read_height_map(path)?;
            let sc = analyze_height_map(&map, *reference)?;
            (
                sc.volume_mm3,
                format!("height map {}", path.display()),
                Some(sc),
            )
        }
        WearVolume::ScarDiameter(d) => (
            cap_volume_from_scar(w.pin_radius_mm, *d)?.0,
            format!("spherical cap, scar diameter {d} mm"),
            None,
        ),
    };
    let k = archard_k(volume, w.normal_force_n, s)?;
    Ok(WearResult {
        volume_mm3: volume,
        volume_source: source,
        sliding_distance_m: s,
        k_mm3_per_nm: k,
        k_dimensionless: w.hardness_gpa.map(|h| archard_dimensionless(k, h * 1e9)),
        scar,
    })
}

/// One of the article's wear tests, re-derived.
#[derive(Debug, Clone, Serialize)]
pub struct WearTestRow {
    pub pin: String,
    pub sliding_distance_m: f64,
    pub implied_volume_mm3: f64,
    pub k_back_1e_7: f64,
    pub k_article_1e_7: f64,
}

/// The wear tests of a CSV (pin, normal_force_N, velocity_m_per_min, duration_s,
/// k_1e-7_mm3_per_Nm, mean_depth_um), each re-derived by [`wear_test_row`].
pub fn wear_tests(path: &Path) -> Result<Vec<WearTestRow>> {
    read_wear_tests(path)?.iter().map(wear_test_row).collect()
}

/// One wear test re-derived: the implied volume V = k F s, and k back from V.
pub fn wear_test_row(w: &WearTest) -> Result<WearTestRow> {
    let v = w.implied_volume_mm3();
    Ok(WearTestRow {
        pin: w.pin.clone(),
        sliding_distance_m: w.distance_m(),
        implied_volume_mm3: v,
        k_back_1e_7: archard_k(v, w.normal_force_n, w.distance_m())? * 1e7,
        k_article_1e_7: w.k_1e7,
    })
}
