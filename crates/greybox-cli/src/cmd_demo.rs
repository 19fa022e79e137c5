//! `greybox demo`: the whole pipeline on the bundled example study
//! ([`greybox_report::demo`]), printed stage by stage.

use crate::output::print_json;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output directory.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once the demo is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let demo = greybox_report::demo::run(&a.out, a.force)?;
    if a.json {
        return print_json(&serde_json::to_value(&demo.summary)?);
    }
    print!("{}", greybox_report::text::demo(&demo, &a.out)?);
    Ok(())
}
