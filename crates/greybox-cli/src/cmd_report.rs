//! `greybox report`: one self-contained HTML page for a study directory.

use crate::output::emit;
use anyhow::Result;
use greybox_report::report::{report, ReportOptions};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The study directory (e.g. the output of greybox demo); searched recursively.
    pub study_dir: PathBuf,
    /// The page to write (default: STUDY_DIR/report.html).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Largest file read whole, in bytes (JSON, CSV, TOML, recordings) [default: 64 MiB].
    #[arg(long, value_name = "BYTES")]
    pub max_file_bytes: Option<u64>,
    /// Largest SVG file turned into a figure, in bytes [default: 8 MiB].
    #[arg(long, value_name = "BYTES")]
    pub max_svg_bytes: Option<u64>,
    /// Most bytes read to find a CSV file's header line [default: 64 KiB].
    #[arg(long, value_name = "BYTES")]
    pub max_header_bytes: Option<u64>,
    /// Most directory entries looked at in the whole search [default: 100000].
    #[arg(long, value_name = "N")]
    pub max_entries: Option<u64>,
    /// Deepest directory level searched below STUDY_DIR [default: 6].
    #[arg(long, value_name = "N")]
    pub max_depth: Option<u64>,
    /// Largest page written, in bytes [default: 64 MiB].
    #[arg(long, value_name = "BYTES")]
    pub max_page_bytes: Option<u64>,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    // the defaults live in the library (ReportOptions::default); flags only override them
    let mut o = ReportOptions::new(a.study_dir);
    o.out = a.out;
    let caps = [
        (a.max_file_bytes, &mut o.max_file_bytes),
        (a.max_svg_bytes, &mut o.max_svg_bytes),
        (a.max_header_bytes, &mut o.max_header_bytes),
        (a.max_entries, &mut o.max_entries),
        (a.max_depth, &mut o.max_depth),
        (a.max_page_bytes, &mut o.max_page_bytes),
    ];
    for (flag, field) in caps {
        if let Some(v) = flag {
            *field = v;
        }
    }
    let s = report(&o)?;
    emit(a.json, &s, |s| {
        let mut t = format!(
            "wrote {} ({:.1} kB): {} sections ({}), {} figures\n",
            s.path,
            greybox_core::units::bytes_to_kb(s.bytes),
            s.sections.len(),
            s.sections.join(", "),
            s.figures
        );
        for w in &s.warnings {
            t += &format!("warning: {}\n", crate::flags::shown(w));
        }
        t
    })
}
