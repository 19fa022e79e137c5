//! The export stage: a law file as a table for an FE engine (Abaqus, DEFORM, LS-DYNA, CSV)
//! or a surrogate table, written safely with provenance. What a table is and how each format
//! is written lives in `greybox_friction::export` (the registry `engine`, the dispatch
//! `write`); this stage reads the law, checks the output path against its inputs, writes and
//! reports.

mod options;

pub use options::*;

use crate::output::provenance;
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::choice::Choice;
use greybox_core::outputs::check_file_output;
use greybox_friction::export::write::{table_text, TableText};
use greybox_friction::spec::LawFile;

use greybox_friction::export::engine::{equidistant, AxisPoints, ExportFormat};
use greybox_friction::export::write::ExportReport;

/// Values from `MIN:MAX:N` (equidistant, both ends included) or a comma list; `what`
/// names the field in errors.
///
/// ```
/// use greybox_pipeline::export::parse_values;
/// assert_eq!(parse_values("0:1:3", "x").unwrap(), [0.0, 0.5, 1.0]);
/// assert_eq!(parse_values("2, 5", "x").unwrap(), [2.0, 5.0]);
/// assert!(parse_values("1:0:3", "pressure_MPa").unwrap_err().to_string().contains("pressure_MPa"));
/// ```
pub fn parse_values(text: &str, what: &str) -> Result<Vec<f64>> {
    let nums = |s: &str| -> Result<f64> {
        let v: f64 = s
            .trim()
            .parse()
            .with_context(|| format!("{what}: '{s}' is not a number"))?;
        if !v.is_finite() {
            bail!("{what}: '{s}' is not finite");
        }
        Ok(v)
    };
    let parts: Vec<&str> = text.split(':').collect();
    if parts.len() == 3 {
        let (a, b) = (nums(parts[0])?, nums(parts[1])?);
        let n: AxisPoints = parts[2]
            .parse()
            .with_context(|| format!("{what}: the N of MIN:MAX:N"))?;
        if !(b > a) {
            bail!("{what}: MIN:MAX:N needs MIN < MAX");
        }
        return Ok(equidistant(a, b, n.get()));
    }
    text.split(',').map(nums).collect()
}

/// Export; returns what was written and its deviation from the law.
pub fn export(a: &ExportOptions) -> Result<ExportReport> {
    // Read once: the outputs are checked against the law's inputs before the law (possibly
    // a model file of hundreds of MB) is built from the text read here.
    let law_file = LawFile::read(&a.law)?;
    let law_files = law_file.inputs();
    let mut inputs = vec![("law", a.law.as_path())];
    inputs.extend(
        law_files[1..]
            .iter()
            .map(|f| ("a file the law reads", f.as_path())),
    );
    if let Some(w) = a.table.engine.deform_windows() {
        inputs.push(("deform_windows", w.as_path()));
    }
    check_file_output(&a.out, "out", &inputs)?;
    let law = law_file.build()?;
    let TableText { text, report, note } = table_text(law.as_ref(), &a.table)?;
    write_string_atomic(&a.out, &text)?;
    provenance(&inputs)?.write_beside(&a.out)?;
    let deviation = match report.max_deviation {
        Some(d) => format!(
            "; max deviation from the law {d:.3e} on {} points inside the grid",
            report.check_points
        ),
        None => String::new(),
    };
    let mut warnings = Vec::new();
    if text.len() > LARGE_TABLE_BYTES {
        warnings.push(format!(
            "{} is {:.1} MB ({} table values): engines read a table this size slowly; coarsen the grid{}",
            a.out.display(),
            text.len() as f64 / 1e6,
            report.shape.iter().product::<usize>(),
            if a.table.adaptive_grid || a.format() == ExportFormat::Table {
                " or loosen `tolerance`"
            } else {
                ""
            }
        ));
    }
    Ok(ExportReport {
        line: format!(
            "exported {} as {} to {}{note}{deviation}",
            law.name(),
            a.format().name(),
            a.out.display()
        ),
        bytes: text.len(),
        warnings,
        ..report
    })
}

/// A written table above this size (bytes) gets a warning.
pub const LARGE_TABLE_BYTES: usize = 16_000_000;
