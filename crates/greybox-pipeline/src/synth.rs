//! The virtual tribometer: recordings and their ground truth for a plan.

use crate::output::{provenance, stage_out_dir};
use crate::study::Study;
use anyhow::{Context, Result};
use greybox_recording::csv_recording::write_csv_recording;
use greybox_recording::readers::RecordingFormat;
use greybox_recording::tdms::write_tdms_recording;
use greybox_tribo::plan::Plan;
use greybox_tribo::synth::write_ground_truth;
use serde::Serialize;
use std::path::Path;

/// What the virtual rig wrote.
#[derive(Debug, Clone, Serialize)]
pub struct SynthSummary {
    pub pins: usize,
    pub samples: usize,
    pub seed: u64,
    pub cof_true_min: f64,
    pub cof_true_max: f64,
    pub files: Vec<String>,
}

/// Build the study's plan, simulate it and write the recordings (in each of `formats`) and
/// `ground_truth.csv` into the directory `out` (staged, swapped in whole; an existing
/// non-empty `out` needs `force`). The seed is `study.synth.seed`.
pub fn synth(
    study: &Study,
    formats: &[RecordingFormat],
    out: &Path,
    force: bool,
    inputs: &[(&str, &Path)],
) -> Result<SynthSummary> {
    let plan = study.plan.build().context("cannot build the plan")?;
    let staged = stage_out_dir(out, force, inputs)?;
    let mut summary = synthesize(study, &plan, staged.path(), formats)?;
    provenance(inputs)?
        .with_seed(study.synth.seed)
        .write_into(staged.path())?;
    summary.files = summary.files.iter().map(|f| staged.shown_str(f)).collect();
    staged.commit()?;
    Ok(summary)
}

/// Simulate every pin of the plan and write recordings and the ground truth into `out`.
pub fn synthesize(
    study: &Study,
    plan: &Plan,
    out: &Path,
    formats: &[RecordingFormat],
) -> Result<SynthSummary> {
    let mut files = Vec::new();
    let mut samples = 0;
    for pin in 1..=plan.pins.len() as u32 {
        greybox_core::interrupt::check()?;
        let rec = study.synth.simulate_pin(plan, &study.contact, pin)?;
        samples += rec.len();
        for f in formats {
            let p = out.join(format!("pin{pin:02}.{}", f.extension()));
            match f {
                RecordingFormat::Csv => write_csv_recording(&p, &rec)?,
                RecordingFormat::Tdms => write_tdms_recording(
                    &p,
                    &rec,
                    study
                        .recording
                        .reader
                        .tdms_group
                        .as_deref()
                        .unwrap_or(greybox_recording::DEFAULT_TDMS_GROUP),
                )?,
                RecordingFormat::Spreadsheet => {
                    anyhow::bail!("synth writes CSV or TDMS recordings, not spreadsheets")
                }
            }
            files.push(p.display().to_string());
        }
    }
    let truth = study.synth.ground_truth(plan, &study.contact)?;
    let p = out.join("ground_truth.csv");
    write_ground_truth(&p, &truth)?;
    files.push(p.display().to_string());
    let mu = truth.iter().map(|t| t.cof_true);
    Ok(SynthSummary {
        pins: plan.pins.len(),
        samples,
        seed: study.synth.seed,
        cof_true_min: mu.clone().fold(f64::INFINITY, f64::min),
        cof_true_max: mu.fold(f64::NEG_INFINITY, f64::max),
        files,
    })
}
