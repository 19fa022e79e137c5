//! Sweeps section: per sweep, its cases with their axes and main results (from
//! `results.csv`, written by `greybox sweep collect`) and its plots.

use super::page::{Block, Section, Table};
use super::scan::Found;
use super::{shown, svg_figure, Ctx};
use anyhow::{Context, Result};
use std::path::Path;

/// The results shown per case, when the table has them (a `_ci95` column: the half-width of
/// the 95 % interval of the one before it).
const SHOWN: [&str; 10] = [
    "cutting_force_N_per_mm",
    "cutting_force_ci95_N_per_mm",
    "feed_force_N_per_mm",
    "feed_force_ci95_N_per_mm",
    "force_ratio",
    "contact_length_mm",
    "max_temperature_C",
    "steady",
    "sure",
    "case_wall_s",
];

pub fn section(dir: &Path, found: &Found, w: &mut Ctx) -> Option<Section> {
    let mut s = Section::new("sweeps", "Sweeps");
    for sw in &found.sweeps {
        let r = sweep_blocks(dir, sw, w);
        s.add_from(sw, r, w);
    }
    (!s.blocks.is_empty()).then_some(s)
}

fn sweep_blocks(dir: &Path, sw: &Path, w: &mut Ctx) -> Result<Vec<Block>> {
    w.admit(&sw.join(greybox_sweep::PLAN_FILE))?;
    let plan = greybox_sweep::Plan::read(sw)?;
    let name = shown(dir, sw);
    let mut out = vec![Block::Heading(format!("Sweep {name}"))];
    let results = sw.join("results.csv");
    if !results.exists() {
        out.push(Block::Text(format!(
            "{} cases of {}; no results table yet (greybox sweep collect {name}).",
            plan.cases.len(),
            plan.source
        )));
        return Ok(out);
    }
    let mut rdr = w.csv(&results)?;
    let header: Vec<String> = rdr.headers()?.iter().map(str::to_string).collect();
    let cols: Vec<usize> = ["case", "status"]
        .iter()
        .map(|c| c.to_string())
        .chain(plan.fields.iter().cloned())
        .chain(SHOWN.iter().map(|c| c.to_string()))
        .filter_map(|c| header.iter().position(|h| *h == c))
        .collect();
    let hdr: Vec<&str> = cols.iter().map(|&i| header[i].as_str()).collect();
    let mut t = Table::new(
        &format!(
            "{} cases of {} ({})",
            plan.cases.len(),
            plan.source,
            shown(dir, &results)
        ),
        &hdr,
    );
    for (k, r) in rdr.records().enumerate() {
        let r = r.with_context(|| format!("{}: line {}", results.display(), k + 2))?;
        t.row(
            cols.iter()
                .map(|&i| {
                    let c = r.get(i).unwrap_or("");
                    match c.parse::<f64>() {
                        Ok(x) if c.contains('.') && x.abs() >= 1e-3 => super::num(x, 4),
                        _ => c.to_string(),
                    }
                })
                .collect(),
        );
    }
    out.push(Block::Table(t));
    let plots = w.list(&sw.join("plots"), "svg");
    let figs: Vec<Block> = plots
        .iter()
        .map(|p| {
            svg_figure(
                dir,
                p,
                "A result over the first axis, one curve per value of the others",
                w,
            )
        })
        .collect();
    if !figs.is_empty() {
        out.push(Block::Row(figs));
    }
    Ok(out)
}
