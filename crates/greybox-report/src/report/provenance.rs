//! Provenance section: for every output with a provenance record, the command that made
//! it, greybox's version, the seed, and each input with its SHA-256; and the wall times
//! the stages recorded.

use super::page::{Block, Section, Table};
use super::scan::Found;
use super::{num, shown, Ctx};
use greybox_core::provenance::Provenance;
use serde_json::Value;
use std::path::Path;

pub fn section(dir: &Path, found: &Found, w: &mut Ctx) -> Option<Section> {
    let mut s = Section::new("provenance", "Provenance");
    let mut runs = Table::new(
        "What made each output",
        &["record", "command", "greybox version", "seed"],
    );
    let mut inputs = Table::new(
        "Inputs, with their SHA-256",
        &["record", "role", "path", "bytes", "SHA-256"],
    );
    for p in &found.provenance {
        match w.admit(p).and_then(|()| Ok(Provenance::read(p)?)) {
            Ok(r) => {
                let rec = shown(dir, p);
                runs.row(vec![
                    rec.clone(),
                    r.command.join(" "),
                    format!("{} {}", r.program, r.version),
                    r.seed.map(|s| s.to_string()).unwrap_or_else(|| "—".into()),
                ]);
                for i in &r.inputs {
                    inputs.row(vec![
                        rec.clone(),
                        i.role.clone(),
                        i.path.clone(),
                        i.bytes.to_string(),
                        i.sha256.clone(),
                    ]);
                }
            }
            Err(e) => s.push(w.note(p, &e)),
        }
    }
    let times = wall_times(dir, found, w);
    if !runs.rows.is_empty() {
        s.push(Block::Table(runs));
    }
    if !inputs.rows.is_empty() {
        s.push(Block::Table(inputs));
    }
    if !times.rows.is_empty() {
        s.push(Block::Table(times));
    }
    (!s.blocks.is_empty()).then_some(s)
}

/// Wall times recorded by cuts (`wall_s`) and fits (per model family).
fn wall_times(dir: &Path, found: &Found, w: &mut Ctx) -> Table {
    let mut t = Table::new("Wall times", &["output", "what", "wall time (s)"]);
    let mut read = |p: &Path| -> Option<Value> { serde_json::from_slice(&w.read(p).ok()?).ok() };
    for c in &found.cuts {
        let p = c.join("summary.json");
        if let Some(s) = read(&p).and_then(|v| v.get("wall_s").and_then(Value::as_f64)) {
            t.row(vec![shown(dir, &p), "cut".into(), num(s, 3)]);
        }
    }
    for p in &found.fit_reports {
        let fams = read(p)
            .and_then(|v| v.get("families").and_then(Value::as_array).cloned())
            .unwrap_or_default();
        for f in fams {
            if let (Some(name), Some(s)) = (
                f.get("family").and_then(Value::as_str),
                f.get("seconds").and_then(Value::as_f64),
            ) {
                t.row(vec![shown(dir, p), format!("fit {name}"), num(s, 3)]);
            }
        }
    }
    t
}
