//! `greybox identify`.

use crate::args::choice_name;
use crate::cmd_plan::PlanFlags;
use crate::output::print_json;
use anyhow::{Context, Result};
use greybox_core::choice::Choice;
use greybox_core::dataset::PressureConvention;
use greybox_pipeline::identify::{
    all_rows_table, files_table, identify_campaign, inspect_text, matching_text, summary_table,
    Expectation, IdentifyOptions, IdentifyResult, SegmentsHook,
};
use greybox_pipeline::identify_settings::IdentifySettings;
use greybox_pipeline::study::Study;
use greybox_tribo::campaign::{read_expected_steps, FileReport};
use greybox_tribo::identify::Alignment;
use greybox_tribo::identify_config::{Segmentation, SteadyRule, TestMode};
use greybox_tribo::readers::RecordingFormat;
use std::path::{Path, PathBuf};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum InFormat {
    /// Delimited text (.csv, .txt, .tsv, .dat, .asc, .prn).
    Csv,
    Tdms,
    /// Spreadsheets (.xlsx, .xlsm, .xls, .xlsb, .ods).
    Xlsx,
}

impl From<InFormat> for RecordingFormat {
    fn from(f: InFormat) -> Self {
        match f {
            InFormat::Csv => RecordingFormat::Csv,
            InFormat::Tdms => RecordingFormat::Tdms,
            InFormat::Xlsx => RecordingFormat::Spreadsheet,
        }
    }
}

/// Segment and identify tribometer recordings from any rig.
///
/// Three ways to find the steps, tried in this order with `--segment auto`: a step/segment
/// column (`--map step=Step`), a speed channel (`--map speed="Velocity:rpm"`, with
/// `--track-radius-mm` or `--track-radii-mm` for rpm), or the signals themselves (change
/// points of F_N and F_t/F_N). greybox's own NC-program recordings (a trigger channel and a
/// `--study` plan) keep the plan-timed path. With a plan (`--study` with a [plan], or
/// `--plan-steps` listing pin, normal_force_N, sliding_velocity_m_per_min in run order),
/// segments are matched to its steps; without one, loads and velocities are the measured
/// ones. `--inspect` prints what was found per file and writes an SVG per recording.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub plan: PlanFlags,
    /// Recording files (CSV/TXT, XLSX/XLS/ODS, TDMS) or directories: a file per step, per
    /// pin or for the whole campaign. A directory gives its pinNN files when the plan's pins
    /// are all there, else every recording file in natural order.
    #[arg(long, num_args = 1.., required = true)]
    pub recordings: Vec<PathBuf>,
    /// Which files to pick from a directory (default: every supported format).
    #[arg(long, value_enum)]
    pub format: Option<InFormat>,
    /// How to find the steps.
    #[arg(long, value_parser = choice_name::<Segmentation>())]
    pub segment: Option<String>,
    /// How the rig ran its tests (study `[identify] mode`). `reciprocating` (ASTM G133):
    /// strokes instead of plateaus, μ from the middle half of each stroke with the sign taken
    /// by direction, one row per test averaged over the steady cycles, the per-cycle μ in
    /// `<out>.cycles.csv`. Default `auto`: reciprocating where the rig profile says so or the
    /// signals show it (a reversing position, or a friction force that changes sign
    /// regularly).
    #[arg(long = "test-mode", value_parser = clap::builder::PossibleValuesParser::new(
        ["auto"].into_iter().chain(TestMode::names())))]
    pub test_mode: Option<String>,
    /// Expected steps without timing: CSV with pin, normal_force_N,
    /// sliding_velocity_m_per_min [, step], in the order they were run.
    #[arg(long = "plan-steps")]
    pub plan_steps: Option<PathBuf>,
    /// Ignore the study's plan: loads and velocities from the recordings.
    #[arg(long = "no-plan")]
    pub no_plan: bool,
    /// How to align the plan with each recording (plan-timing path).
    #[arg(long, value_parser = choice_name::<Alignment>())]
    pub align: Option<String>,
    /// Which part of each segment gives its steady value: `auto` (the final stationary
    /// stretch after run-in, ASTM G99/G133 practice; drift reported as a trend), `last:P%`
    /// (the last P % of the segment's sliding time) or `from:Ts` (from T seconds after the
    /// segment's start).
    #[arg(long, value_parser = parse_steady)]
    pub steady: Option<String>,
    /// Time dropped after the spindle ramp, s.
    #[arg(long = "settle-s")]
    pub settle_s: Option<f64>,
    /// Channel mapping ROLE=NAME[:UNIT[:SCALE]], repeatable. Roles: time, normal, tangential,
    /// radial, trigger, step, speed, radius, cof, position; an empty name (speed=) ignores a role. Unmapped
    /// roles are found by their usual names (Fz, Fx, Time, Step, Velocity, ...).
    #[arg(long = "map")]
    pub map: Vec<String>,
    /// 1-based header line of text files (default: found below any preamble).
    #[arg(long = "header-line")]
    pub header_line: Option<u64>,
    /// Sample rate of files without a time column, Hz.
    #[arg(long = "sample-rate-hz")]
    pub sample_rate_hz: Option<f64>,
    /// Rig profile of the files (phoenix-te, pcs-mtm, bruker-umt, rtec, pod-dwf; `list`
    /// prints them); default: detected from each file's preamble and header when exactly one
    /// profile matches.
    #[arg(long)]
    pub rig: Option<String>,
    /// Normal load, N, for rigs that do not record it (dead-weight pin-on-disc rigs).
    #[arg(long = "constant-normal-force-N")]
    pub constant_normal_force_n: Option<f64>,
    /// Sliding velocity, m/min, for rigs that do not record their speed.
    #[arg(long = "constant-sliding-velocity-m-per-min")]
    pub constant_sliding_velocity_m_per_min: Option<f64>,
    /// Track radius per segment for rpm speed channels, mm (comma-separated: one per segment
    /// of each file, or of the whole campaign).
    #[arg(long = "track-radii-mm", value_delimiter = ',')]
    pub track_radii_mm: Vec<f64>,
    /// Spreadsheet sheet to read (default: the first holding a table).
    #[arg(long)]
    pub sheet: Option<String>,
    /// TDMS group holding the channels.
    #[arg(long = "tdms-group")]
    pub tdms_group: Option<String>,
    /// Pressure convention written to the dataset (overrides [contact] convention).
    #[arg(long, value_parser = choice_name::<PressureConvention>())]
    pub convention: Option<String>,
    /// Output dataset CSV.
    #[arg(long, default_value = "dataset.csv")]
    pub out: PathBuf,
    /// Ground truth CSV from `greybox synth`: report the identification error against it.
    #[arg(long)]
    pub truth: Option<PathBuf>,
    /// Print every plateau, not only the per-pin summary.
    #[arg(long)]
    pub all: bool,
    /// Print per file the mapped columns, sampling rate and every segment (start, end, load,
    /// speed, steady window, μ, flags), and write an SVG per recording with the steady
    /// windows shaded into --inspect-dir.
    #[arg(long)]
    pub inspect: bool,
    /// Where --inspect writes its SVGs (default: DATASET_inspect/ beside the dataset).
    #[arg(long = "inspect-dir")]
    pub inspect_dir: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

fn parse_steady(s: &str) -> std::result::Result<String, String> {
    s.parse::<SteadyRule>().map(|_| s.to_string())
}

impl Args {
    /// The library's settings for these flags.
    fn settings(&self) -> IdentifySettings {
        IdentifySettings {
            map: self.map.clone(),
            rig: self.rig.clone(),
            constant_normal_force_N: self.constant_normal_force_n,
            constant_sliding_velocity_m_per_s: self
                .constant_sliding_velocity_m_per_min
                .map(greybox_core::units::m_per_min_to_m_per_s),
            tdms_group: self.tdms_group.clone(),
            header_line: self.header_line,
            sample_rate_hz: self.sample_rate_hz,
            sheet: self.sheet.clone(),
            align: self.align.clone(),
            segment: self.segment.clone(),
            steady: self.steady.clone(),
            test_mode: self.test_mode.clone(),
            settle_time_s: self.settle_s,
            convention: self.convention.clone(),
        }
    }
}

/// Whether the user gave a plan: a `[plan]` section in the study, or a plan-shape flag.
fn plan_given(args: &Args) -> Result<bool> {
    let f = &args.plan;
    let flags = f.normal_force_min_n.is_some()
        || f.normal_force_max_n.is_some()
        || f.normal_force_count.is_some()
        || f.velocity_min.is_some()
        || f.velocity_max.is_some()
        || f.velocity_count.is_some();
    let in_study = match &f.study {
        Some(path) => Study::declares_plan(path)?,
        None => false,
    };
    Ok(flags || in_study)
}

/// `--rig list`: every profile with its test mode and the export it was written against.
fn print_rigs() {
    for p in greybox_tribo::profiles::PROFILES {
        println!(
            "{:<12} {} [{}]\n             written against: {}",
            p.name,
            p.vendor,
            p.mode.name(),
            p.verified_against
        );
    }
}

pub fn run(args: Args) -> Result<()> {
    if args.rig.as_deref() == Some("list") {
        print_rigs();
        return Ok(());
    }
    let mut study = args.plan.study()?;
    args.settings().apply(&mut study)?;
    let expect = if let Some(path) = &args.plan_steps {
        Expectation::Steps(read_expected_steps(path)?)
    } else if !args.no_plan && plan_given(&args)? {
        Expectation::Plan(study.plan.build().context("cannot build the plan")?)
    } else {
        Expectation::None
    };
    let mut radii = args.track_radii_mm.clone();
    if radii.is_empty() {
        if let (Expectation::None | Expectation::Steps(_), Some(r)) =
            (&expect, args.plan.track_radius_mm)
        {
            radii.push(r);
        }
    }
    let side_inputs = [
        ("study", args.plan.study.as_deref()),
        ("plan_steps", args.plan_steps.as_deref()),
        ("truth", args.truth.as_deref()),
    ]
    .into_iter()
    .filter_map(|(f, p)| p.map(|p| (f.to_string(), p.to_path_buf())))
    .collect();
    let inspect_dir = args.inspect.then(|| {
        args.inspect_dir.clone().unwrap_or_else(|| {
            let stem = args
                .out
                .file_stem()
                .map(|s| s.to_string_lossy().to_string())
                .unwrap_or_else(|| "dataset".into());
            args.out.with_file_name(format!("{stem}_inspect"))
        })
    });
    let options = IdentifyOptions {
        recordings: args.recordings.clone(),
        format: args.format.map(Into::into),
        expect,
        track_radii_mm: radii,
        dataset: args.out.clone(),
        inspect_dir,
        truth: args.truth.clone(),
        side_inputs,
    };
    let show = |files: &[FileReport], dir: &Path| {
        print!("{}", inspect_text(files));
        println!("inspect plots -> {}", dir.display());
    };
    let show: Option<SegmentsHook> = (!args.json).then_some(&show as _);
    let IdentifyResult {
        dataset: ds,
        summary,
    } = identify_campaign(&study, &options, show)?;
    if args.json {
        return print_json(&summary);
    }
    if args.inspect {
        print!("{}", matching_text(&summary.identification.matching));
    }
    print!(
        "{}",
        if args.all {
            all_rows_table(&ds)
        } else {
            summary_table(&ds)
        }
    );
    print!("{}", files_table(&summary.identification));
    print!("{}", greybox_pipeline::text::identify_footer(&summary));
    Ok(())
}
