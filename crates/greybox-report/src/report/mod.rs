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
mod input;
mod models;
pub mod page;
mod provenance;
mod rig;
pub mod sanitize;
mod scan;
mod sweeps;

use anyhow::{Context, Result};
use greybox_core::atomic::write_string_atomic;
use input::Cap;
use page::Section;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What to report on, where to write it, and the budgets that bound the work on a study
/// directory nobody vouches for (each cap has a CLI flag of the same name, e.g.
/// `--max-file-bytes`; a cap reached is a warning naming it, or an error for the page).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ReportOptions {
    /// The study directory (searched recursively; each directory once, however many links
    /// lead to it).
    pub study_dir: PathBuf,
    /// The page to write (default: `STUDY_DIR/report.html`). Never one of the files the
    /// report reads, nor a path under `/dev`.
    pub out: Option<PathBuf>,
    /// Largest file read whole (JSON, CSV, TOML, recordings, model files): a larger one is
    /// skipped with a warning. Default 64 MiB.
    pub max_file_bytes: u64,
    /// Largest SVG file turned into a figure: a larger one is left out with a warning.
    /// Default 8 MiB.
    pub max_svg_bytes: u64,
    /// Most bytes read to find the first line (header) of a CSV file when recognising it.
    /// Default 64 KiB.
    pub max_header_bytes: u64,
    /// Most directory entries looked at, over the whole search and the figure folders:
    /// past it the search stops with a warning. Default 100 000.
    pub max_entries: u64,
    /// Deepest directory level searched below the study directory. Default 6.
    pub max_depth: u64,
    /// Largest page: figures that would make it larger are left out with a warning, and a
    /// page still larger is refused. Default 64 MiB.
    pub max_page_bytes: u64,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            study_dir: PathBuf::from("."),
            out: None,
            max_file_bytes: 64 << 20,
            max_svg_bytes: 8 << 20,
            max_header_bytes: 64 << 10,
            max_entries: 100_000,
            max_depth: 6,
            max_page_bytes: 64 << 20,
        }
    }
}

impl ReportOptions {
    /// The defaults for `study_dir`.
    pub fn new(study_dir: impl Into<PathBuf>) -> Self {
        ReportOptions {
            study_dir: study_dir.into(),
            ..Default::default()
        }
    }
    fn cap(&self, field: &'static str) -> Cap {
        let bytes = match field {
            "max_file_bytes" => self.max_file_bytes,
            "max_svg_bytes" => self.max_svg_bytes,
            "max_header_bytes" => self.max_header_bytes,
            "max_entries" => self.max_entries,
            "max_depth" => self.max_depth,
            _ => self.max_page_bytes,
        };
        Cap { bytes, field }
    }
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
    /// Files that were found but could not be read, with the reason; files skipped; what was
    /// removed from figures; caps reached.
    pub warnings: Vec<String>,
}

/// The state of one report: its budgets, the warnings of the section builders and every
/// file read (the inputs an `--out` must not replace).
pub(crate) struct Ctx {
    dir: PathBuf,
    file: Cap,
    svg: Cap,
    pub(crate) header: Cap,
    entries: Cap,
    pub(crate) depth: u64,
    page: Cap,
    warnings: Vec<String>,
    /// Files read, in the order read.
    pub(crate) inputs: Vec<PathBuf>,
    /// Directory entries looked at so far (against `max_entries`).
    entries_seen: u64,
    /// Bytes of figures on the page so far (against `max_page_bytes`).
    figure_bytes: u64,
    figures: usize,
}

impl Ctx {
    pub(crate) fn new(o: &ReportOptions) -> Self {
        Ctx {
            dir: o.study_dir.clone(),
            file: o.cap("max_file_bytes"),
            svg: o.cap("max_svg_bytes"),
            header: o.cap("max_header_bytes"),
            entries: o.cap("max_entries"),
            depth: o.max_depth,
            page: o.cap("max_page_bytes"),
            warnings: Vec::new(),
            inputs: Vec::new(),
            entries_seen: 0,
            figure_bytes: 0,
            figures: 0,
        }
    }

    /// Records a warning.
    pub(crate) fn warn(&mut self, msg: String) {
        self.warnings.push(msg);
    }

    /// Records `e` about `what` and returns a paragraph saying so, for the section.
    pub(crate) fn note(&mut self, what: &Path, e: &anyhow::Error) -> page::Block {
        let msg = format!("could not read {}: {e:#}", what.display());
        self.warnings.push(msg.clone());
        page::Block::Text(msg)
    }

    /// Checks that `p` is a regular file within `max_file_bytes` and records it as an input;
    /// call before handing a path to a reader of another crate (which opens it itself).
    pub(crate) fn admit(&mut self, p: &Path) -> Result<()> {
        input::regular_within(p, self.file)?;
        self.inputs.push(p.to_path_buf());
        Ok(())
    }

    /// The bytes of `p` (a regular file within `max_file_bytes`), recorded as an input.
    pub(crate) fn read(&mut self, p: &Path) -> Result<Vec<u8>> {
        let b = input::read_capped(p, self.file)?;
        self.inputs.push(p.to_path_buf());
        Ok(b)
    }

    /// The text of `p` (a regular file within `max_file_bytes`), recorded as an input.
    pub(crate) fn read_text(&mut self, p: &Path) -> Result<String> {
        String::from_utf8(self.read(p)?).context("not UTF-8 text")
    }

    /// A CSV reader over `p` read within `max_file_bytes`.
    pub(crate) fn csv(&mut self, p: &Path) -> Result<csv::Reader<std::io::Cursor<Vec<u8>>>> {
        Ok(csv::Reader::from_reader(std::io::Cursor::new(
            self.read(p)?,
        )))
    }

    /// The first line of `p` within `max_header_bytes`, recorded as an input.
    pub(crate) fn header(&mut self, p: &Path) -> Result<String> {
        let h = input::first_line(p, self.header)?;
        self.inputs.push(p.to_path_buf());
        Ok(h)
    }

    /// Takes one directory entry from the `max_entries` budget; `false` (with a warning, the
    /// first time) once it is spent.
    pub(crate) fn take_entry(&mut self, dir: &Path) -> bool {
        if self.entries_seen == self.entries.bytes {
            self.entries_seen += 1;
            self.warn(format!(
                "stopped looking at directory entries in {} and after: {} entries seen, the cap max_entries (raise it with {})",
                dir.display(),
                self.entries.bytes,
                self.entries.flag()
            ));
        }
        if self.entries_seen >= self.entries.bytes {
            return false;
        }
        self.entries_seen += 1;
        true
    }

    /// The files of `dir` whose name ends in `.{ext}`, sorted, within the entry budget.
    pub(crate) fn list(&mut self, dir: &Path, ext: &str) -> Vec<PathBuf> {
        let Ok(rd) = std::fs::read_dir(dir) else {
            return Vec::new();
        };
        let mut files = Vec::new();
        for e in rd {
            if !self.take_entry(dir) {
                break;
            }
            if let Ok(e) = e {
                let p = e.path();
                if p.extension().is_some_and(|x| x == ext) {
                    files.push(p);
                }
            }
        }
        files.sort();
        files
    }

    /// An SVG file from the study rebuilt for the page (read within `max_svg_bytes`,
    /// sanitised; what was removed is a warning), within the page budget.
    pub(crate) fn svg(&mut self, path: &Path) -> Result<String> {
        let bytes = input::read_capped(path, self.svg)?;
        self.inputs.push(path.to_path_buf());
        let text = String::from_utf8(bytes).context("not UTF-8 text")?;
        self.figures += 1;
        let s = sanitize::sanitize_svg(&text, &format!("fig{}", self.figures))?;
        if let Some(w) = s.warning(&shown(&self.dir, path)) {
            self.warn(w);
        }
        let total = self.figure_bytes + s.svg.len() as u64;
        if total > self.page.bytes {
            anyhow::bail!(
                "left out: the page's figures would reach {total} bytes, {}",
                self.page.exceeded()
            );
        }
        self.figure_bytes = total;
        Ok(s.svg)
    }
}

impl Section {
    /// The blocks drawn from the file `p`, or the reason it could not be read (recorded in
    /// `w` too).
    pub(crate) fn add_from(&mut self, p: &Path, r: Result<Vec<page::Block>>, w: &mut Ctx) {
        match r {
            Ok(bs) => self.blocks.extend(bs),
            Err(e) => self.blocks.push(w.note(p, &e)),
        }
    }
}

/// Refuses an output path under `/dev` or one that is not a regular file, before any work.
fn check_out_path(out: &Path) -> Result<()> {
    let abs = std::path::absolute(out).unwrap_or_else(|_| out.to_path_buf());
    let canon = std::fs::canonicalize(out).unwrap_or_else(|_| abs.clone());
    if abs.starts_with("/dev") || canon.starts_with("/dev") {
        anyhow::bail!(
            "out {}: a path under /dev is never written by greybox report",
            out.display()
        );
    }
    greybox_core::outputs::check_file_output(out, "out", &[])?;
    Ok(())
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
    check_out_path(&out)?;
    let mut w = Ctx::new(o);
    let found =
        scan::scan(dir, &mut w).with_context(|| format!("cannot search {}", dir.display()))?;
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
    // every file read is an input: the page must replace none of them
    let inputs: Vec<(&str, &Path)> = w
        .inputs
        .iter()
        .map(|p| ("STUDY_DIR", p.as_path()))
        .collect();
    greybox_core::outputs::check_file_output(&out, "out", &inputs)?;
    let intro = vec![
        format!(
            "Study directory: {}. Written by greybox {} (greybox report).",
            dir.display(),
            env!("CARGO_PKG_VERSION")
        ),
        "Every figure is drawn from the files named in its caption; paths are relative to the study directory.".to_string(),
    ];
    let html = page::render("greybox study report", &intro, &sections);
    if html.len() as u64 > w.page.bytes {
        anyhow::bail!(
            "the page would be {} bytes, {}; nothing written",
            html.len(),
            w.page.exceeded()
        );
    }
    write_string_atomic(&out, &html)?;
    Ok(ReportSummary {
        path: out.display().to_string(),
        bytes: html.len() as u64,
        sections: sections.iter().map(|s| s.title.clone()).collect(),
        figures: html.matches("<figure").count(),
        warnings: w.warnings,
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

/// An SVG file of the study as a figure block (rebuilt by [`Ctx::svg`]), or a warning
/// paragraph if it cannot be used.
pub(crate) fn svg_figure(dir: &Path, path: &Path, caption: &str, w: &mut Ctx) -> page::Block {
    match w.svg(path) {
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
        let e = report(&ReportOptions::new(d.path())).unwrap_err();
        assert!(
            format!("{e:#}").contains("no greybox outputs found"),
            "{e:#}"
        );
        let e = report(&ReportOptions::new(d.path().join("nope"))).unwrap_err();
        assert!(format!("{e:#}").contains("not a directory"), "{e:#}");
    }
}
