//! `greybox fit`: the article's learning protocol with honest validation.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::fit::{fit, FitResult};
use greybox_pipeline::settings::fit::FitSettings;

#[derive(clap::Args, Debug, Clone)]
pub struct Args {
    #[command(flatten)]
    pub settings: FitSettings,
    /// Print the report as JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let FitResult {
        report,
        outputs,
        warnings,
    } = fit(&a.settings.options()?)?;
    for w in &warnings {
        eprintln!("warning: {}", crate::flags::shown(w));
    }
    if a.json {
        return print_json(&report);
    }
    print!("{}", greybox_report::text::fit(&report, &outputs));
    Ok(())
}
