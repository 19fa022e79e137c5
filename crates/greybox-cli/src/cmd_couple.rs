//! `greybox couple`: the restart loop with an external FE engine.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::couple::couple;
use greybox_pipeline::settings::couple::CoupleSettings;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Write the bundled example (model.inp, segment.inp, law.json) into this directory and stop.
    #[arg(long)]
    pub example: Option<PathBuf>,
    /// Friction windows in the example.
    #[arg(long, default_value_t = greybox_couple::example::ExampleWindows::of(5))]
    pub example_windows: greybox_couple::example::ExampleWindows,
    #[command(flatten)]
    pub settings: CoupleSettings,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    if let Some(dir) = &a.example {
        greybox_couple::example::write_example(dir, a.example_windows.get())?;
        println!(
            "wrote {0}/model.inp, {0}/segment.inp and {0}/law.json; run:\n  greybox couple --deck {0}/model.inp --segment {0}/segment.inp --law {0}/law.json --work {0}/run",
            dir.display()
        );
        return Ok(());
    }
    let s = &a.settings;
    let r = couple(&s.options()?)?;
    if a.json {
        return print_json(&r);
    }
    print!("{}", greybox_report::text::coupling(&r, s.tol, &s.work));
    Ok(())
}
