//! `greybox adhesive`: the ploughing correction μ_adh = μ_app − μ_plough.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::adhesive::{adhesive, correction_path};
use greybox_pipeline::settings::adhesive::AdhesiveSettings;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub settings: AdhesiveSettings,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let options = a.settings.options()?;
    let (ds, c) = adhesive(&options)?;
    if a.json {
        return print_json(&c);
    }
    print!("{}", greybox_report::text::correction(&c));
    if let Some(line) = greybox_pipeline::adhesive::analytic_beside(&options, &ds)? {
        println!("{line}");
    }
    let out = &a.settings.out;
    println!(
        "wrote {} and {}",
        out.display(),
        correction_path(out).display()
    );
    Ok(())
}
