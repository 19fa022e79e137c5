//! `greybox characterize`: FRF of the rig from impact-hammer recordings, and the article's
//! dynamics check against the campaign's spindle excitation.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::characterize::characterize;
use greybox_pipeline::settings::characterize::CharacterizeSettings;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub settings: CharacterizeSettings,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let r = characterize(&a.settings.options()?)?;
    if a.json {
        return print_json(&r);
    }
    print!("{}", greybox_report::text::characterize(&r));
    println!("wrote {}", r.files.join(", "));
    Ok(())
}
