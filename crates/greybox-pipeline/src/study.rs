//! The study TOML file: one file drives plan, synth and identify.

use anyhow::{Context, Result};
use greybox_contact::PinContact;
use greybox_learn::protocol::FitConfig;
use greybox_recording::ChannelMap;
use greybox_tribo::config::IdentifyConfig;
use greybox_tribo::plan::PlanSpec;
use greybox_tribo::synth::SynthConfig;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The bundled example study (drives `greybox demo`).
pub const DEMO_STUDY: &str = include_str!("../../../examples/demo-study.toml");

/// A whole study. Every section is optional and takes documented defaults.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Study {
    pub plan: PlanSpec,
    pub contact: PinContact,
    pub synth: SynthConfig,
    pub identify: IdentifyConfig,
    pub recording: ChannelMap,
    pub fit: FitConfig,
    /// The keys its file states in `[plan]` (none without a file or a `[plan]`): what the
    /// article's defaults do not fill in. Read with the study, from the same text.
    #[serde(skip)]
    pub declared_plan_keys: Vec<String>,
}

impl Study {
    /// Parse a study TOML; `source` names it in errors. Every section is optional; unknown
    /// keys are errors that name the line.
    ///
    /// ```
    /// use greybox_pipeline::Study;
    /// let s = Study::parse("[plan]\nvelocity_count = 5\ntrack_radius_mm = 80.0\n", "s.toml").unwrap();
    /// assert_eq!((s.plan.velocity_count.get(), s.plan.normal_force_count.get()), (5, 10));
    /// let e = Study::parse("[plan]\nvelocity_cnt = 5\n", "s.toml").unwrap_err();
    /// assert!(format!("{e:#}").contains("velocity_cnt"));
    /// ```
    pub fn parse(text: &str, source: &str) -> Result<Self> {
        let (mut study, raw): (Study, toml::Value) =
            crate::config_toml::parse_with_raw(text, source, "study file")?;
        study.declared_plan_keys = raw
            .get("plan")
            .and_then(toml::Value::as_table)
            .map(|t| t.keys().cloned().collect())
            .unwrap_or_default();
        study
            .contact
            .validate()
            .with_context(|| format!("{source}: [contact]"))?;
        Ok(study)
    }
    pub fn load(path: &Path) -> Result<Self> {
        let text = crate::config_toml::read_text(path, "study file")?;
        Self::parse(&text, &path.display().to_string())
    }
    /// The study from `--study`, or all defaults.
    pub fn load_or_default(path: Option<&Path>) -> Result<Self> {
        match path {
            Some(p) => Self::load(p),
            None => Ok(Study::default()),
        }
    }
    /// The study as TOML.
    pub fn to_toml(&self) -> Result<String> {
        Ok(toml::to_string_pretty(self)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn demo_study_parses_and_round_trips() {
        let s = Study::parse(DEMO_STUDY, "demo").unwrap();
        assert_eq!(s.plan.track_radius_mm, Some(100.0));
        let back = Study::parse(&s.to_toml().unwrap(), "round trip").unwrap();
        assert_eq!(back.plan, s.plan);
        assert_eq!(back.synth, s.synth);
    }
    #[test]
    fn unknown_keys_are_rejected_with_position() {
        let e = Study::parse("[plan]\ntrack_radius_m = 0.1\n", "s.toml").unwrap_err();
        let msg = format!("{e:#}");
        assert!(
            msg.contains("s.toml") && msg.contains("track_radius_m") && msg.contains("line 2"),
            "{msg}"
        );
    }
}
