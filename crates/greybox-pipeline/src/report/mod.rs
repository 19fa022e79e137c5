//! `greybox report`: one self-contained HTML page for a study directory — the campaign,
//! the friction data, the models, the cuts with pictures of the chip, sweeps, rig dynamics
//! and wear, and the provenance of every output. Each section appears only when its data is in
//! the directory, wherever it lies in the tree (a `greybox demo` output, or a folder where
//! a user ran the stages one by one).
//!
//! A file that is there but cannot be read does not stop the report: its section says what
//! went wrong, and the summary lists it among the warnings.

mod campaign;
mod cutting;
mod friction;
mod models;
pub mod page;
mod provenance;
mod rig;
mod scan;
mod sweeps;

use anyhow::{Context, Result};
use greybox_core::atomic::write_string_atomic;
use page::Section;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What to report on and where to write it.
#[derive(Debug, Clone)]
pub struct ReportOptions {
    /// The study directory (searched recursively).
    pub study_dir: PathBuf,
    /// The page to write (default: `STUDY_DIR/report.html`).
    pub out: Option<PathBuf>,
}

/// What the report holds.
#[derive(Debug, Clone, Serialize)]
pub struct ReportSummary {
    pub path: String,
    pub bytes: u64,
    /// Section titles, in page order.
    pub sections: Vec<String>,
    /// Inline figures (plots and chip pictures).
    pub figures: usize,
    /// Files that were found but could not be read, with the reason.
    pub warnings: Vec<String>,
}

/// Collects the warnings of the section builders.
#[derive(Default)]
pub(crate) struct Warnings(Vec<String>);

impl Warnings {
    /// Records `e` about `what` and returns a paragraph saying so, for the section.
    pub(crate) fn note(&mut self, what: &Path, e: &anyhow::Error) -> page::Block {
        let msg = format!("could not read {}: {e:#}", what.display());
        self.0.push(msg.clone());
        page::Block::Text(msg)
    }
}

impl Section {
    /// The blocks drawn from the file `p`, or the reason it could not be read (recorded in
    /// `w` too).
    pub(crate) fn add_from(&mut self, p: &Path, r: Result<Vec<page::Block>>, w: &mut Warnings) {
        match r {
            Ok(bs) => self.blocks.extend(bs),
            Err(e) => self.blocks.push(w.note(p, &e)),
        }
    }
}

/// Writes the report page for `o.study_dir` (atomically) and returns its summary.
pub fn report(o: &ReportOptions) -> Result<ReportSummary> {
    let dir = &o.study_dir;
    if !dir.is_dir() {
        anyhow::bail!(
            "{}: not a directory (expected a study directory, e.g. the output of greybox demo)",
            dir.display()
        );
    }
    let out = o.out.clone().unwrap_or_else(|| dir.join("report.html"));
    let found = scan::scan(dir).with_context(|| format!("cannot search {}", dir.display()))?;
    let mut w = Warnings::default();
    let sections: Vec<Section> = [
        campaign::section(dir, &found, &mut w),
        friction::section(dir, &found, &mut w),
        models::section(dir, &found, &mut w),
        cutting::section(dir, &found, &mut w),
        sweeps::section(dir, &found, &mut w),
        rig::section(dir, &found, &mut w),
        provenance::section(dir, &found, &mut w),
    ]
    .into_iter()
    .flatten()
    .collect();
    if sections.is_empty() {
        anyhow::bail!(
            "{}: no greybox outputs found (plan run sheet, dataset, fit report, law, cut, sweep, characterisation, wear tests or provenance)",
            dir.display()
        );
    }
    let intro = vec![
        format!(
            "Study directory: {}. Written by greybox {} (greybox report).",
            dir.display(),
            env!("CARGO_PKG_VERSION")
        ),
        "Every figure is drawn from the files named in its caption; paths are relative to the study directory.".to_string(),
    ];
    let html = page::render("greybox study report", &intro, &sections);
    write_string_atomic(&out, &html)?;
    Ok(ReportSummary {
        path: out.display().to_string(),
        bytes: html.len() as u64,
        sections: sections.iter().map(|s| s.title.clone()).collect(),
        figures: html.matches("<figure").count(),
        warnings: w.0,
    })
}

/// `path` relative to the study directory, for captions.
pub(crate) fn shown(dir: &Path, path: &Path) -> String {
    path.strip_prefix(dir).unwrap_or(path).display().to_string()
}

/// A number with `digits` significant digits, without exponent for everyday magnitudes.
pub(crate) fn num(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        return format!("{:.*e}", digits.saturating_sub(1), v);
    }
    let decimals = (digits as i32 - 1 - mag).max(0) as usize;
    format!("{v:.decimals$}")
}

/// An SVG file as a figure block, or a warning paragraph if it cannot be read.
pub(crate) fn svg_figure(dir: &Path, path: &Path, caption: &str, w: &mut Warnings) -> page::Block {
    match std::fs::read_to_string(path)
        .with_context(|| "cannot read the file".to_string())
        .and_then(|t| page::inline_svg(&t).context("no <svg> element in it"))
    {
        Ok(svg) => page::Block::Figure {
            svg,
            caption: format!("{caption} ({})", shown(dir, path)),
        },
        Err(e) => w.note(path, &e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn numbers_keep_their_significant_digits() {
        assert_eq!(num(0.975308, 3), "0.975");
        assert_eq!(num(2941.18, 4), "2941");
        assert_eq!(num(1.2e-8, 3), "1.20e-8");
        assert_eq!(num(f64::NAN, 3), "n/a");
    }
    #[test]
    fn an_empty_or_missing_directory_is_a_clear_error() {
        let d = tempfile::tempdir().unwrap();
        let e = report(&ReportOptions {
            study_dir: d.path().into(),
            out: None,
        })
        .unwrap_err();
        assert!(
            format!("{e:#}").contains("no greybox outputs found"),
            "{e:#}"
        );
        let e = report(&ReportOptions {
            study_dir: d.path().join("nope"),
            out: None,
        })
        .unwrap_err();
        assert!(format!("{e:#}").contains("not a directory"), "{e:#}");
    }
}
