//! `greybox identify`.

use crate::flags::shown;
use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::identify::{identify_campaign, IdentifyResult, SegmentsHook};
use greybox_pipeline::settings::identify::IdentifySettings;
use greybox_report::text::identify::{
    all_rows_table, files_table, inspect_text, matching_text, summary_table,
};
use greybox_tribo::campaign::FileReport;
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
    pub settings: IdentifySettings,
    /// Print the rig profiles greybox knows (name, program, test mode, the real export each
    /// was written against) and exit; needs no recordings.
    #[arg(long, exclusive = true)]
    pub list_rigs: bool,
    /// Print every plateau, not only the per-pin summary.
    #[arg(long)]
    pub all: bool,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

/// `--list-rigs`: every profile with its test mode and the export it was written against.
fn print_rigs() {
    for p in greybox_recording::profiles::PROFILES {
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
    if args.list_rigs {
        print_rigs();
        return Ok(());
    }
    let (study, options) = args.settings.prepare()?;
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
    if args.settings.inspect {
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
        shown(&greybox_report::text::identify_footer(&summary))
    );
    Ok(())
}
