//! The settings of one identification run that override a study's `[recording]`,
//! `[identify]` and `[contact]` sections: one type, applied the same way by the command
//! line (its flags) and Python (its keyword arguments), with errors that name the setting.
//!
//! ```
//! use greybox_pipeline::identify_settings::IdentifySettings;
//! use greybox_pipeline::Study;
//! let mut study = Study::default();
//! let s = IdentifySettings::from_json(r#"{"steady": "last:50%", "convention": "article-eq7",
//!     "map": ["radius=Radius:mm"], "constant_normal_force_N": 60}"#)?;
//! s.apply(&mut study)?;
//! assert_eq!(study.recording.constant_normal_n, Some(60.0));
//! assert_eq!(study.contact.convention.to_string(), "article-eq7");
//! let e = IdentifySettings { sample_rate_hz: Some(-1.0), ..Default::default() }
//!     .apply(&mut study).unwrap_err();
//! assert!(e.to_string().contains("identify.sample_rate_hz"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::study::Study;
use anyhow::{bail, Context, Result};
use greybox_core::choice::Choice;
use greybox_core::dataset::PressureConvention;
use greybox_tribo::campaign::Segmentation;
use greybox_tribo::identify::Alignment;
use greybox_tribo::identify_config::{SteadyRule, TestMode};
use serde::{Deserialize, Serialize};

/// Overrides of a study for one identification; `None` (or empty) keeps the study's value.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[allow(non_snake_case)]
pub struct IdentifySettings {
    /// Channel mappings `ROLE=NAME[:UNIT[:SCALE]]` (roles: time, normal, tangential, radial,
    /// trigger, step, speed, radius, cof, position); an empty name ignores a role.
    pub map: Vec<String>,
    /// Rig profile (see `greybox_tribo::profiles`).
    pub rig: Option<String>,
    /// Normal load of rigs that do not record it, N.
    pub constant_normal_force_N: Option<f64>,
    /// Sliding velocity of rigs that do not record their speed, m/s.
    pub constant_sliding_velocity_m_per_s: Option<f64>,
    pub tdms_group: Option<String>,
    /// 1-based header line of text files.
    pub header_line: Option<u64>,
    /// Sample rate of files without a time column, Hz.
    pub sample_rate_hz: Option<f64>,
    /// Spreadsheet sheet.
    pub sheet: Option<String>,
    /// How the plan is aligned with each recording (sets plan-timing segmentation).
    pub align: Option<String>,
    /// How the steps are found: auto, plan-timing, step-column, speed, signals.
    pub segment: Option<String>,
    /// Steady-state rule: `auto`, `last:P%`, `from:Ts`.
    pub steady: Option<String>,
    /// auto, continuous, stepped or reciprocating.
    pub test_mode: Option<String>,
    /// Time dropped after the spindle ramp, s.
    pub settle_time_s: Option<f64>,
    /// Pressure convention of the dataset: textbook-max, textbook-mean, article-eq7.
    pub convention: Option<String>,
}

/// A choice named `field` in errors.
fn choice<T: Choice>(text: &Option<String>) -> Result<Option<T>> {
    text.as_deref()
        .map(T::parse_choice)
        .transpose()
        .map_err(|e| anyhow::anyhow!("identify.{e}"))
}

/// A positive, finite number, or an error naming the setting.
fn positive(v: Option<f64>, field: &str) -> Result<Option<f64>> {
    match v {
        Some(x) if !(x.is_finite() && x > 0.0) => {
            bail!("identify.{field}: must be a positive number, got {x}")
        }
        v => Ok(v),
    }
}

impl IdentifySettings {
    /// Settings from JSON (Python's keyword arguments); unknown keys are errors.
    pub fn from_json(text: &str) -> Result<Self> {
        serde_json::from_str(text).context("identify settings")
    }

    /// Override `study` with every setting given, after checking all of them.
    pub fn apply(&self, study: &mut Study) -> Result<()> {
        let align = choice::<Alignment>(&self.align)?;
        let segment = choice::<Segmentation>(&self.segment)?;
        let convention = choice::<PressureConvention>(&self.convention)?;
        let test_mode = match self.test_mode.as_deref() {
            Some("auto") => Some(None),
            _ => choice::<TestMode>(&self.test_mode)?.map(Some),
        };
        let steady = self
            .steady
            .as_deref()
            .map(|s| s.parse::<SteadyRule>())
            .transpose()
            .map_err(|e| anyhow::anyhow!("identify.steady: {e}"))?;
        let force = positive(self.constant_normal_force_N, "constant_normal_force_N")?;
        let speed = positive(
            self.constant_sliding_velocity_m_per_s,
            "constant_sliding_velocity_m_per_s",
        )?;
        let rate = positive(self.sample_rate_hz, "sample_rate_hz")?;
        if let Some(r) = &self.rig {
            greybox_tribo::profiles::by_name(r).context("identify.rig")?;
        }
        let rec = &mut study.recording;
        for m in &self.map {
            rec.apply_override(m).context("identify.map")?;
        }
        rec.rig = self.rig.clone().or(rec.rig.take());
        rec.constant_normal_n = force.or(rec.constant_normal_n);
        rec.constant_sliding_m_s = speed.or(rec.constant_sliding_m_s);
        rec.tdms_group = self.tdms_group.clone().or(rec.tdms_group.take());
        rec.header_line = self.header_line.or(rec.header_line);
        rec.sample_rate_hz = rate.or(rec.sample_rate_hz);
        rec.sheet = self.sheet.clone().or(rec.sheet.take());
        let id = &mut study.identify;
        if let Some(a) = align {
            id.align = a;
            id.segmentation = Segmentation::PlanTiming;
        }
        id.segmentation = segment.unwrap_or(id.segmentation);
        if let Some(s) = steady {
            id.steady = s;
        }
        if let Some(m) = test_mode {
            id.mode = m;
        }
        id.settle_time_s = self.settle_time_s.unwrap_or(id.settle_time_s);
        study.contact.convention = convention.unwrap_or(study.contact.convention);
        Ok(())
    }
}
