//! A friction dataset CSV (the columns identification writes) from a few rows.

use std::path::Path;

/// The header of a dataset CSV as identification writes it.
pub const HEADER: &str = "pin,step,normal_force_N,normal_force_measured_N,sliding_velocity_m_per_min,hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n";

/// One stationary step of a dataset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Normal force, N (planned and measured).
    pub normal_force_n: f64,
    /// Sliding velocity, m/min.
    pub velocity_m_per_min: f64,
    /// Hertz pressure, MPa (textbook-max convention).
    pub pressure_mpa: f64,
    /// Apparent friction coefficient μ_app.
    pub cof_apparent: f64,
}

/// A dataset of one pin, one step per row (steps numbered from 0), written to `path`.
pub fn write_rows(path: &Path, rows: &[Row]) {
    let mut csv = String::from(HEADER);
    for (k, r) in rows.iter().enumerate() {
        let (f, v, p, mu) = (
            r.normal_force_n,
            r.velocity_m_per_min,
            r.pressure_mpa,
            r.cof_apparent,
        );
        csv += &format!("1,{k},{f},{f},{v},{p},textbook-max,{mu},0.01,1000,1,2,0,true,\n");
    }
    std::fs::write(path, csv).unwrap();
}

/// A dataset of one `(normal force N, μ_app)` row per step, all at 100 m/min and 1500 MPa,
/// written to `path`.
pub fn write_dataset(path: &Path, rows: &[(f64, f64)]) {
    let rows: Vec<Row> = rows
        .iter()
        .map(|&(normal_force_n, cof_apparent)| Row {
            normal_force_n,
            velocity_m_per_min: 100.0,
            pressure_mpa: 1500.0,
            cof_apparent,
        })
        .collect();
    write_rows(path, &rows);
}
