//! Terminal and JSON output helpers.

use anyhow::Result;
use greybox_core::outputs::{check_dir_output, Existing, StagedDir};
use greybox_core::provenance::Provenance;
use serde::Serialize;
use std::path::Path;

/// The provenance record of this run: greybox's version, the command line and `inputs`
/// (hashed now).
pub fn provenance(inputs: &[(&str, &Path)]) -> Result<Provenance> {
    Ok(Provenance::new(
        "greybox",
        env!("CARGO_PKG_VERSION"),
        std::env::args().collect(),
    )
    .inputs(inputs)?)
}

/// Begin the output directory `--out`: refused if it holds one of `inputs` or (unless
/// `force`) already holds files; written into a staging directory that
/// [`StagedDir::commit`] swaps in whole.
pub fn stage_out_dir(out: &Path, force: bool, inputs: &[(&str, &Path)]) -> Result<StagedDir> {
    check_dir_output(out, "--out", inputs)?;
    Ok(StagedDir::begin(out, "--out", Existing::from_force(force))?)
}

/// Print a value as pretty JSON on stdout.
pub fn print_json<T: Serialize>(value: &T) -> Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

/// A plain-text table with right-aligned columns.
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    pub fn new(header: &[&str]) -> Self {
        Table {
            header: header.iter().map(|s| s.to_string()).collect(),
            rows: Vec::new(),
        }
    }
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }
    pub fn render(&self) -> String {
        let n = self.header.len();
        let mut width = vec![0; n];
        for r in std::iter::once(&self.header).chain(&self.rows) {
            for (w, c) in width.iter_mut().zip(r) {
                *w = (*w).max(c.chars().count());
            }
        }
        let line = |r: &Vec<String>| -> String {
            r.iter()
                .zip(&width)
                .map(|(c, w)| format!("{c:>w$}"))
                .collect::<Vec<_>>()
                .join("  ")
        };
        let mut s = line(&self.header);
        s.push('\n');
        s.push_str(
            &width
                .iter()
                .map(|w| "-".repeat(*w))
                .collect::<Vec<_>>()
                .join("  "),
        );
        s.push('\n');
        for r in &self.rows {
            s.push_str(&line(r));
            s.push('\n');
        }
        s
    }
}
