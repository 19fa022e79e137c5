//! Finding greybox outputs in a study directory by what they hold, not where they lie.

use anyhow::Result;
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

/// Searches `dir` to a depth of 6.
pub fn scan(dir: &Path) -> Result<Found> {
    let mut f = Found::default();
    walk(dir, 0, &mut f)?;
    Ok(f)
}

fn walk(dir: &Path, depth: usize, f: &mut Found) -> Result<()> {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for p in entries {
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        if p.is_dir() {
            let sweep_cases = name == "cases" && is_sweep(dir);
            if depth < 6 && !skipped(&name) && !sweep_cases {
                walk(&p, depth + 1, f)?;
            }
            continue;
        }
        classify(&p, &name, f);
    }
    Ok(())
}

/// Whether `dir` is a sweep's output directory (its `plan.json` lists cases and fields).
fn is_sweep(dir: &Path) -> bool {
    let keys = json_keys(&dir.join(crate::sweep::PLAN_FILE));
    keys.iter().any(|k| k == "cases") && keys.iter().any(|k| k == "fields")
}

/// The first line of a text file (its CSV header), if readable.
fn header(p: &Path) -> Option<String> {
    use std::io::BufRead;
    let file = std::fs::File::open(p).ok()?;
    let mut line = String::new();
    std::io::BufReader::new(file).read_line(&mut line).ok()?;
    Some(line)
}

/// The top-level keys of a JSON object file (small files only: reports, laws, summaries).
fn json_keys(p: &Path) -> Vec<String> {
    let small = std::fs::metadata(p)
        .map(|m| m.len() < 64 << 20)
        .unwrap_or(false);
    if !small {
        return Vec::new();
    }
    std::fs::read_to_string(p)
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| v.as_object().map(|o| o.keys().cloned().collect()))
        .unwrap_or_default()
}

fn classify(p: &Path, name: &str, f: &mut Found) {
    if name == "provenance.json" || name.ends_with(".provenance.json") {
        f.provenance.push(p.to_path_buf());
        return;
    }
    if name == crate::sweep::PLAN_FILE {
        if let Some(d) = p.parent().filter(|d| is_sweep(d)) {
            f.sweeps.push(d.to_path_buf());
            return;
        }
    }
    if name == "run_sheet.csv" {
        f.run_sheets.push(p.to_path_buf());
        return;
    }
    if name.ends_with(".csv") {
        let h = header(p).unwrap_or_default();
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
    let keys = json_keys(p);
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
