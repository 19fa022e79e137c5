//! `greybox report`: one self-contained HTML page for a study directory.

use crate::output::emit;
use anyhow::Result;
use greybox_pipeline::report::{report, ReportOptions};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The study directory (e.g. the output of greybox demo); searched recursively.
    pub study_dir: PathBuf,
    /// The page to write (default: STUDY_DIR/report.html).
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let s = report(&ReportOptions {
        study_dir: a.study_dir,
        out: a.out,
    })?;
    emit(a.json, &s, |s| {
        let mut t = format!(
            "wrote {} ({:.1} kB): {} sections ({}), {} figures\n",
            s.path,
            s.bytes as f64 / 1e3,
            s.sections.len(),
            s.sections.join(", "),
            s.figures
        );
        for w in &s.warnings {
            t += &format!("warning: {w}\n");
        }
        t
    })
}
