//! `greybox synth`.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::settings::synth::SynthSettings;

/// The virtual tribometer: a study's campaign simulated into raw recordings and their
/// ground truth. Without `--study`, the bundled example study (the article's campaign, as
/// `greybox demo` runs it); the plan flags override either.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub settings: SynthSettings,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> Result<()> {
    let summary = args.settings.run()?;
    if args.json {
        return print_json(&summary);
    }
    print!("{}", greybox_report::text::synth(&summary));
    println!(
        "  wrote {} files to {}",
        summary.files.len(),
        args.settings.out.display()
    );
    Ok(())
}
