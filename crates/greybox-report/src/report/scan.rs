//! Finding greybox outputs in a study directory by what they hold, not where they lie.

use super::{input, Ctx};
use anyhow::Result;
use std::collections::HashSet;
use std::os::unix::fs::MetadataExt;
use std::path::{Path, PathBuf};

/// The outputs found, each list in path order.
#[derive(Debug, Default)]
pub struct Found {
    /// Run sheets of `greybox plan` (`run_sheet.csv`).
    pub run_sheets: Vec<PathBuf>,
    /// Friction datasets (CSV with a `cof_apparent` column).
    pub datasets: Vec<PathBuf>,
    /// Ploughing corrections (`*.correction.json`).
    pub corrections: Vec<PathBuf>,
    /// Fit reports (`report.json` with `families`).
    pub fit_reports: Vec<PathBuf>,
    /// Friction-law files (JSON with a top-level `law`).
    pub laws: Vec<PathBuf>,
    /// Cut output directories (a `summary.json` with the cutting force).
    pub cuts: Vec<PathBuf>,
    /// Rig characterisations (`report.json` with `loads`).
    pub characterizations: Vec<PathBuf>,
    /// Wear-test tables (CSV with a `k_1e-7_mm3_per_Nm` column).
    pub wear_tests: Vec<PathBuf>,
    /// Provenance records.
    pub provenance: Vec<PathBuf>,
    /// Sweep output directories (a sweep `plan.json`); their cases are not searched one
    /// by one (the sweep's results table stands for them).
    pub sweeps: Vec<PathBuf>,
}

/// Directories never searched: VTK series, staging and resumable directories, hidden ones.
fn skipped(name: &str) -> bool {
    name == "vtk" || name == "frames" || name.starts_with('.') || name.ends_with(".partial")
}

/// Searches `dir` to a depth of `max_depth`, each directory once (by device and inode:
/// links are followed but a directory reached again, e.g. through `ln -s . loop`, is not
/// searched again), looking at no more than `max_entries` entries. FIFOs, devices and
/// sockets are never opened: each is named among the warnings.
pub(crate) fn scan(dir: &Path, cx: &mut Ctx) -> Result<Found> {
    let mut w = Walk::default();
    w.dir(dir, 0, cx)?;
    if let Some(first) = &w.too_deep_first {
        cx.warn(format!(
            "{} directories deeper than max_depth ({}) not searched, first {} (raise max_depth)",
            w.too_deep,
            cx.depth,
            first.display()
        ));
    }
    Ok(w.found)
}

#[derive(Default)]
struct Walk {
    found: Found,
    /// (device, inode) of the directories searched.
    seen: HashSet<(u64, u64)>,
    too_deep: usize,
    too_deep_first: Option<PathBuf>,
}

impl Walk {
    fn dir(&mut self, dir: &Path, depth: u64, cx: &mut Ctx) -> Result<()> {
        let m = std::fs::metadata(dir)?;
        if !self.seen.insert((m.dev(), m.ino())) {
            return Ok(());
        }
        let mut entries = Vec::new();
        for e in std::fs::read_dir(dir)? {
            if !cx.take_entry(dir) {
                break;
            }
            if let Ok(e) = e {
                entries.push(e.path());
            }
        }
        entries.sort();
        for p in entries {
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            // links followed; a dangling one is passed over
            let Ok(m) = std::fs::metadata(&p) else {
                continue;
            };
            if m.is_dir() {
                let sweep_cases = name == "cases" && is_sweep(dir, cx);
                if skipped(&name) || sweep_cases {
                    continue;
                }
                if depth >= cx.depth {
                    self.too_deep += 1;
                    self.too_deep_first.get_or_insert(p);
                    continue;
                }
                if let Err(e) = self.dir(&p, depth + 1, cx) {
                    cx.warn(format!("cannot search {}: {e:#}", p.display()));
                }
                continue;
            }
            if !m.is_file() {
                cx.warn(format!(
                    "skipped {}: {}, not a regular file (never opened)",
                    p.display(),
                    input::kind(&m)
                ));
                continue;
            }
            classify(&p, &name, &mut self.found, cx);
        }
        Ok(())
    }
}

/// Whether `dir` is a sweep's output directory (its `plan.json` lists cases and fields).
fn is_sweep(dir: &Path, cx: &mut Ctx) -> bool {
    let plan = dir.join(greybox_sweep::PLAN_FILE);
    if !plan.exists() {
        return false;
    }
    let keys = json_keys(&plan, cx);
    keys.iter().any(|k| k == "cases") && keys.iter().any(|k| k == "fields")
}

/// The top-level keys of a JSON object file read within `max_file_bytes` (a file over it
/// is named among the warnings).
fn json_keys(p: &Path, cx: &mut Ctx) -> Vec<String> {
    match cx.read(p) {
        Ok(bytes) => serde_json::from_slice::<serde_json::Value>(&bytes)
            .ok()
            .and_then(|v| v.as_object().map(|o| o.keys().cloned().collect()))
            .unwrap_or_default(),
        Err(e) => {
            cx.note(p, &e);
            Vec::new()
        }
    }
}

fn classify(p: &Path, name: &str, f: &mut Found, cx: &mut Ctx) {
    if name == "provenance.json" || name.ends_with(".provenance.json") {
        f.provenance.push(p.to_path_buf());
        return;
    }
    if name == greybox_sweep::PLAN_FILE {
        if let Some(d) = p.parent().filter(|d| is_sweep(d, cx)) {
            f.sweeps.push(d.to_path_buf());
            return;
        }
    }
    if name == "run_sheet.csv" {
        f.run_sheets.push(p.to_path_buf());
        return;
    }
    if name.ends_with(".csv") {
        let h = match cx.header(p) {
            Ok(h) => h,
            Err(e) => {
                cx.note(p, &e);
                return;
            }
        };
        let cols: Vec<&str> = h.trim().split(',').map(str::trim).collect();
        if cols.contains(&"cof_apparent") {
            f.datasets.push(p.to_path_buf());
        } else if cols.contains(&"k_1e-7_mm3_per_Nm") {
            f.wear_tests.push(p.to_path_buf());
        }
        return;
    }
    if name.ends_with(".correction.json") {
        f.corrections.push(p.to_path_buf());
        return;
    }
    if !name.ends_with(".json") {
        return;
    }
    let keys = json_keys(p, cx);
    let has = |k: &str| keys.iter().any(|x| x == k);
    if name == "summary.json" && has("cutting_force_n_per_mm") {
        if let Some(d) = p.parent() {
            f.cuts.push(d.to_path_buf());
        }
    } else if has("families") && has("features") {
        f.fit_reports.push(p.to_path_buf());
    } else if has("loads") && has("files") {
        f.characterizations.push(p.to_path_buf());
    } else if has("law") {
        f.laws.push(p.to_path_buf());
    }
}
