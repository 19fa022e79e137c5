//! Johnson–Cook parameters: A, B, n, m from compression flow curves, and the rate
//! sensitivity C from a measured cutting force (inverse cutting simulations).

use crate::output::provenance;
use crate::simulate::read_cutting_setup;
use anyhow::{Context, Result};
use greybox_core::outputs::check_file_output;
use greybox_material::fit::{fit_johnson_cook, read_flow_curves, FitOptions, JcFit};
use greybox_sim::cut_run::{find_rate_sensitivity, RateSensitivityFit};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Fit A, B, n, m to the flow curves of `curves` (CSV: strain, stress_MPa, temperature_C,
/// strain_rate_per_s); with `out`, the fit is written there as JSON (with its provenance).
pub fn fit_flow_curves(curves: &Path, options: &FitOptions, out: Option<&Path>) -> Result<JcFit> {
    let inputs = [("curves", curves)];
    if let Some(p) = out {
        check_file_output(p, "out", &inputs)?;
    }
    let pts = read_flow_curves(curves)?;
    let f = fit_johnson_cook(&pts, options).with_context(|| curves.display().to_string())?;
    if let Some(p) = out {
        write_json_beside_provenance(p, &f, &inputs)?;
    }
    Ok(f)
}

/// Cutting simulations of one calibration of C (the search needs two to bracket).
pub type CalibrationRuns = greybox_core::count::Count<2, 100>;

/// Options of [`fit_rate_sensitivity`].
#[derive(Debug, Clone)]
pub struct RateSensitivityOptions {
    /// Cutting set-up TOML (its material's C is replaced in each run).
    pub config: PathBuf,
    /// Measured cutting force per unit width, N/m.
    pub measured_force_n_per_m: f64,
    /// Range of C searched.
    pub c_range: (f64, f64),
    /// Stop when the force is matched within this, N/m.
    pub tolerance_n_per_m: f64,
    /// At most this many cutting simulations.
    pub max_runs: CalibrationRuns,
    /// Write the result as JSON here.
    pub out: Option<PathBuf>,
}

/// Find J-C C so that the simulated steady cutting force matches the measured one.
pub fn fit_rate_sensitivity(o: &RateSensitivityOptions) -> Result<RateSensitivityFit> {
    let inputs = [("config", o.config.as_path())];
    if let Some(p) = &o.out {
        check_file_output(p, "out", &inputs)?;
    }
    let case = read_cutting_setup(&o.config)?;
    let r = find_rate_sensitivity(
        &case.setup,
        case.law.clone(),
        o.measured_force_n_per_m,
        o.c_range,
        o.tolerance_n_per_m,
        o.max_runs.get(),
    )?;
    if let Some(p) = &o.out {
        write_json_beside_provenance(p, &r, &inputs)?;
    }
    Ok(r)
}

/// Write `value` as pretty JSON to `path`, its provenance beside it.
fn write_json_beside_provenance(
    path: &Path,
    value: &impl Serialize,
    inputs: &[(&str, &Path)],
) -> Result<()> {
    let text = serde_json::to_string_pretty(value)?;
    let staged = vec![
        provenance(inputs)?.stage_beside(path)?,
        greybox_core::atomic::stage(path, |w| w.write_all(text.as_bytes()))?,
    ];
    greybox_core::atomic::commit_together(staged)?;
    Ok(())
}
