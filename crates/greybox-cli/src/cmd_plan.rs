//! `greybox plan`.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::plan::plan;
use greybox_pipeline::settings::plan::PlanSettings;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub plan: PlanSettings,
    /// Output directory: study.toml, run_sheet.csv, nc/pinNN.nc.
    #[arg(long, default_value = "plan-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> Result<()> {
    let study = args.plan.study()?;
    let summary = plan(&study, &args.out, args.force, &args.plan.inputs())?;
    if args.json {
        return print_json(&summary);
    }
    print!("{}", greybox_report::text::plan(&summary));
    println!(
        "  wrote {} files to {}",
        summary.files.len(),
        args.out.display()
    );
    Ok(())
}
