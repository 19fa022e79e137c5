//! The sweep file: a base case and the axes to vary.
//!
//! ```toml
//! [sweep]
//! kind = "cutting"                  # or "pin"
//! base = "aisi1045-cut.toml"        # relative to this file
//! fraction = 1.0                    # of the base's cut length (cutting)
//! max_cases = 10000                 # refuse axes that multiply to more cases
//! stop_when_sure = true             # cutting: end a cut once its forces are sure
//!
//! [[axis]]                          # a list of values
//! field = "cutting_speed_m_s"
//! values = [2.5, 4.0]
//!
//! [[axis]]                          # a range: count points from start to stop (log = true: geometric)
//! field = "uncut_chip_thickness_m"
//! range = { start = 5e-5, stop = 1e-4, count = 2 }
//!
//! [[axis]]                          # zipped: the fields change together
//! zip = [
//!   { field = "friction.law_file", values = ["law.json", "none"] },
//!   { field = "mu", values = [0.35, 0.35] },
//! ]
//!
//! [slurm]                           # optional: resources of each array task
//! partition = "compute"
//! cpus_per_task = 2
//! ```
//! Axes multiply (every combination); the values of a zipped axis go together. A field is
//! a dotted path into the base configuration (`insert.rake_deg`,
//! `material.plasticity.c`); the value `"none"` removes an optional field (e.g. the law
//! file: back to the constant `mu`).

use anyhow::{bail, Result};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// What each case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CaseKind {
    /// An orthogonal cut (a `CuttingSetup` TOML).
    Cutting,
    /// A pin pressed in and slid (a `PinSetup` TOML).
    Pin,
}

greybox_core::choice!(CaseKind, "sweep.kind", [Cutting => "cutting", Pin => "pin"]);

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    pub kind: CaseKind,
    /// The base configuration, relative to the sweep file.
    pub base: PathBuf,
    /// Cutting: the fraction of the configured cut length to simulate.
    #[serde(default = "one")]
    pub fraction: f64,
    /// Cutting: chip pictures per case (0: the last state only).
    #[serde(default = "no_frames")]
    pub frames: greybox_pipeline::simulate::Frames,
    /// Most cases the axes may multiply to (default [`DEFAULT_MAX_CASES`]): counted from the
    /// axes' lengths before any case is built, so a mistyped range cannot fill memory.
    #[serde(default = "default_max_cases")]
    pub max_cases: MaxCases,
    /// Cutting: end each cut once its force intervals meet the base's `[steady]` targets
    /// (default); `false` runs every cut to its full length.
    #[serde(default = "yes")]
    pub stop_when_sure: bool,
}

fn no_frames() -> greybox_pipeline::simulate::Frames {
    greybox_pipeline::simulate::Frames::of(0)
}

/// Values `[sweep] max_cases` may be raised to: every case is a directory and a run.
pub type MaxCases = greybox_core::count::Count<1, 10_000_000>;

fn yes() -> bool {
    true
}

/// Default of `[sweep] max_cases`: 10 000 cases.
pub const DEFAULT_MAX_CASES: MaxCases = MaxCases::of(10_000);

fn default_max_cases() -> MaxCases {
    DEFAULT_MAX_CASES
}

fn one() -> f64 {
    1.0
}

/// `count` points from `start` to `stop` (both included); `log`: evenly spaced in log.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    pub start: f64,
    pub stop: f64,
    /// Values of the axis (each case is a directory and a run: at most [`MaxCases::MAX`]).
    pub count: MaxCases,
    #[serde(default)]
    pub log: bool,
}

impl Range {
    fn values(&self, what: &str) -> Result<Vec<f64>> {
        let count = self.count.get();
        let ok = self.start.is_finite() && self.stop.is_finite();
        if !ok || (self.log && !(self.start > 0.0 && self.stop > 0.0)) {
            bail!("{what}: range needs finite start and stop (> 0 with log = true)");
        }
        if count == 1 {
            return Ok(vec![self.start]);
        }
        Ok((0..count)
            .map(|k| {
                let t = k as f64 / (count - 1) as f64;
                if self.log {
                    (self.start.ln() + t * (self.stop.ln() - self.start.ln())).exp()
                } else {
                    self.start + t * (self.stop - self.start)
                }
            })
            .collect())
    }
}

/// One field's values: a list or a range.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldValues {
    pub field: String,
    #[serde(default)]
    pub values: Option<Vec<toml::Value>>,
    #[serde(default)]
    pub range: Option<Range>,
}

impl FieldValues {
    /// The number of values, without expanding them.
    fn len(&self) -> usize {
        match (&self.values, &self.range) {
            (Some(v), None) => v.len(),
            (None, Some(r)) => r.count.get(),
            _ => 0,
        }
    }
    fn expand(&self, what: &str) -> Result<Vec<toml::Value>> {
        match (&self.values, &self.range) {
            (Some(v), None) if !v.is_empty() => Ok(v.clone()),
            (None, Some(r)) => Ok(r
                .values(what)?
                .into_iter()
                .map(toml::Value::Float)
                .collect()),
            _ => bail!(
                "{what} ({}): give either a non-empty `values` list or a `range`",
                self.field
            ),
        }
    }
}

/// An axis: one field, or several zipped.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    #[serde(default)]
    pub field: Option<String>,
    #[serde(default)]
    pub values: Option<Vec<toml::Value>>,
    #[serde(default)]
    pub range: Option<Range>,
    #[serde(default)]
    pub zip: Vec<FieldValues>,
}

/// Resources of each Slurm array task; unset ones come from the cost estimate.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SlurmSection {
    pub partition: Option<String>,
    pub account: Option<String>,
    /// Wall-time limit per task, `HH:MM:SS` (default: from the cost estimate).
    pub time: Option<String>,
    /// Memory per task, MB (default: from the particle count).
    pub mem_mb: Option<u64>,
    pub cpus_per_task: Option<u32>,
    /// At most this many tasks at once (`--array=…%N`).
    pub max_concurrent: Option<u32>,
    /// More `#SBATCH` lines, verbatim (e.g. `"--qos=short"`).
    pub extra: Vec<String>,
}

/// A whole sweep file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    pub sweep: SweepSection,
    #[serde(default)]
    pub axis: Vec<Axis>,
    #[serde(default)]
    pub slurm: SlurmSection,
}

/// An axis expanded: its field names and, per point, one value per field.
#[derive(Debug, Clone, PartialEq)]
pub struct ExpandedAxis {
    pub fields: Vec<String>,
    pub points: Vec<Vec<toml::Value>>,
}

impl SweepFile {
    /// Reads and checks a sweep file.
    pub fn load(path: &Path) -> Result<(SweepFile, PathBuf)> {
        let f: SweepFile = greybox_pipeline::config_toml::read(path, "sweep file")?;
        if !(f.sweep.fraction > 0.0 && f.sweep.fraction <= 1.0) {
            bail!(
                "{}: [sweep] fraction must be in (0, 1], got {}",
                path.display(),
                f.sweep.fraction
            );
        }
        let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
        Ok((f, dir))
    }

    /// The number of cases the axes multiply to (as a float: it may exceed every integer
    /// type), from their lengths alone; with the lengths per axis.
    pub fn case_count(&self) -> (f64, Vec<usize>) {
        let lens: Vec<usize> = self
            .axis
            .iter()
            .map(|a| match &a.field {
                Some(f) => FieldValues {
                    field: f.clone(),
                    values: a.values.clone(),
                    range: a.range.clone(),
                }
                .len(),
                None => a.zip.iter().map(FieldValues::len).max().unwrap_or(0),
            })
            .collect();
        (lens.iter().map(|&n| n as f64).product(), lens)
    }

    /// Every axis with its points (zipped fields of equal length); refused before anything is
    /// expanded when the axes multiply to more than `[sweep] max_cases`.
    pub fn expand_axes(&self) -> Result<Vec<ExpandedAxis>> {
        let (count, lens) = self.case_count();
        if count > self.sweep.max_cases.as_u64() as f64 {
            let per_axis: Vec<String> = lens.iter().map(usize::to_string).collect();
            bail!(greybox_core::budget::over_cap(
                &format!(
                    "the axes multiply to {count:.0} cases ({})",
                    per_axis.join(" × ")
                ),
                "[sweep] max_cases",
                &self.sweep.max_cases.to_string(),
                "max_cases = N in the sweep file's [sweep] section",
            ));
        }
        self.axis
            .iter()
            .enumerate()
            .map(|(k, a)| {
                let what = format!("axis {}", k + 1);
                let fields: Vec<FieldValues> = match (&a.field, a.zip.is_empty()) {
                    (Some(f), true) => vec![FieldValues {
                        field: f.clone(),
                        values: a.values.clone(),
                        range: a.range.clone(),
                    }],
                    (None, false) if a.values.is_none() && a.range.is_none() => a.zip.clone(),
                    _ => bail!("{what}: give either `field` with `values`/`range`, or `zip` (a list of fields)"),
                };
                let cols: Vec<Vec<toml::Value>> = fields
                    .iter()
                    .map(|f| f.expand(&what))
                    .collect::<Result<_>>()?;
                let n = cols[0].len();
                if cols.iter().any(|c| c.len() != n) {
                    bail!("{what}: zipped fields need the same number of values, got {:?}", cols.iter().map(Vec::len).collect::<Vec<_>>());
                }
                Ok(ExpandedAxis {
                    fields: fields.iter().map(|f| f.field.clone()).collect(),
                    points: (0..n).map(|i| cols.iter().map(|c| c[i].clone()).collect()).collect(),
                })
            })
            .collect()
    }
}

/// Every combination of the axes' points, the first axis varying slowest: per case, the
/// (field, value) pairs.
pub fn combinations(axes: &[ExpandedAxis]) -> Vec<Vec<(String, toml::Value)>> {
    let mut out: Vec<Vec<(String, toml::Value)>> = vec![Vec::new()];
    for a in axes {
        out = out
            .into_iter()
            .flat_map(|prefix| {
                a.points.iter().map(move |p| {
                    let mut v = prefix.clone();
                    v.extend(a.fields.iter().cloned().zip(p.iter().cloned()));
                    v
                })
            })
            .collect();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    fn parse(t: &str) -> SweepFile {
        toml::from_str(t).unwrap()
    }
    #[test]
    fn axes_multiply_zips_go_together_and_ranges_expand() {
        let f = parse(
            r#"
[sweep]
kind = "cutting"
base = "b.toml"
[[axis]]
field = "cutting_speed_m_s"
values = [1.0, 2.0]
[[axis]]
field = "uncut_chip_thickness_m"
range = { start = 1e-5, stop = 1e-3, count = 3, log = true }
[[axis]]
zip = [ { field = "friction.law_file", values = ["a.json", "none"] }, { field = "mu", values = [0.2, 0.3] } ]
"#,
        );
        let axes = f.expand_axes().unwrap();
        let h: Vec<f64> = axes[1]
            .points
            .iter()
            .map(|p| p[0].as_float().unwrap())
            .collect();
        assert!((h[1] - 1e-4).abs() < 1e-15, "{h:?}");
        let cases = combinations(&axes);
        assert_eq!(cases.len(), 2 * 3 * 2);
        // first axis slowest, zipped values together
        assert_eq!(cases[0][0].1.as_float(), Some(1.0));
        assert_eq!(cases[11][0].1.as_float(), Some(2.0));
        assert_eq!(cases[1][2].1.as_str(), Some("none"));
        assert_eq!(cases[1][3].1.as_float(), Some(0.3));
    }
    #[test]
    fn malformed_axes_are_named() {
        let f = parse("[sweep]\nkind = \"pin\"\nbase = \"b.toml\"\n[[axis]]\nzip = [ { field = \"a\", values = [1] }, { field = \"b\", values = [1, 2] } ]\n");
        let e = f.expand_axes().unwrap_err().to_string();
        assert!(e.contains("axis 1") && e.contains("same number"), "{e}");
        let f = parse("[sweep]\nkind = \"pin\"\nbase = \"b.toml\"\n[[axis]]\nfield = \"a\"\n");
        let e = f.expand_axes().unwrap_err().to_string();
        assert!(e.contains("axis 1 (a)") && e.contains("values"), "{e}");
        let e = toml::from_str::<SweepFile>("[sweep]\nkind = \"cut\"\nbase = \"b.toml\"\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("sweep.kind: 'cut' is not one of cutting, pin"),
            "{e}"
        );
    }
    #[test]
    fn cases_are_counted_before_they_are_expanded() {
        let t = "[sweep]\nkind = \"pin\"\nbase = \"b.toml\"\n[[axis]]\nfield = \"a\"\nrange = { start = 1, stop = 2, count = 100000 }\n[[axis]]\nfield = \"b\"\nrange = { start = 1, stop = 2, count = 100000 }\n";
        let e = parse(t).expand_axes().unwrap_err().to_string();
        assert!(
            e.contains("10000000000 cases (100000 × 100000)") && e.contains("max_cases = 10000"),
            "{e}"
        );
        // raising the cap is allowed up to the cap of the cap
        let raised = |n: &str| {
            t.replace(
                "base = \"b.toml\"",
                &format!("base = \"b.toml\"\nmax_cases = {n}"),
            )
        };
        assert_eq!(parse(&raised("10000000")).case_count().0, 1e10);
        let e = toml::from_str::<SweepFile>(&raised("20000000000"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("max_cases") && e.contains("above the cap of 10000000"),
            "{e}"
        );
    }
}
