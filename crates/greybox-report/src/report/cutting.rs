//! Cutting section, per cut: the summary, the force history with its averaged part, the
//! contact profiles along the rake face, μ over time per friction window, and the chip
//! (last state by temperature and plastic strain; frames when the cut drew them).

use super::page::{Block, Section, Table};
use super::scan::Found;
use super::{num, shown, svg_figure, Ctx};
use anyhow::{Context, Result};
use greybox_core::plot::{lines, Line};
use greybox_sim::steady_report::SteadyQuantity;
use serde::Deserialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// μ histories drawn per cut (windows evenly picked among those in contact).
const MAX_WINDOWS: usize = 8;

pub fn section(dir: &Path, found: &Found, w: &mut Ctx) -> Option<Section> {
    let mut s = Section::new("cutting", "Cutting");
    for cut in &found.cuts {
        {
            let r = cut_blocks(dir, cut, w);
            s.add_from(cut, r, w);
        }
    }
    (!s.blocks.is_empty()).then_some(s)
}

fn summary_table(v: &Value) -> Table {
    let f = |k: &str, digits: usize| {
        v.get(k)
            .and_then(Value::as_f64)
            .map(|x| num(x, digits))
            .unwrap_or_else(|| "n/a".into())
    };
    let int = |k: &str| {
        v.get(k)
            .map(|x| x.to_string())
            .unwrap_or_else(|| "n/a".into())
    };
    // a value with the half-width of its 95 % interval, where the cut gives one
    let pm = |k: &str, ci: &str, digits: usize| match v.get(ci).and_then(Value::as_f64) {
        Some(h) => format!("{} ± {}", f(k, digits), num(h, 2)),
        None => f(k, digits),
    };
    let mut t = Table::new("Summary", &["quantity", "value"]);
    let rests_on = v
        .pointer("/steady_state/rests_on")
        .and_then(Value::as_str)
        .unwrap_or("");
    let steady = match v.get("steady").and_then(Value::as_bool) {
        Some(true) => format!("from {} mm of cut: {rests_on}", f("steady_from_mm", 3)),
        Some(false) => format!(
            "no steady stretch; averaged from {} mm of cut",
            f("averaged_from_mm", 3)
        ),
        None => "n/a".into(),
    };
    let sure = match (
        v.get("sure").and_then(Value::as_bool),
        v.get("limit_reached").and_then(Value::as_bool),
    ) {
        (Some(true), _) => format!("yes, at {} mm of cut", f("sure_at_mm", 3)),
        (Some(false), Some(true)) => "no: the cut reached its length limit first".into(),
        (Some(false), _) => "no".into(),
        _ => "n/a".into(),
    };
    let mut rows: Vec<(&str, String)> = vec![
        (
            "friction law",
            v.get("law")
                .and_then(Value::as_str)
                .unwrap_or("n/a")
                .to_string(),
        ),
        (
            "cutting force F'c (N/mm, 95 % interval)",
            pm("cutting_force_n_per_mm", "cutting_force_ci95_n_per_mm", 4),
        ),
        (
            "feed force F'f (N/mm, 95 % interval)",
            pm("feed_force_n_per_mm", "feed_force_ci95_n_per_mm", 4),
        ),
        ("F'f / F'c", f("force_ratio", 3)),
        (
            "specific cutting force k_c (N/mm²)",
            f("specific_cutting_force_n_per_mm2", 4),
        ),
        ("chip thickness (mm)", f("chip_thickness_mm", 3)),
        (
            "chip compression ratio (95 % interval)",
            pm("compression_ratio", "compression_ratio_ci95", 3),
        ),
        ("shear angle (°)", f("shear_angle_deg", 3)),
        ("contact length (mm)", f("contact_length_mm", 3)),
        (
            "maximum temperature at the end (°C)",
            f("max_temperature_c", 4),
        ),
        (
            "peak temperature over the run (°C)",
            f("peak_temperature_c", 4),
        ),
        ("melting temperature (°C)", f("melt_temperature_c", 4)),
        ("steady stretch", steady),
        (
            "F'c drift across the stretch (N/mm, 95 % interval)",
            drift_cell(v, "cutting_force_n_per_mm"),
        ),
        (
            "F'f drift across the stretch (N/mm, 95 % interval)",
            drift_cell(v, "feed_force_n_per_mm"),
        ),
        ("intervals within the targets", sure),
        ("simulated cut length (mm)", f("simulated_cut_length_mm", 3)),
        ("particles", int("particles")),
        ("steps", int("steps")),
        ("energy balance error", f("energy_error", 3)),
        ("wall time (s)", f("wall_s", 3)),
    ];
    if let Some(d) = v.get("damage_at_end") {
        rows.push(("ductile damage at the end", damage_cell(d)));
    }
    for (k, val) in rows {
        t.row(vec![k.to_string(), val]);
    }
    t
}

/// How far damage went: the particles it initiated in and their mean and largest degradation.
fn damage_cell(d: &Value) -> String {
    let n = |k: &str| d.get(k).and_then(Value::as_u64);
    let x = |k: &str| d.get(k).and_then(Value::as_f64);
    match (
        n("initiated"),
        n("particles"),
        x("mean_degradation"),
        x("max_degradation"),
    ) {
        (Some(i), Some(p), Some(mean), Some(max)) => format!(
            "initiated in {i} of {p} particles; degradation there {} on average, {} at most",
            num(mean, 3),
            num(max, 3)
        ),
        _ => "n/a".into(),
    }
}

/// A force's change across the steady stretch with its 95 % interval, and whether it settled.
fn drift_cell(v: &Value, force: &str) -> String {
    let quantity = v
        .pointer(&format!("/steady_state/{force}"))
        .and_then(|q| SteadyQuantity::deserialize(q).ok());
    match quantity
        .as_ref()
        .map(|q| (q.drift, q.drift_ci95, q.drifting()))
    {
        Some((Some(d), Some(h), drifting)) => format!(
            "{} ± {}{}",
            num(d, 2),
            num(h, 2),
            if drifting {
                ": still drifting, the mean is the stretch's"
            } else {
                ": none seen"
            }
        ),
        _ => "n/a".into(),
    }
}

fn cut_blocks(dir: &Path, cut: &Path, w: &mut Ctx) -> Result<Vec<Block>> {
    let text = w.read_text(&cut.join("summary.json"))?;
    let v: Value = serde_json::from_str(&text).context("summary.json is not JSON")?;
    let name = shown(dir, cut);
    let name = if name.is_empty() {
        ".".to_string()
    } else {
        name
    };
    let mut out = vec![
        Block::Heading(format!("Cut {name}")),
        Block::Table(summary_table(&v)),
    ];
    let fig = |f: &str, caption: &str, w: &mut Ctx| -> Option<Block> {
        let p = cut.join(f);
        p.exists().then(|| svg_figure(dir, &p, caption, w))
    };
    let mut row: Vec<Block> = [
        (
            "forces.svg",
            "Forces per unit width over the cut; shaded: the part averaged",
        ),
        (
            "profile_stress.svg",
            "Contact pressure and shear stress along the rake face",
        ),
        (
            "profile_velocity.svg",
            "Sliding velocity along the rake face",
        ),
        (
            "profile_temperature.svg",
            "Contact temperature along the rake face",
        ),
        (
            "profile_mu.svg",
            "μ along the rake face: the law's value and τ/p",
        ),
    ]
    .iter()
    .filter_map(|(f, c)| fig(f, c, w))
    .collect();
    let hist = cut.join("mu_history.csv");
    if hist.exists() {
        match w.csv(&hist).and_then(mu_history) {
            Ok(svg) => row.push(Block::Figure {
                svg,
                caption: format!(
                    "μ over time in friction windows of the rake face ({})",
                    shown(dir, &hist)
                ),
            }),
            Err(e) => row.push(w.note(&hist, &e)),
        }
    }
    if !row.is_empty() {
        out.push(Block::Row(row));
    }
    let chips: Vec<Block> = [
        (
            "chip_temperature.svg",
            "The chip at the end of the run by temperature",
        ),
        (
            "chip_plastic_strain.svg",
            "The chip at the end of the run by equivalent plastic strain",
        ),
    ]
    .iter()
    .filter_map(|(f, c)| fig(f, c, w))
    .collect();
    out.extend(chips);
    if let Some(b) = frames(dir, &cut.join("frames"), w) {
        out.push(b);
    }
    Ok(out)
}

/// `frames/chip_NNN.svg` as one slider figure.
fn frames(dir: &Path, frames_dir: &Path, w: &mut Ctx) -> Option<Block> {
    let files = w.list(frames_dir, "svg");
    let mut svgs = Vec::new();
    for f in &files {
        match w.svg(f) {
            Ok(s) => svgs.push(s),
            Err(e) => {
                w.note(f, &e);
            }
        }
    }
    (!svgs.is_empty()).then(|| Block::Frames {
        caption: format!(
            "Chip formation: {} frames by temperature on one scale ({}); move the slider",
            svgs.len(),
            shown(dir, frames_dir)
        ),
        svgs,
    })
}

/// μ against time for up to [`MAX_WINDOWS`] rake-face windows, evenly picked by distance
/// from the edge.
fn mu_history(mut rdr: csv::Reader<impl std::io::Read>) -> Result<String> {
    let h = rdr.headers()?.clone();
    let col = |name: &str| {
        h.iter()
            .position(|c| c == name)
            .with_context(|| format!("no column '{name}'"))
    };
    let (ct, cw, cf, cd, cm) = (
        col("time_s")?,
        col("window")?,
        col("face")?,
        col("distance_from_edge_um")?,
        col("mu")?,
    );
    // window → (distance µm, times µs, μ)
    let mut series: BTreeMap<u64, (f64, Vec<f64>, Vec<f64>)> = BTreeMap::new();
    for (k, r) in rdr.records().enumerate() {
        let r = r.with_context(|| format!("line {}", k + 2))?;
        if &r[cf] != "rake" {
            continue;
        }
        let field = |c: usize| -> Result<f64> {
            r[c].trim()
                .parse::<f64>()
                .with_context(|| format!("line {}: column {}: expected a number", k + 2, &h[c]))
        };
        let e = series
            .entry(field(cw)? as u64)
            .or_insert((field(cd)?, Vec::new(), Vec::new()));
        e.1.push(field(ct)? * 1e6);
        e.2.push(field(cm)?);
    }
    let mut ws: Vec<(f64, Vec<f64>, Vec<f64>)> = series.into_values().collect();
    ws.sort_by(|a, b| a.0.total_cmp(&b.0));
    let step = ws.len().div_ceil(MAX_WINDOWS).max(1);
    let picked: Vec<&(f64, Vec<f64>, Vec<f64>)> = ws.iter().step_by(step).collect();
    let labels: Vec<String> = picked
        .iter()
        .map(|s| format!("{} µm from the edge", num(s.0, 3)))
        .collect();
    let palette = [
        "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf", "#7f7f7f",
    ];
    let ls: Vec<Line> = picked
        .iter()
        .zip(&labels)
        .enumerate()
        .map(|(k, (s, label))| Line {
            label,
            colour: palette[k % palette.len()],
            x: &s.1,
            y: &s.2,
        })
        .collect();
    anyhow::ensure!(!ls.is_empty(), "no rake-face windows in it");
    Ok(lines(
        "mu history per friction window",
        "time (µs)",
        "friction coefficient mu (-)",
        &ls,
        false,
        &[],
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damage_cell_says_how_far_damage_went() {
        let d = serde_json::json!({
            "particles": 1594, "initiated": 378, "mean_degradation": 0.818, "max_degradation": 0.99
        });
        assert_eq!(
            damage_cell(&d),
            format!(
                "initiated in 378 of 1594 particles; degradation there {} on average, {} at most",
                num(0.818, 3),
                num(0.99, 3)
            )
        );
        assert_eq!(damage_cell(&serde_json::json!({"particles": 3})), "n/a");
        let with = summary_table(&serde_json::json!({ "damage_at_end": d }));
        let without = summary_table(&serde_json::json!({}));
        assert_eq!(with.rows.len(), without.rows.len() + 1);
    }
}
