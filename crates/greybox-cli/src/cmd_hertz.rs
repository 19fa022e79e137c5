//! `greybox hertz`.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::settings::hertz::HertzSettings;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub settings: HertzSettings,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let (e_star, rows) = a.settings.run()?;
    if a.json {
        return print_json(&rows);
    }
    print!(
        "{}",
        greybox_report::text::hertz(e_star, &rows, a.settings.convention)
    );
    Ok(())
}
