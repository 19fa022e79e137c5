//! The settings of the virtual tribometer (`synth`): the study and its `[plan]` overrides,
//! the output, the formats and the `[synth]` overrides, one type for the command line and
//! Python. Without a study the bundled example study (the article's campaign, rig and
//! material) is simulated: a virtual rig needs every one of its parameters, and its
//! recordings say what they are (ground_truth.csv, the study in the provenance).
//!
//! ```
//! use greybox_pipeline::settings::{from_json, synth::{SynthSettings, SynthFormats}};
//! let s: SynthSettings = from_json("synth", r#"{"out": "o", "format": "both", "seed": 7,
//!     "velocity_count": 2}"#)?;
//! assert_eq!(s.format, SynthFormats::Both);
//! let study = s.study()?;
//! assert_eq!((study.synth.seed, study.plan.velocity_count.get()), (7, 2));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::settings::plan::PlanSettings;
use crate::study::Study;
use crate::synth::SynthSummary;
use anyhow::Result;
use greybox_core::setting::refused;
use greybox_recording::readers::RecordingFormat;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The output directory when no `out` is given.
pub const DEFAULT_SYNTH_DIR: &str = "synth-out";

/// Which recording formats are written.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SynthFormats {
    #[default]
    Csv,
    Tdms,
    Both,
}
greybox_core::choice!(SynthFormats, "format", [Csv => "csv", Tdms => "tdms", Both => "both"]);

impl SynthFormats {
    /// The formats written.
    pub fn formats(self) -> Vec<RecordingFormat> {
        match self {
            SynthFormats::Csv => vec![RecordingFormat::Csv],
            SynthFormats::Tdms => vec![RecordingFormat::Tdms],
            SynthFormats::Both => vec![RecordingFormat::Csv, RecordingFormat::Tdms],
        }
    }
}

/// One virtual campaign as a user states it; `None` keeps the study's value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(default)]
pub struct SynthSettings {
    #[serde(flatten)]
    #[cfg_attr(feature = "cli", command(flatten))]
    pub plan: PlanSettings,
    /// Output directory: pinNN.csv / pinNN.tdms and ground_truth.csv.
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_SYNTH_DIR))]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[cfg_attr(feature = "cli", arg(long))]
    pub force: bool,
    /// Recording format(s): csv, tdms or both.
    #[cfg_attr(feature = "cli", arg(long, default_value = "csv",
        value_parser = greybox_core::choice::clap_parsers::choice::<SynthFormats>()))]
    pub format: SynthFormats,
    /// Random seed (overrides the study's `[synth] seed`).
    #[cfg_attr(feature = "cli", arg(long))]
    pub seed: Option<u64>,
    /// Multiply noise, drift and spikes (overrides `[synth] disturbance_scale`).
    #[cfg_attr(feature = "cli", arg(long))]
    pub disturbance_scale: Option<f64>,
}

impl Default for SynthSettings {
    fn default() -> Self {
        SynthSettings {
            plan: PlanSettings::default(),
            out: PathBuf::from(DEFAULT_SYNTH_DIR),
            force: false,
            format: SynthFormats::default(),
            seed: None,
            disturbance_scale: None,
        }
    }
}

impl SynthSettings {
    /// The study (or the bundled example study) with every override here.
    pub fn study(&self) -> Result<Study> {
        let example = Study::parse(crate::study::DEMO_STUDY, "the bundled example study")?;
        let mut study = self.plan.study_over(example)?;
        if let Some(s) = self.seed {
            study.synth.seed = s;
        }
        if let Some(k) = self.disturbance_scale {
            if !(k.is_finite() && k >= 0.0) {
                let why = format!("must be a finite number ≥ 0, got {k}");
                return Err(refused("synth", "disturbance_scale", why).into());
            }
            study.synth.disturbance_scale = k;
        }
        Ok(study)
    }

    /// Simulate the campaign into `out`.
    pub fn run(&self) -> Result<SynthSummary> {
        let study = self.study()?;
        crate::synth::synth(
            &study,
            &self.format.formats(),
            &self.out,
            self.force,
            &self.plan.inputs(),
        )
    }
}
