//! `greybox synth`.

use crate::cmd_plan::{study_input, PlanFlags};
use crate::output::{print_json, stage_out_dir};
use crate::study::Study;
use anyhow::{Context, Result};
use greybox_tribo::csv_recording::write_csv_recording;
use greybox_tribo::plan::Plan;
use greybox_tribo::readers::RecordingFormat;
use greybox_tribo::synth::write_ground_truth;
use greybox_tribo::tdms::write_tdms_recording;
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutFormat {
    Csv,
    Tdms,
    Both,
}

impl OutFormat {
    pub fn formats(self) -> Vec<RecordingFormat> {
        match self {
            OutFormat::Csv => vec![RecordingFormat::Csv],
            OutFormat::Tdms => vec![RecordingFormat::Tdms],
            OutFormat::Both => vec![RecordingFormat::Csv, RecordingFormat::Tdms],
        }
    }
}

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub plan: PlanFlags,
    /// Output directory: pinNN.csv / pinNN.tdms and ground_truth.csv.
    #[arg(long, default_value = "synth-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    /// Recording format(s).
    #[arg(long, value_enum, default_value_t = OutFormat::Csv)]
    pub format: OutFormat,
    /// Random seed (overrides [synth] seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Multiply noise, drift and spikes (overrides [synth] disturbance_scale).
    #[arg(long)]
    pub disturbance_scale: Option<f64>,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
pub struct SynthSummary {
    pub pins: usize,
    pub samples: usize,
    pub seed: u64,
    pub cof_true_min: f64,
    pub cof_true_max: f64,
    pub files: Vec<String>,
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
                        .tdms_group
                        .as_deref()
                        .unwrap_or(greybox_tribo::recording::DEFAULT_TDMS_GROUP),
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

pub fn print_summary(s: &SynthSummary) {
    println!(
        "synth: {} pins, {} samples (seed {}), true COF {:.3}..{:.3}",
        s.pins, s.samples, s.seed, s.cof_true_min, s.cof_true_max
    );
}

pub fn run(args: Args) -> Result<()> {
    let mut study = args.plan.study()?;
    if let Some(s) = args.seed {
        study.synth.seed = s;
    }
    if let Some(k) = args.disturbance_scale {
        study.synth.disturbance_scale = k;
    }
    let plan = study.plan.build().context("cannot build the plan")?;
    let staged = stage_out_dir(&args.out, args.force, &study_input(&args.plan))?;
    let mut summary = synthesize(&study, &plan, staged.path(), &args.format.formats())?;
    crate::output::provenance(&study_input(&args.plan))?
        .with_seed(study.synth.seed)
        .write_into(staged.path())?;
    summary.files = summary.files.iter().map(|f| staged.shown_str(f)).collect();
    staged.commit()?;
    if args.json {
        return print_json(&summary);
    }
    print_summary(&summary);
    println!(
        "  wrote {} files to {}",
        summary.files.len(),
        args.out.display()
    );
    Ok(())
}
