//! `greybox identify`.

use crate::flags::shown;
use crate::output::print_json;
use anyhow::Result;
use greybox_core::choice::clap_parsers::choice_name;
use greybox_core::choice::Choice;
use greybox_core::dataset::PressureConvention;
use greybox_pipeline::identify::{
    all_rows_table, files_table, identify_campaign, inspect_text, matching_text, summary_table,
    IdentifyResult, SegmentsHook,
};
use greybox_pipeline::settings::identify::{IdentifyInputs, IdentifySettings};
use greybox_pipeline::settings::plan::PlanSettings;
use greybox_tribo::campaign::FileReport;
use greybox_tribo::identify::Alignment;
use greybox_tribo::identify_config::{Segmentation, SteadyRule, TestMode};
use std::path::Path;

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
    pub plan: PlanSettings,
    #[command(flatten)]
    pub inputs: IdentifyInputs,
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
    /// roles are found by their usual names (Fz, Fx, Time, Step, Velocity, ...). NAME `#K` is
    /// column K of the file, counted from 1 (`--map normal=#3:N`), as in a log without header.
    #[arg(long = "map")]
    pub map: Vec<String>,
    /// 1-based header line of text files (default: found below any preamble).
    #[arg(long = "header-line")]
    pub header_line: Option<greybox_pipeline::settings::identify::HeaderLine>,
    /// Sample rate of files without a time column, Hz: time = k / rate.
    #[arg(long = "sample-rate-hz")]
    pub sample_rate_hz: Option<f64>,
    /// Names for the columns in file order, comma-separated, units in the names as in a
    /// header (`t_s,Fn_N,Ft_N`): for a log without a header line, whose columns are otherwise
    /// `#1`, `#2`, … (`--map normal=#2:N` maps by number), or to rename a file's columns.
    #[arg(long, value_delimiter = ',')]
    pub columns: Vec<String>,
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
    /// Spreadsheet sheet to read (default: the first holding a table).
    #[arg(long)]
    pub sheet: Option<String>,
    /// TDMS group holding the channels.
    #[arg(long = "tdms-group")]
    pub tdms_group: Option<String>,
    /// Pressure convention written to the dataset (overrides [contact] convention).
    #[arg(long, value_parser = choice_name::<PressureConvention>())]
    pub convention: Option<String>,
    /// Print every plateau, not only the per-pin summary.
    #[arg(long)]
    pub all: bool,
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
            columns: self.columns.clone(),
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
    if args.inputs.recordings.is_empty() {
        anyhow::bail!("--recordings is required (only `--rig list` runs without it)");
    }
    let mut study = args.plan.study()?;
    args.settings().apply(&mut study)?;
    let options = args.inputs.options(&study, &args.plan)?;
    let show = |files: &[FileReport], dir: &Path| {
        print!("{}", shown(&inspect_text(files)));
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
    if args.inputs.inspect {
        print!(
            "{}",
            shown(&matching_text(&summary.identification.matching))
        );
    }
    print!(
        "{}",
        if args.all {
            all_rows_table(&ds)
        } else {
            summary_table(&ds)
        }
    );
    print!("{}", shown(&files_table(&summary.identification)));
    print!(
        "{}",
        shown(&greybox_pipeline::text::identify_footer(&summary))
    );
    Ok(())
}
