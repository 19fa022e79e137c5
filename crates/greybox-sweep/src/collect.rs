//! `greybox sweep collect`: every case's summary in one CSV (the axes, then the results),
//! and plots of a result against the first numeric axis, one curve per value of the others.

use super::case::{CaseDir, Done, Status};
use super::spec::CaseKind;
use super::Plan;
use anyhow::Result;
use greybox_core::atomic::write_string_atomic;
use greybox_core::outputs::{output_subdir, path_component};
use greybox_core::plot::{lines, Line};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Result columns of a cut: (CSV column with its unit, key in the cut's summary); a
/// `_ci95` column is the half-width of the 95 % interval of the one before it (empty: the
/// cut could not say).
const CUT_COLUMNS: [(&str, &str); 20] = [
    ("cutting_force_N_per_mm", "cutting_force_n_per_mm"),
    ("cutting_force_ci95_N_per_mm", "cutting_force_ci95_n_per_mm"),
    ("feed_force_N_per_mm", "feed_force_n_per_mm"),
    ("feed_force_ci95_N_per_mm", "feed_force_ci95_n_per_mm"),
    ("force_ratio", "force_ratio"),
    (
        "specific_cutting_force_N_per_mm2",
        "specific_cutting_force_n_per_mm2",
    ),
    ("chip_thickness_mm", "chip_thickness_mm"),
    ("compression_ratio", "compression_ratio"),
    ("compression_ratio_ci95", "compression_ratio_ci95"),
    ("shear_angle_deg", "shear_angle_deg"),
    ("contact_length_mm", "contact_length_mm"),
    ("max_temperature_C", "max_temperature_c"),
    ("peak_temperature_C", "peak_temperature_c"),
    ("steady", "steady"),
    ("steady_from_mm", "steady_from_mm"),
    ("sure", "sure"),
    ("limit_reached", "limit_reached"),
    ("simulated_cut_length_mm", "simulated_cut_length_mm"),
    ("particles", "particles"),
    ("solver_wall_s", "wall_s"),
];

/// The results plotted against an axis for cuts.
const CUT_PLOTS: [(&str, &str); 5] = [
    ("cutting_force_N_per_mm", "cutting force F'c (N/mm)"),
    ("feed_force_N_per_mm", "feed force F'f (N/mm)"),
    ("contact_length_mm", "contact length (mm)"),
    ("max_temperature_C", "maximum temperature (°C)"),
    ("shear_angle_deg", "shear angle (°)"),
];

/// What `collect` wrote.
#[derive(Debug, Clone, Serialize)]
pub struct Collected {
    pub csv: String,
    pub cases: usize,
    pub done: usize,
    /// Cases without a result (index, id, status).
    pub missing: Vec<(usize, String, Status)>,
    pub plots: Vec<String>,
}

fn cell(v: Option<&serde_json::Value>) -> String {
    match v {
        Some(serde_json::Value::Null) | None => String::new(),
        Some(serde_json::Value::String(s)) => s.clone(),
        Some(x) => x.to_string(),
    }
}

/// The result columns: fixed for cuts; for pins every scalar of the first summary.
fn columns(plan: &Plan, dones: &[Option<Done>]) -> Vec<(String, String)> {
    match plan.kind {
        CaseKind::Cutting => CUT_COLUMNS
            .iter()
            .map(|(c, k)| (c.to_string(), k.to_string()))
            .collect(),
        CaseKind::Pin => dones
            .iter()
            .flatten()
            .next()
            .and_then(|d| d.summary.as_object())
            .map(|o| {
                o.iter()
                    .filter(|(_, v)| v.is_number() || v.is_boolean())
                    .map(|(k, _)| (k.clone(), k.clone()))
                    .collect()
            })
            .unwrap_or_default(),
    }
}

/// Writes `results.csv` and `plots/*.svg` into the sweep directory `out`.
pub fn collect(out: &Path) -> Result<Collected> {
    let plan = Plan::read(out)?;
    let dones: Vec<Option<Done>> = plan
        .cases
        .iter()
        .map(|c| CaseDir::of(out, &c.id).read_done(c))
        .collect::<Result<_>>()?;
    let cols = columns(&plan, &dones);
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["case".to_string(), "id".into(), "status".into()];
    header.extend(plan.fields.iter().cloned());
    header.extend(cols.iter().map(|c| c.0.clone()));
    header.push("case_wall_s".into());
    header.push("case_peak_memory_MB".into());
    w.write_record(greybox_core::escape::csv_cells(&header))?;
    let mut missing = Vec::new();
    let mut table: Vec<BTreeMap<String, String>> = Vec::new();
    for (c, d) in plan.cases.iter().zip(&dones) {
        let status = if d.is_some() {
            Status::Done
        } else {
            CaseDir::of(out, &c.id).status(c)
        };
        let mut row = vec![
            c.index.to_string(),
            c.id.clone(),
            format!("{status:?}").to_lowercase(),
        ];
        row.extend(c.values.iter().map(|(_, v)| v.clone()));
        let mut named: BTreeMap<String, String> = c.values.iter().cloned().collect();
        for (col, key) in &cols {
            let v = cell(d.as_ref().and_then(|d| d.summary.get(key)));
            named.insert(col.clone(), v.clone());
            row.push(v);
        }
        row.push(
            d.as_ref()
                .map(|d| format!("{:.3}", d.wall_s))
                .unwrap_or_default(),
        );
        row.push(
            d.as_ref()
                .and_then(|d| d.peak_memory_mb)
                .map(|m| format!("{m:.1}"))
                .unwrap_or_default(),
        );
        w.write_record(greybox_core::escape::csv_cells(&row))?;
        if d.is_none() {
            missing.push((c.index, c.id.clone(), status));
        } else {
            table.push(named);
        }
    }
    let csv_path = out.join("results.csv");
    write_string_atomic(&csv_path, &String::from_utf8(w.into_inner()?)?)?;
    let plots = write_plots(&plan, out, &table)?;
    Ok(Collected {
        csv: csv_path.display().to_string(),
        cases: plan.cases.len(),
        done: table.len(),
        missing,
        plots,
    })
}

/// A value for a legend: a file field by its file name (the table keeps the whole path).
fn short_value(field: &str, v: &str) -> String {
    if field.ends_with("_file") {
        Path::new(v)
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| v.to_string())
    } else {
        v.to_string()
    }
}

/// A result against the first axis whose values are all numbers, one curve per
/// combination of the other axes.
fn write_plots(plan: &Plan, out: &Path, table: &[BTreeMap<String, String>]) -> Result<Vec<String>> {
    let num = |s: &str| s.trim().parse::<f64>().ok();
    let Some(x_axis) = plan.fields.iter().find(|f| {
        table
            .iter()
            .all(|r| r.get(*f).and_then(|v| num(v)).is_some())
    }) else {
        return Ok(Vec::new());
    };
    let others: Vec<&String> = plan.fields.iter().filter(|f| *f != x_axis).collect();
    let results: Vec<(String, String)> = match plan.kind {
        CaseKind::Cutting => CUT_PLOTS
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect(),
        CaseKind::Pin => table
            .first()
            .map(|r| {
                r.keys()
                    .filter(|k| {
                        !plan.fields.contains(k) && r.get(*k).and_then(|v| num(v)).is_some()
                    })
                    .map(|k| (k.clone(), k.clone()))
                    .collect()
            })
            .unwrap_or_default(),
    };
    let dir = output_subdir(out, "plots")?;
    let palette = [
        "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b",
    ];
    let mut written = Vec::new();
    for (col, label) in results {
        // curve label → (x, y) sorted by x
        let mut curves: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
        for r in table {
            let (Some(x), Some(y)) = (num(&r[x_axis]), r.get(&col).and_then(|v| num(v))) else {
                continue;
            };
            let key = others
                .iter()
                .map(|f| {
                    let v = r.get(*f).map_or("(not set)", String::as_str);
                    format!("{f} = {}", short_value(f, v))
                })
                .collect::<Vec<_>>()
                .join(", ");
            curves.entry(key).or_default().push((x, y));
        }
        if curves.is_empty() {
            continue;
        }
        let data: Vec<(String, Vec<f64>, Vec<f64>)> = curves
            .into_iter()
            .map(|(k, mut pts)| {
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                let label = if k.is_empty() { label.clone() } else { k };
                (
                    label,
                    pts.iter().map(|p| p.0).collect(),
                    pts.iter().map(|p| p.1).collect(),
                )
            })
            .collect();
        let ls: Vec<Line> = data
            .iter()
            .enumerate()
            .map(|(k, (l, x, y))| Line {
                label: l,
                colour: palette[k % palette.len()],
                x,
                y,
            })
            .collect();
        let svg = lines(
            &format!("{label} over {x_axis}"),
            x_axis,
            &label,
            &ls,
            false,
            &[],
        );
        let name = format!("{col}_vs_{}.svg", x_axis.replace('.', "_"));
        let field = "a plot's file name (from its fields and the cases' summary keys)";
        let p = dir.join(path_component(&name, &out.join(super::PLAN_FILE), field)?);
        write_string_atomic(&p, &svg)?;
        written.push(p.display().to_string());
    }
    Ok(written)
}
