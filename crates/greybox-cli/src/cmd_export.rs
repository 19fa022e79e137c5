//! `greybox export`: a friction law as tables for FE engines, or as a surrogate table. The
//! options are the library's [`ExportOverrides`], their defaults the library's per format
//! (stated in `--help` from [`ExportOverrides::defaults_of`]); a flag only overrides.

use crate::output::emit;
use anyhow::Result;
use greybox_core::choice::clap_parsers::choice;
use greybox_friction::export::engine::ExportFormat;
use greybox_pipeline::export::{export, ExportOptions, ExportOverrides};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Law file, model file from `greybox fit`, or table.
    #[arg(long)]
    pub law: PathBuf,
    #[arg(long, value_parser = choice::<ExportFormat>())]
    pub format: ExportFormat,
    /// Output file.
    #[arg(long)]
    pub out: PathBuf,
    #[command(flatten)]
    pub overrides: ExportOverrides,
    /// Print the export report as JSON.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// The library's options: its defaults, with the fields these flags set.
    pub fn options(&self) -> Result<ExportOptions> {
        ExportOptions::new(self.law.clone(), self.format, self.out.clone())
            .overridden(&self.overrides)
    }
}

pub fn run(a: Args) -> Result<()> {
    let report = export(&a.options()?)?;
    for w in &report.warnings {
        eprintln!("warning: {}", crate::flags::shown(w));
    }
    emit(a.json, &report, |r| format!("{}\n", r.line))
}
