//! The settings of one identification: one type, [`IdentifySettings`], parsed from the
//! command line (clap, feature `cli`) and from Python's keyword arguments (the same JSON by
//! the same field names), with one default per field. It holds the study and its `[plan]`
//! overrides ([`PlanSettings`], flattened), what is read and written, and the overrides of
//! the study's `[recording]`, `[identify]` and `[contact]` sections; errors name the field.
//!
//! Without a study nothing is assumed: the contact takes the library's default
//! convention (textbook-max) and loads and speeds come from the recordings. A study whose
//! `[plan]` states loads or velocities (or a load or velocity range given here) is matched to
//! the recordings unless `no_plan` is set; a `[plan]` with only the track radius states no
//! campaign, and its radius turns rpm channels into sliding speeds.
//!
//! ```
//! use greybox_pipeline::settings::identify::IdentifySettings;
//! let s: IdentifySettings = greybox_pipeline::settings::from_json("identify",
//!     r#"{"recordings": ["r.csv"], "steady": "last:50%", "convention": "article-eq7",
//!     "map": ["radius=Radius:mm", "normal=#2:N"], "constant_normal_force_N": 60,
//!     "columns": ["t_s", "Fn_N"], "normal_force_count": 3}"#)?;
//! let study = s.study()?;
//! assert_eq!(study.recording.constant_normal_n, Some(60.0));
//! assert_eq!(study.recording.reader.columns, ["t_s", "Fn_N"]);
//! assert_eq!(study.recording.normal.as_ref().unwrap().name, "#2");
//! assert_eq!(study.contact.convention.to_string(), "article-eq7");
//! assert_eq!(study.plan.normal_force_count.get(), 3);
//! let e = IdentifySettings { sample_rate_hz: Some(-1.0), ..Default::default() }
//!     .study().unwrap_err();
//! assert!(e.to_string().contains("identify.sample_rate_hz"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::identify::{Expectation, IdentifyOptions};
use crate::settings::plan::PlanSettings;
use crate::study::Study;
use anyhow::{Context, Result};
use greybox_core::dataset::PressureConvention;
use greybox_core::setting::refused;
use greybox_core::setting::{SettingError, SettingPath};
use greybox_recording::readers::RecordingFormat;
use greybox_recording::TestMode;
use greybox_tribo::campaign::read_expected_steps;
use greybox_tribo::campaign::Segmentation;
use greybox_tribo::config::SteadyRule;
use greybox_tribo::config::TimeZero;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// A 1-based line number of a recording's head (0: no header line).
pub type HeaderLine = greybox_core::count::Count<0, 1_000_000>;

/// The dataset written when no `out` is given.
pub const DEFAULT_DATASET: &str = "dataset.csv";

/// How the rig ran its tests: `auto` (from the rig profile or the signals) or one mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TestModeSetting {
    #[default]
    Auto,
    Continuous,
    Stepped,
    Reciprocating,
}
greybox_core::choice!(TestModeSetting, "test_mode", [
    Auto => "auto", Continuous => "continuous", Stepped => "stepped",
    Reciprocating => "reciprocating",
]);

impl TestModeSetting {
    /// The study's `[identify] mode`: `None` detects it.
    pub fn mode(self) -> Option<TestMode> {
        match self {
            TestModeSetting::Auto => None,
            TestModeSetting::Continuous => Some(TestMode::Continuous),
            TestModeSetting::Stepped => Some(TestMode::Stepped),
            TestModeSetting::Reciprocating => Some(TestMode::Reciprocating),
        }
    }
}

#[cfg(feature = "cli")]
fn parse_steady(s: &str) -> std::result::Result<SteadyRule, String> {
    s.parse()
}

/// One identification as a user states it; `None` (or empty) keeps the study's value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(default)]
#[allow(non_snake_case)]
pub struct IdentifySettings {
    #[serde(flatten)]
    #[cfg_attr(feature = "cli", command(flatten))]
    pub plan: PlanSettings,
    /// Recording files (CSV/TXT, XLSX/XLS/ODS, TDMS) or directories: a file per step, per
    /// pin or for the whole campaign. A directory gives its pinNN files when the plan's pins
    /// are all there, else every recording file in natural order.
    #[cfg_attr(feature = "cli", arg(long, num_args = 1..))]
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
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_DATASET))]
    pub out: PathBuf,
    /// Ground truth CSV from `synth`: report the identification error against it.
    #[cfg_attr(feature = "cli", arg(long))]
    pub truth: Option<PathBuf>,
    /// Report per file the mapped columns, sampling rate and every segment (start, end,
    /// load, speed, steady window, μ, flags), and write an SVG per recording with the steady
    /// windows shaded into `inspect_dir`.
    #[cfg_attr(feature = "cli", arg(long))]
    pub inspect: bool,
    /// Where inspect writes its SVGs (default: DATASET_inspect/ beside the dataset).
    #[cfg_attr(feature = "cli", arg(long = "inspect-dir"))]
    pub inspect_dir: Option<PathBuf>,
    /// How the steps are found: auto (a step column, then a speed channel, then the plan's
    /// timing for greybox's own NC-program recordings, then the signals), plan-timing,
    /// step-column, speed, signals.
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<Segmentation>()))]
    pub segment: Option<Segmentation>,
    /// How the rig ran its tests (study `[identify] mode`). `reciprocating` (ASTM G133):
    /// strokes instead of plateaus, μ from the middle half of each stroke with the sign taken
    /// by direction, one row per test averaged over the steady cycles, the per-cycle μ in
    /// `<out>.cycles.csv`. `auto`: reciprocating where the rig profile says so or the
    /// signals show it (a reversing position, or a friction force that changes sign
    /// regularly). Default: the study's (auto).
    #[cfg_attr(feature = "cli", arg(long = "test-mode",
        value_parser = greybox_core::choice::clap_parsers::choice::<TestModeSetting>()))]
    pub test_mode: Option<TestModeSetting>,
    /// How to align the plan with each recording (sets plan-timing segmentation).
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<TimeZero>()))]
    pub align: Option<TimeZero>,
    /// Which part of each segment gives its steady value: `auto` (the final stationary
    /// stretch after run-in, ASTM G99/G133 practice; drift reported as a trend), `last:P%`
    /// (the last P % of the segment's sliding time) or `from:Ts` (from T seconds after the
    /// segment's start). Default: the study's (auto).
    #[cfg_attr(feature = "cli", arg(long, value_parser = parse_steady))]
    pub steady: Option<SteadyRule>,
    /// Time dropped after the spindle ramp, s.
    #[cfg_attr(feature = "cli", arg(long = "settle-s"))]
    pub settle_time_s: Option<f64>,
    /// Channel mappings `ROLE=NAME[:UNIT[:SCALE]]`. Roles: time, normal, tangential,
    /// radial, trigger, step, speed, radius, cof, position; an empty name (`speed=`) ignores
    /// a role. Unmapped roles are found by their usual names (Fz, Fx, Time, Step, Velocity,
    /// ...). NAME `#K` is column K of the file, counted from 1 (`normal=#3:N`), as in a log
    /// without header.
    #[cfg_attr(feature = "cli", arg(long = "map"))]
    pub map: Vec<String>,
    /// 1-based header line of text files (default: found below any preamble).
    #[cfg_attr(feature = "cli", arg(long = "header-line"))]
    pub header_line: Option<HeaderLine>,
    /// Sample rate of files without a time column, Hz: time = k / rate.
    #[cfg_attr(feature = "cli", arg(long = "sample-rate-hz"))]
    pub sample_rate_hz: Option<f64>,
    /// Names for the columns in file order, units in the names as in a header
    /// (`t_s,Fn_N,Ft_N`): for a log without a header line, whose columns are otherwise
    /// `#1`, `#2`, … (`normal=#2:N` maps by number), or to rename a file's columns.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub columns: Vec<String>,
    /// Rig profile of the files (`identify --list-rigs` prints them); default (`auto`):
    /// detected from each file's preamble and header when exactly one profile matches.
    #[cfg_attr(feature = "cli", arg(long, value_parser = clap::builder::PossibleValuesParser::new(greybox_recording::profiles::choices())))]
    pub rig: Option<String>,
    /// Normal load, N, for rigs that do not record it (dead-weight pin-on-disc rigs).
    #[cfg_attr(feature = "cli", arg(long = "constant-normal-force-N"))]
    pub constant_normal_force_N: Option<f64>,
    /// Sliding velocity, m/s, for rigs that do not record their speed (on the command line
    /// in m/min: `--constant-sliding-velocity-m-per-min`).
    #[cfg_attr(feature = "cli", arg(long = "constant-sliding-velocity-m-per-min", value_name = "M_PER_MIN",
        value_parser = greybox_core::units::clap_parsers::m_per_min_as_m_per_s))]
    pub constant_sliding_velocity_m_per_s: Option<f64>,
    /// Spreadsheet sheet to read (default: the first holding a table).
    #[cfg_attr(feature = "cli", arg(long))]
    pub sheet: Option<String>,
    /// TDMS group holding the channels.
    #[cfg_attr(feature = "cli", arg(long = "tdms-group"))]
    pub tdms_group: Option<String>,
    /// Pressure convention written to the dataset (overrides the study's `[contact]
    /// convention`; without a study: textbook-max).
    #[cfg_attr(feature = "cli", arg(long,
        value_parser = greybox_core::choice::clap_parsers::choice::<PressureConvention>()))]
    pub convention: Option<PressureConvention>,
}

impl Default for IdentifySettings {
    fn default() -> Self {
        IdentifySettings {
            plan: PlanSettings::default(),
            recordings: Vec::new(),
            format: None,
            plan_steps: None,
            no_plan: false,
            track_radii_mm: Vec::new(),
            out: PathBuf::from(DEFAULT_DATASET),
            truth: None,
            inspect: false,
            inspect_dir: None,
            segment: None,
            test_mode: None,
            align: None,
            steady: None,
            settle_time_s: None,
            map: Vec::new(),
            header_line: None,
            sample_rate_hz: None,
            columns: Vec::new(),
            rig: None,
            constant_normal_force_N: None,
            constant_sliding_velocity_m_per_s: None,
            sheet: None,
            tdms_group: None,
            convention: None,
        }
    }
}

/// `v` where absent or positive, else `identify.<field>` refused.
fn positive(v: Option<f64>, field: &str) -> Result<Option<f64>> {
    Ok(greybox_core::setting::positive_if_given(
        "identify", field, v,
    )?)
}

impl IdentifySettings {
    /// The study file (or none) with the plan overrides and every setting here applied.
    pub fn study(&self) -> Result<Study> {
        let mut study = self.plan.study()?;
        self.apply(&mut study)?;
        Ok(study)
    }

    /// The study and the identification's options: what [`crate::identify::identify_campaign`]
    /// runs.
    pub fn prepare(&self) -> Result<(Study, IdentifyOptions)> {
        if self.recordings.is_empty() {
            let why = "give at least one recording file or directory";
            return Err(refused("identify", "recordings", why).into());
        }
        let study = self.study()?;
        let options = self.options(&study)?;
        Ok((study, options))
    }

    /// Override `study` with every setting given, after checking all of them.
    fn apply(&self, study: &mut Study) -> Result<()> {
        let force = positive(self.constant_normal_force_N, "constant_normal_force_N")?;
        let speed = positive(
            self.constant_sliding_velocity_m_per_s,
            "constant_sliding_velocity_m_per_s",
        )?;
        let rate = positive(self.sample_rate_hz, "sample_rate_hz")?;
        if let Some(r) = &self.rig {
            greybox_recording::profiles::by_name(r)
                .map_err(|e| anyhow::Error::from(refused("identify", "rig", e.to_string())))?;
        }
        let rec = &mut study.recording;
        for (k, m) in self.map.iter().enumerate() {
            rec.apply_override(m).map_err(|e| {
                SettingError::new(SettingPath::new("identify", "map").at(k), e.to_string())
            })?;
        }
        rec.rig = self.rig.clone().or(rec.rig.take());
        rec.constant_normal_n = force.or(rec.constant_normal_n);
        rec.constant_sliding_m_s = speed.or(rec.constant_sliding_m_s);
        rec.reader.tdms_group = self.tdms_group.clone().or(rec.reader.tdms_group.take());
        rec.reader.header_line = self
            .header_line
            .map(HeaderLine::as_u64)
            .or(rec.reader.header_line);
        rec.sample_rate_hz = rate.or(rec.sample_rate_hz);
        rec.reader.sheet = self.sheet.clone().or(rec.reader.sheet.take());
        if !self.columns.is_empty() {
            rec.reader.columns = self.columns.clone();
        }
        let id = &mut study.identify;
        if let Some(a) = self.align {
            id.align = a;
            id.segmentation = Segmentation::PlanTiming;
        }
        id.segmentation = self.segment.unwrap_or(id.segmentation);
        if let Some(s) = self.steady {
            id.steady = s;
        }
        if let Some(m) = self.test_mode {
            id.mode = m.mode();
        }
        id.settle_time_s = self.settle_time_s.unwrap_or(id.settle_time_s);
        study.contact.convention = self.convention.unwrap_or(study.contact.convention);
        Ok(())
    }

    /// The identification's options: the steps file, else the plan where one is given
    /// (loads or velocities stated in the study's `[plan]` or here, unless `no_plan`: a
    /// `[plan]` holding only a track radius is no campaign), else the loads and speeds
    /// measured; without a plan, the study's or the flags' track radius serves the rpm
    /// channels.
    pub fn options(&self, study: &Study) -> Result<IdentifyOptions> {
        let expect = if let Some(path) = &self.plan_steps {
            Expectation::Steps(read_expected_steps(path)?)
        } else if !self.no_plan && self.plan.stated_in(study).campaign() {
            Expectation::Plan(study.plan.build().context("cannot build the plan")?)
        } else {
            Expectation::None
        };
        let mut radii = self.track_radii_mm.clone();
        if radii.is_empty() && !matches!(expect, Expectation::Plan(_)) {
            radii.extend(study.plan.track_radius_mm);
        }
        let side_inputs = [
            ("study", self.plan.study.as_ref()),
            ("plan_steps", self.plan_steps.as_ref()),
            ("truth", self.truth.as_ref()),
        ]
        .into_iter()
        .filter_map(|(f, p)| p.map(|p| (f.to_string(), p.clone())))
        .collect();
        Ok(IdentifyOptions {
            recordings: self.recordings.clone(),
            format: self.format,
            expect,
            track_radii_mm: radii,
            dataset: self.out.clone(),
            inspect_dir: self.inspect.then(|| self.inspect_dir()),
            truth: self.truth.clone(),
            side_inputs,
        })
    }

    /// Where inspect writes its SVGs: `inspect_dir`, else DATASET_inspect/ beside the dataset.
    fn inspect_dir(&self) -> PathBuf {
        self.inspect_dir.clone().unwrap_or_else(|| {
            let stem = self
                .out
                .file_stem()
                .map(|s| s.to_string_lossy().to_string());
            let stem = stem.unwrap_or_else(|| "dataset".into());
            self.out.with_file_name(format!("{stem}_inspect"))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_study_with_only_a_track_radius_is_no_plan_but_gives_the_radius() {
        let d = tempfile::tempdir().unwrap();
        let path = d.path().join("study.toml");
        std::fs::write(&path, "[plan]\ntrack_radius_mm = 80.0\n").unwrap();
        let mut s = IdentifySettings {
            recordings: vec!["r.csv".into()],
            ..Default::default()
        };
        s.plan.study = Some(path.clone());
        let (_, o) = s.prepare().unwrap();
        assert!(matches!(o.expect, Expectation::None));
        assert_eq!(o.track_radii_mm, [80.0]);
        // a stated velocity makes it a campaign: aligned against the plan, radius in the plan
        std::fs::write(
            &path,
            "[plan]\ntrack_radius_mm = 80.0\nvelocity_count = 3\n",
        )
        .unwrap();
        let (_, o) = s.prepare().unwrap();
        assert!(matches!(o.expect, Expectation::Plan(_)));
        assert!(o.track_radii_mm.is_empty());
    }
}
