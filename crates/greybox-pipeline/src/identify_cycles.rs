//! Reciprocating tests (ASTM G133) in the identify stage: the per-cycle evolution written
//! beside the dataset (`<dataset>.cycles.csv`) and its pictures (its `--inspect` lines are
//! `greybox_report::text::identify::reciprocating_lines`).

use anyhow::Result;
use greybox_tribo::campaign::FileReport;
use std::path::{Path, PathBuf};

/// The per-cycle file beside a dataset: `<dataset>.cycles.csv` (as the provenance record is
/// `<dataset>.provenance.json`).
pub fn cycles_path(dataset: &Path) -> PathBuf {
    let mut name = dataset
        .file_name()
        .map(|n| n.to_os_string())
        .unwrap_or_default();
    name.push(".cycles.csv");
    dataset.with_file_name(name)
}

/// Whether any segment was identified as a reciprocating test.
pub fn any_reciprocating(files: &[FileReport]) -> bool {
    files
        .iter()
        .flat_map(|f| &f.segments)
        .any(|s| s.reciprocating.is_some())
}

/// The per-cycle CSV: `file, cycle, time_s, mu_forward, mu_backward, mu_mean`, then the
/// dataset row the cycle belongs to (`pin, step`, empty when unmatched) and whether it is one
/// of the steady cycles averaged (`steady`, 1 or 0).
pub fn cycles_csv(files: &[FileReport]) -> Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(greybox_core::escape::csv_cells([
        "file",
        "cycle",
        "time_s",
        "mu_forward",
        "mu_backward",
        "mu_mean",
        "pin",
        "step",
        "steady",
    ]))?;
    for f in files {
        for s in &f.segments {
            let Some(r) = &s.reciprocating else { continue };
            let (pin, step) = s.matched.map_or((String::new(), String::new()), |(p, k)| {
                (p.to_string(), k.to_string())
            });
            for (k, c) in r.cycles.iter().enumerate() {
                let steady = (r.steady_cycles.0..r.steady_cycles.1).contains(&k);
                w.write_record(greybox_core::escape::csv_cells([
                    f.source.clone(),
                    c.index.to_string(),
                    format!("{:.6}", c.time_s),
                    format!("{:.6}", c.mu_forward),
                    format!("{:.6}", c.mu_backward),
                    format!("{:.6}", c.mu_mean),
                    pin.clone(),
                    step.clone(),
                    u8::from(steady).to_string(),
                ]))?;
            }
        }
    }
    Ok(String::from_utf8(w.into_inner()?)?)
}

/// `<name>.cycles.svg`: μ forward, backward and mean per cycle, the steady cycles shaded.
pub fn write_cycles_plot(f: &FileReport, dir: &Path, name: &str) -> Result<()> {
    let mut series: [(Vec<f64>, Vec<f64>); 3] = Default::default();
    let mut bands_owned: Vec<(f64, f64, String)> = Vec::new();
    let mut base = 0usize;
    for g in &f.segments {
        let Some(r) = &g.reciprocating else { continue };
        for c in &r.cycles {
            let x = (base + c.index) as f64;
            for (k, v) in [c.mu_forward, c.mu_backward, c.mu_mean]
                .into_iter()
                .enumerate()
            {
                series[k].0.push(x);
                series[k].1.push(v);
            }
        }
        let (a, b) = r.steady_cycles;
        bands_owned.push((
            (base + a + 1) as f64,
            (base + b) as f64,
            format!("{}", g.index),
        ));
        base += r.cycles.len();
    }
    if base == 0 {
        return Ok(());
    }
    let bands: Vec<(f64, f64, &str)> = bands_owned
        .iter()
        .map(|(a, b, l)| (*a, *b, l.as_str()))
        .collect();
    let line = |label, colour, k: usize| greybox_core::plot::Line {
        label,
        colour,
        x: &series[k].0,
        y: &series[k].1,
    };
    let svg = greybox_core::plot::lines(
        &format!("{name}: μ per cycle (ASTM G133 mid-stroke), steady cycles shaded"),
        "cycle",
        "μ [-]",
        &[
            line("forward", "#1f4e9c", 0),
            line("backward", "#b2182b", 1),
            line("mean", "#222222", 2),
        ],
        false,
        &bands,
    );
    greybox_core::atomic::write_string_atomic(&dir.join(format!("{name}.cycles.svg")), &svg)?;
    Ok(())
}
