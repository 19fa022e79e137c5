//! Rig dynamics and wear: the impact-hammer characterisation (resonances per load, FRF and
//! coherence plots) and the Archard wear rates of the wear tests.

use super::page::{Block, Section, Table};
use super::scan::Found;
use super::{num, shown, svg_figure, Ctx};
use anyhow::{Context, Result};
use serde_json::Value;
use std::path::Path;

pub fn section(dir: &Path, found: &Found, w: &mut Ctx) -> Option<Section> {
    let mut s = Section::new("rig", "Rig dynamics and wear");
    for p in &found.characterizations {
        {
            let r = dynamics_blocks(dir, p, w);
            s.add_from(p, r, w);
        }
    }
    for p in &found.wear_tests {
        match w.admit(p).and_then(|()| wear_table(dir, p)) {
            Ok(t) => s.push(Block::Table(t)),
            Err(e) => s.push(w.note(p, &e)),
        }
    }
    (!s.blocks.is_empty()).then_some(s)
}

fn dynamics_blocks(dir: &Path, p: &Path, w: &mut Ctx) -> Result<Vec<Block>> {
    let v: Value = serde_json::from_slice(&w.read(p)?).context("not JSON")?;
    let loads = v
        .get("loads")
        .and_then(Value::as_array)
        .context("no 'loads' list")?;
    let mut t = Table::new(
        &format!("Resonances per static load ({})", shown(dir, p)),
        &[
            "load (N)",
            "impacts used",
            "usable up to (Hz)",
            "resonance (Hz)",
            "damping ratio",
        ],
    );
    let f = |v: &Value, k: &str, d: usize| {
        v.get(k)
            .and_then(Value::as_f64)
            .map(|x| num(x, d))
            .unwrap_or_else(|| "n/a".into())
    };
    for l in loads {
        let res = l
            .get("resonances")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        let first = res.first();
        t.row(vec![
            f(l, "load_n", 4),
            l.get("impacts_used")
                .map(|v| v.to_string())
                .unwrap_or_default(),
            f(l, "usable_max_hz", 4),
            first
                .map(|r| f(r, "frequency_hz", 4))
                .unwrap_or_else(|| "none found".into()),
            first.map(|r| f(r, "damping", 3)).unwrap_or_default(),
        ]);
    }
    let mut out = vec![Block::Heading("Rig dynamics".into()), Block::Table(t)];
    if let Some(check) = v.get("excitation_check").and_then(Value::as_object) {
        let mut t = Table::new(
            "Check against the campaign's excitation (spindle harmonics below the first resonance)",
            &["quantity", "value"],
        );
        for (k, val) in check {
            let shown = match val.as_f64() {
                Some(x) if !val.is_u64() => num(x, 4),
                _ => val.to_string(),
            };
            t.row(vec![k.replace('_', " "), shown]);
        }
        out.push(Block::Table(t));
    }
    let d = p.parent().unwrap_or(dir);
    let figs: Vec<Block> = [
        ("frf_magnitude.svg", "Frequency response magnitude per load"),
        ("coherence.svg", "Coherence of the impacts per load"),
    ]
    .iter()
    .map(|(f, c)| (d.join(f), c))
    .filter(|(f, _)| f.exists())
    .map(|(f, c)| svg_figure(dir, &f, c, w))
    .collect();
    if !figs.is_empty() {
        out.push(Block::Row(figs));
    }
    Ok(out)
}

fn wear_table(dir: &Path, p: &Path) -> Result<Table> {
    let tests = greybox_contact::wear::read_wear_tests(p)?;
    let mut t = Table::new(
        &format!("Wear tests: Archard specific wear rate ({})", shown(dir, p)),
        &[
            "pin",
            "normal force (N)",
            "velocity (m/min)",
            "duration (s)",
            "k (1e-7 mm³/(N·m))",
            "mean depth (µm)",
        ],
    );
    for w in tests {
        t.row(vec![
            w.pin,
            num(w.normal_force_n, 4),
            num(w.velocity_m_per_min, 3),
            num(w.duration_s, 4),
            num(w.k_1e7, 3),
            num(w.mean_depth_um, 3),
        ]);
    }
    Ok(t)
}
