//! Stage 1: plan a campaign — the study file, the run sheet and one NC program per pin.

use crate::output::{provenance, stage_out_dir};
use crate::study::Study;
use anyhow::{Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_tribo::gcode::write_program;
use greybox_tribo::plan::Plan;
use serde::Serialize;
use std::path::Path;

/// What a plan holds, for a report.
#[derive(Debug, Clone, Serialize)]
pub struct PlanSummary {
    pub pins: usize,
    pub steps: usize,
    pub normal_forces_n: Vec<f64>,
    pub velocity_min_m_per_min: f64,
    pub velocity_max_m_per_min: f64,
    pub spindle_rpm_min: f64,
    pub spindle_rpm_max: f64,
    pub pin_duration_s: f64,
    pub campaign_recording_s: f64,
    /// The files written, as the caller named them.
    pub files: Vec<String>,
}

/// Build the study's plan and write it into the directory `out` (staged, swapped in whole;
/// an existing non-empty `out` needs `force`). `inputs` are recorded in its provenance
/// (e.g. the study file).
///
/// ```
/// use greybox_pipeline::{plan::plan, Study};
/// let dir = tempfile::tempdir().unwrap();
/// let mut study = Study::default(); // the article's design: 10 loads × 21 velocities
/// study.plan.track_radius_mm = Some(100.0);
/// let out = dir.path().join("plan");
/// let s = plan(&study, &out, false, &[]).unwrap();
/// assert_eq!((s.pins, s.steps), (10, 210));
/// assert!(out.join("nc/pin10.nc").is_file() && out.join("provenance.json").is_file());
/// // n = v / (2π R): 20 m/min on a 100 mm track radius is 31.83 rpm (NC programs hold 0.01 rpm)
/// assert!((s.spindle_rpm_min - 20.0 / (2.0 * std::f64::consts::PI * 0.1)).abs() <= 0.005);
/// ```
pub fn plan(
    study: &Study,
    out: &Path,
    force: bool,
    inputs: &[(&str, &Path)],
) -> Result<PlanSummary> {
    let plan = study.plan.build().context("cannot build the plan")?;
    let staged = stage_out_dir(out, force, inputs)?;
    let files = write_plan(study, &plan, staged.path())?;
    provenance(inputs)?.write_into(staged.path())?;
    let files = files.iter().map(|f| staged.shown_str(f)).collect();
    staged.commit()?;
    Ok(summarize(&plan, files))
}

/// Write study.toml, run_sheet.csv and the NC programs of a plan into `out`.
pub fn write_plan(study: &Study, plan: &Plan, out: &Path) -> Result<Vec<String>> {
    let mut files = Vec::new();
    let mut resolved = study.clone();
    resolved.plan = plan.spec.clone();
    let p = out.join("study.toml");
    write_string_atomic(&p, &resolved.to_toml()?)?;
    files.push(p.display().to_string());
    let p = out.join("run_sheet.csv");
    plan.write_run_sheet(&p)?;
    files.push(p.display().to_string());
    for pin in 1..=plan.pins.len() as u32 {
        let p = out.join("nc").join(format!("pin{pin:02}.nc"));
        write_string_atomic(&p, &write_program(plan, pin))?;
        files.push(p.display().to_string());
    }
    Ok(files)
}

/// The summary of `plan`, listing `files`.
pub fn summarize(plan: &Plan, files: Vec<String>) -> PlanSummary {
    let v: Vec<f64> = plan
        .pin_steps(1)
        .iter()
        .map(|s| s.sliding_velocity_m_s * 60.0)
        .collect();
    let rpm: Vec<f64> = plan.pin_steps(1).iter().map(|s| s.spindle_rpm).collect();
    PlanSummary {
        pins: plan.pins.len(),
        steps: plan.steps.len(),
        normal_forces_n: plan.pins.iter().map(|p| p.normal_force_n).collect(),
        velocity_min_m_per_min: v.iter().cloned().fold(f64::INFINITY, f64::min),
        velocity_max_m_per_min: v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        spindle_rpm_min: rpm.iter().cloned().fold(f64::INFINITY, f64::min),
        spindle_rpm_max: rpm.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        pin_duration_s: plan.pins[0].end_s,
        campaign_recording_s: plan.pins.iter().map(|p| p.end_s).sum(),
        files,
    }
}
