//! `greybox synth`.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::settings::plan::PlanSettings;
use greybox_pipeline::synth::synth;
use greybox_tribo::readers::RecordingFormat;
use std::path::PathBuf;

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
    pub plan: PlanSettings,
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

pub fn run(args: Args) -> Result<()> {
    let mut study = args.plan.study()?;
    if let Some(s) = args.seed {
        study.synth.seed = s;
    }
    if let Some(k) = args.disturbance_scale {
        study.synth.disturbance_scale = k;
    }
    let summary = synth(
        &study,
        &args.format.formats(),
        &args.out,
        args.force,
        &args.plan.inputs(),
    )?;
    if args.json {
        return print_json(&summary);
    }
    print!("{}", greybox_pipeline::text::synth(&summary));
    println!(
        "  wrote {} files to {}",
        summary.files.len(),
        args.out.display()
    );
    Ok(())
}
