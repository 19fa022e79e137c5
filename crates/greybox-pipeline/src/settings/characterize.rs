//! The settings of a rig characterisation (`greybox characterize`): the hammer recordings,
//! their channels, the record and window, and the campaign plan whose spindle excitation the
//! rig's resonances are checked against — one type, one default per field (the library's
//! constants), checked once.
//!
//! ```
//! use greybox_pipeline::settings::{characterize::CharacterizeSettings, from_json};
//! let s: CharacterizeSettings = from_json("characterize",
//!     r#"{"recordings": ["a.csv@500", "b.csv"], "block_s": 0.5}"#)?;
//! let o = s.options()?;
//! assert_eq!((o.recordings[0].1, o.recordings[1].1), (Some(500.0), None));
//! assert_eq!((o.channels.hammer.as_str(), o.impact.block_s), ("hammer_N", 0.5));
//! assert!(o.plan.is_none(), "no plan stated: no excitation check");
//! let e = from_json::<CharacterizeSettings>("characterize", r#"{"recordings": ["a.csv@5 kN"]}"#)
//!     .unwrap_err();
//! assert!(format!("{e:#}").contains("'5 kN' is not a load in N"), "{e:#}");
//! # Ok::<(), anyhow::Error>(())
//! ```

use super::plan::PlanSettings;
use crate::characterize::{
    CharacterizeOptions, ExcitationPlan, Harmonics, ImpactChannels, DEFAULT_CHARACTERIZE_DIR,
    DEFAULT_HAMMER_CHANNEL, DEFAULT_HARMONICS, DEFAULT_RESPONSE_CHANNEL, DEFAULT_TDMS_GROUP,
    DEFAULT_TIME_COLUMN,
};
use anyhow::Result;
use greybox_core::setting::positive_if_given;
use greybox_tribo::frf::ImpactConfig;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// One characterisation as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(default)] // unknown keys: refused by `settings::from_json` (serde cannot with `flatten`)
pub struct CharacterizeSettings {
    /// Hammer recording PATH[@LOAD_N] (CSV or TDMS; repeatable). Recordings with the same load
    /// are averaged together; different loads are compared.
    #[cfg_attr(feature = "cli", arg(long = "recording", required = true))]
    pub recordings: Vec<RecordingAtLoad>,
    /// Hammer force channel (N).
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_HAMMER_CHANNEL))]
    pub hammer: String,
    /// Response channel (accelerometer or dynamometer output).
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_RESPONSE_CHANNEL))]
    pub response: String,
    /// CSV time column (seconds); without it, --sample-rate-hz.
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_TIME_COLUMN))]
    pub time: String,
    /// Sample rate when the CSV has no time column (or the TDMS channel no wf_increment), Hz.
    #[cfg_attr(feature = "cli", arg(long = "sample-rate-hz"))]
    pub sample_rate_hz: Option<f64>,
    /// TDMS group of the channels.
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_TDMS_GROUP))]
    pub tdms_group: String,
    /// Record length per impact, s [default: 1].
    #[cfg_attr(feature = "cli", arg(long = "block-s"))]
    pub block_s: Option<f64>,
    /// Exponential window value at the record end (1 = none) [default: 0.01].
    #[cfg_attr(feature = "cli", arg(long))]
    pub exponential_end: Option<f64>,
    /// Harmonics of the spindle rotation frequency in the excitation check.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = Harmonics::of(DEFAULT_HARMONICS)))]
    pub harmonics: Harmonics,
    /// The campaign plan for the excitation check (a study TOML and/or plan flags; none
    /// stated: no check, and the report says so).
    #[serde(flatten)]
    #[cfg_attr(feature = "cli", command(flatten))]
    pub plan: PlanSettings,
    /// Output directory: frf_<load>.csv, plots, report.json.
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_CHARACTERIZE_DIR))]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[cfg_attr(feature = "cli", arg(long))]
    pub force: bool,
}

impl Default for CharacterizeSettings {
    fn default() -> Self {
        CharacterizeSettings {
            recordings: Vec::new(),
            hammer: DEFAULT_HAMMER_CHANNEL.into(),
            response: DEFAULT_RESPONSE_CHANNEL.into(),
            time: DEFAULT_TIME_COLUMN.into(),
            sample_rate_hz: None,
            tdms_group: DEFAULT_TDMS_GROUP.into(),
            block_s: None,
            exponential_end: None,
            harmonics: Harmonics::of(DEFAULT_HARMONICS),
            plan: PlanSettings::default(),
            out: DEFAULT_CHARACTERIZE_DIR.into(),
            force: false,
        }
    }
}

impl CharacterizeSettings {
    /// The characterisation's options: the record and window over the library's, and the
    /// plan where any of it is stated (its errors are the user's to see, never a silent "no
    /// check"; a track radius alone checks against the article's velocities, and says so).
    pub fn options(&self) -> Result<CharacterizeOptions> {
        if self.recordings.is_empty() {
            let why = "give at least one hammer recording";
            return Err(greybox_core::setting::refused("characterize", "recordings", why).into());
        }
        let given = |field: &str, value| positive_if_given("characterize", field, value);
        let mut impact = ImpactConfig::default();
        if let Some(b) = given("block_s", self.block_s)? {
            impact.block_s = b;
        }
        if let Some(e) = given("exponential_end", self.exponential_end)? {
            impact.exponential_end = e;
        }
        let sample_rate_hz = given("sample_rate_hz", self.sample_rate_hz)?;
        let study = self.plan.study()?;
        let stated = self.plan.stated_in(&study);
        let plan = match stated.any() {
            true => Some(ExcitationPlan {
                plan: study.plan.build()?,
                velocities_stated: stated.velocities,
            }),
            false => None,
        };
        Ok(CharacterizeOptions {
            recordings: self
                .recordings
                .iter()
                .map(|r| (r.path.clone(), r.load_n))
                .collect(),
            channels: ImpactChannels {
                hammer: self.hammer.clone(),
                response: self.response.clone(),
                time: self.time.clone(),
                sample_rate_hz,
                tdms_group: self.tdms_group.clone(),
            },
            impact,
            harmonics: self.harmonics,
            plan,
            study: self.plan.study.clone(),
            out: self.out.clone(),
            force: self.force,
        })
    }
}

/// A hammer recording and the normal load it was taken at, written `PATH[@LOAD_N]`.
#[derive(Debug, Clone, PartialEq)]
pub struct RecordingAtLoad {
    pub path: PathBuf,
    /// Normal load, N (none: one group of its own).
    pub load_n: Option<f64>,
}

impl std::str::FromStr for RecordingAtLoad {
    type Err = String;
    fn from_str(spec: &str) -> Result<Self, String> {
        let (path, load_n) = match spec.rsplit_once('@') {
            Some((p, load)) => match load.trim().parse::<f64>() {
                Ok(f) if f.is_finite() && f >= 0.0 => (p, Some(f)),
                _ => return Err(format!("'{spec}': '{load}' is not a load in N")),
            },
            None => (spec, None),
        };
        Ok(RecordingAtLoad {
            path: PathBuf::from(path),
            load_n,
        })
    }
}

impl std::fmt::Display for RecordingAtLoad {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.load_n {
            Some(load) => write!(f, "{}@{load}", self.path.display()),
            None => write!(f, "{}", self.path.display()),
        }
    }
}

greybox_core::text_serde!(RecordingAtLoad);
