//! `greybox characterize`: FRF of the rig from impact-hammer recordings, and the article's
//! dynamics check against the campaign's spindle excitation.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::characterize::{
    characterize, recording_with_load, CharacterizeOptions, ImpactChannels,
};
use greybox_pipeline::settings::plan::PlanSettings;
use greybox_tribo::frf::ImpactConfig;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Hammer recording PATH[@LOAD_N] (CSV or TDMS; repeatable). Recordings with the same load
    /// are averaged together; different loads are compared.
    #[arg(long = "recording", required = true)]
    pub recordings: Vec<String>,
    /// Hammer force channel (N).
    #[arg(long, default_value = "hammer_N")]
    pub hammer: String,
    /// Response channel (accelerometer or dynamometer output).
    #[arg(long, default_value = "response")]
    pub response: String,
    /// CSV time column (seconds); without it, --sample-rate-hz.
    #[arg(long, default_value = "time_s")]
    pub time: String,
    /// Sample rate when the CSV has no time column, Hz.
    #[arg(long = "sample-rate-hz")]
    pub sample_rate_hz: Option<f64>,
    /// TDMS group of the channels.
    #[arg(long, default_value = "Hammer")]
    pub tdms_group: String,
    /// Record length per impact, s.
    #[arg(long = "block-s")]
    pub block_s: Option<f64>,
    /// Exponential window value at the record end (1 = none).
    #[arg(long)]
    pub exponential_end: Option<f64>,
    /// Harmonics of the spindle rotation frequency in the excitation check.
    #[arg(long, default_value_t = greybox_pipeline::characterize::Harmonics::of(3))]
    pub harmonics: greybox_pipeline::characterize::Harmonics,
    /// The campaign plan for the excitation check (study TOML and/or plan flags).
    #[command(flatten)]
    pub plan: PlanSettings,
    /// Output directory: frf_<load>.csv, plots, report.json.
    #[arg(long, default_value = "characterize-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// The library's options for these flags.
    pub fn options(&self) -> Result<CharacterizeOptions> {
        let mut impact = ImpactConfig::default();
        if let Some(b) = self.block_s {
            impact.block_s = b;
        }
        if let Some(e) = self.exponential_end {
            impact.exponential_end = e;
        }
        Ok(CharacterizeOptions {
            recordings: self
                .recordings
                .iter()
                .map(|s| recording_with_load(s))
                .collect::<Result<_>>()?,
            channels: ImpactChannels {
                hammer: self.hammer.clone(),
                response: self.response.clone(),
                time: self.time.clone(),
                sample_rate_hz: self.sample_rate_hz,
                tdms_group: self.tdms_group.clone(),
            },
            impact,
            harmonics: self.harmonics,
            plan: self.plan.study().ok().and_then(|s| s.plan.build().ok()),
            study: self.plan.study.clone(),
            out: self.out.clone(),
            force: self.force,
        })
    }
}

pub fn run(a: Args) -> Result<()> {
    let r = characterize(&a.options()?)?;
    if a.json {
        return print_json(&r);
    }
    print!("{}", greybox_report::text::characterize(&r));
    println!("wrote {}", r.files.join(", "));
    Ok(())
}
