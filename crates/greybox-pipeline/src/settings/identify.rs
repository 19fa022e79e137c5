//! The settings of one identification run that override a study's `[recording]`,
//! `[identify]` and `[contact]` sections: one type, applied the same way by the command
//! line (its flags) and Python (its keyword arguments), with errors that name the setting.
//!
//! ```
//! use greybox_pipeline::settings::identify::IdentifySettings;
//! use greybox_pipeline::Study;
//! let mut study = Study::default();
//! let s = IdentifySettings::from_json(r#"{"steady": "last:50%", "convention": "article-eq7",
//!     "map": ["radius=Radius:mm", "normal=#2:N"], "constant_normal_force_N": 60,
//!     "columns": ["t_s", "Fn_N"]}"#)?;
//! s.apply(&mut study)?;
//! assert_eq!(study.recording.constant_normal_n, Some(60.0));
//! assert_eq!(study.recording.columns, ["t_s", "Fn_N"]);
//! assert_eq!(study.recording.normal.as_ref().unwrap().name, "#2");
//! assert_eq!(study.contact.convention.to_string(), "article-eq7");
//! let e = IdentifySettings { sample_rate_hz: Some(-1.0), ..Default::default() }
//!     .apply(&mut study).unwrap_err();
//! assert!(e.to_string().contains("identify.sample_rate_hz"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::identify::{Expectation, IdentifyOptions};
use crate::settings::plan::PlanSettings;
use crate::study::Study;
use anyhow::{bail, Context, Result};
use greybox_core::choice::Choice;
use greybox_core::dataset::PressureConvention;
use greybox_tribo::campaign::read_expected_steps;
use greybox_tribo::campaign::Segmentation;
use greybox_tribo::identify::Alignment;
use greybox_tribo::identify_config::{SteadyRule, TestMode};
use greybox_tribo::readers::RecordingFormat;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// A 1-based line number of a recording's head (0: no header line).
pub type HeaderLine = greybox_core::count::Count<0, 1_000_000>;
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
    pub header_line: Option<HeaderLine>,
    /// Sample rate of files without a time column, Hz.
    pub sample_rate_hz: Option<f64>,
    /// Names for the columns in file order (units in the names: `t_s`, `Fn_N`), for logs
    /// without a header line; empty keeps the study's (default: the file's own names).
    pub columns: Vec<String>,
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
        rec.header_line = self.header_line.map(HeaderLine::as_u64).or(rec.header_line);
        rec.sample_rate_hz = rate.or(rec.sample_rate_hz);
        rec.sheet = self.sheet.clone().or(rec.sheet.take());
        if !self.columns.is_empty() {
            rec.columns = self.columns.clone();
        }
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

/// What one identification reads and writes, and what it matches the segments to.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct IdentifyInputs {
    /// Recording files (CSV/TXT, XLSX/XLS/ODS, TDMS) or directories: a file per step, per
    /// pin or for the whole campaign. A directory gives its pinNN files when the plan's pins
    /// are all there, else every recording file in natural order.
    /// Required, except by `identify --rig list`.
    #[cfg_attr(feature = "cli", arg(long, num_args = 1.., required_unless_present = "rig"))]
    pub recordings: Vec<PathBuf>,
    /// Which files to pick from a directory: csv, tdms or spreadsheet (default: every
    /// supported format).
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<RecordingFormat>()))]
    pub format: Option<RecordingFormat>,
    /// Expected steps without timing: CSV with pin, normal_force_N,
    /// sliding_velocity_m_per_min [, step], in the order they were run.
    #[cfg_attr(feature = "cli", arg(long = "plan-steps"))]
    pub plan_steps: Option<PathBuf>,
    /// Ignore the study's plan: loads and velocities from the recordings.
    #[cfg_attr(feature = "cli", arg(long = "no-plan"))]
    pub no_plan: bool,
    /// Track radius per segment for rpm speed channels, mm (comma-separated: one per segment
    /// of each file, or of the whole campaign).
    #[cfg_attr(feature = "cli", arg(long = "track-radii-mm", value_delimiter = ','))]
    pub track_radii_mm: Vec<f64>,
    /// Output dataset CSV.
    #[cfg_attr(feature = "cli", arg(long, default_value = "dataset.csv"))]
    pub out: PathBuf,
    /// Ground truth CSV from `greybox synth`: report the identification error against it.
    #[cfg_attr(feature = "cli", arg(long))]
    pub truth: Option<PathBuf>,
    /// Print per file the mapped columns, sampling rate and every segment (start, end, load,
    /// speed, steady window, μ, flags), and write an SVG per recording with the steady
    /// windows shaded into the inspect directory.
    #[cfg_attr(feature = "cli", arg(long))]
    pub inspect: bool,
    /// Where inspect writes its SVGs (default: DATASET_inspect/ beside the dataset).
    #[cfg_attr(feature = "cli", arg(long = "inspect-dir"))]
    pub inspect_dir: Option<PathBuf>,
}

impl IdentifyInputs {
    /// The identification's options: the steps file, else the plan where one is given
    /// (`plan`'s study or ranges, unless `no_plan`), else the loads and speeds measured;
    /// without a plan, the plan settings' track radius serves the rpm channels.
    pub fn options(&self, study: &Study, plan: &PlanSettings) -> Result<IdentifyOptions> {
        let expect = if let Some(path) = &self.plan_steps {
            Expectation::Steps(read_expected_steps(path)?)
        } else if !self.no_plan && plan.gives_plan()? {
            Expectation::Plan(study.plan.build().context("cannot build the plan")?)
        } else {
            Expectation::None
        };
        let mut radii = self.track_radii_mm.clone();
        if radii.is_empty() && !matches!(expect, Expectation::Plan(_)) {
            radii.extend(plan.track_radius_mm);
        }
        let side_inputs = [
            ("study", plan.study.as_ref()),
            ("plan_steps", self.plan_steps.as_ref()),
            ("truth", self.truth.as_ref()),
        ]
        .into_iter()
        .filter_map(|(f, p)| p.map(|p| (f.to_string(), p.clone())))
        .collect();
        let inspect_dir = self.inspect.then(|| {
            self.inspect_dir.clone().unwrap_or_else(|| {
                let stem = self
                    .out
                    .file_stem()
                    .map(|s| s.to_string_lossy().to_string());
                let stem = stem.unwrap_or_else(|| "dataset".into());
                self.out.with_file_name(format!("{stem}_inspect"))
            })
        });
        Ok(IdentifyOptions {
            recordings: self.recordings.clone(),
            format: self.format,
            expect,
            track_radii_mm: radii,
            dataset: self.out.clone(),
            inspect_dir,
            truth: self.truth.clone(),
            side_inputs,
        })
    }
}
