//! `greybox wear`: Archard specific wear rates from volumes, height maps or scar geometry.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::settings::wear::{WearRun, WearSettings};

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub settings: WearSettings,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    match a.settings.run()? {
        WearRun::Tests(rows) if a.json => print_json(&rows),
        WearRun::Tests(rows) => {
            print!("{}", greybox_report::text::wear_tests(&rows));
            Ok(())
        }
        WearRun::One(r) if a.json => print_json(&r),
        WearRun::One(r) => {
            print!("{}", greybox_report::text::wear(&r));
            Ok(())
        }
    }
}
