//! Friction-data section: μ_app and μ_adh over (Hertz pressure, sliding velocity) at the
//! measured points, and the ploughing correction per load.

use super::page::{Block, Section, Table};
use super::scan::Found;
use super::{num, shown, Ctx};
use anyhow::{Context, Result};
use greybox_contact::ploughing::Correction;
use greybox_core::dataset::FrictionDataset;
use greybox_core::plot::{heatmap, lines, Heatmap, Line};
use std::path::Path;

pub fn section(dir: &Path, found: &Found, w: &mut Ctx) -> Option<Section> {
    let mut s = Section::new("friction-data", "Friction data");
    for p in &found.datasets {
        let r = w.admit(p).and_then(|()| dataset_blocks(dir, p));
        s.add_from(p, r, w);
    }
    for p in &found.corrections {
        let r = w.read_text(p).and_then(|t| correction_blocks(dir, p, &t));
        s.add_from(p, r, w);
    }
    (!s.blocks.is_empty()).then_some(s)
}

/// (min, max) padded by 5 % of the span.
fn padded(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let pad = ((hi - lo) * 0.05).max(hi.abs() * 1e-3).max(1e-9);
    (lo - pad, hi + pad)
}

fn dataset_blocks(dir: &Path, p: &Path) -> Result<Vec<Block>> {
    let ds = FrictionDataset::read_csv(p)?;
    anyhow::ensure!(!ds.records.is_empty(), "no rows");
    let name = shown(dir, p);
    let pts: Vec<(f64, f64)> = ds
        .records
        .iter()
        .map(|r| (r.hertz_pressure_pa * 1e-6, r.sliding_velocity_m_s * 60.0))
        .collect();
    let xr = padded(pts.iter().map(|p| p.0));
    let yr = padded(pts.iter().map(|p| p.1));
    let map = |title: &str, z_label: &str, values: &[f64]| -> String {
        heatmap(&Heatmap {
            title,
            x_label: "Hertz contact pressure (MPa)",
            y_label: "sliding velocity (m/min)",
            z_label,
            x_range: xr,
            y_range: yr,
            background: None,
            points: &pts,
            point_values: Some(values),
            boxes: &[],
        })
    };
    let app: Vec<f64> = ds.records.iter().map(|r| r.cof_apparent).collect();
    let mut figures = vec![Block::Figure {
        svg: map("Apparent friction coefficient", "mu_app (-)", &app),
        caption: format!("μ_app per plateau at its measured load and planned speed ({name})"),
    }];
    let adh: Option<Vec<f64>> = ds.records.iter().map(|r| r.cof_adhesive).collect();
    if let Some(adh) = &adh {
        figures.push(Block::Figure {
            svg: map("Adhesive friction coefficient", "mu_adh (-)", adh),
            caption: format!("μ_adh = μ_app − μ_ploughing per plateau ({name})"),
        });
    }
    let mut pins: Vec<u32> = ds.records.iter().map(|r| r.pin).collect();
    pins.sort_unstable();
    pins.dedup();
    let range = |v: &[f64]| {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(*x), b.max(*x))
            });
        format!("{} … {}", num(lo, 3), num(hi, 3))
    };
    let mut t = Table::new(
        "Summary",
        &[
            "rows",
            "pins",
            "pressure (MPa)",
            "velocity (m/min)",
            "mu_app",
            "mu_adh",
            "non-stationary plateaus",
        ],
    );
    t.row(vec![
        ds.records.len().to_string(),
        pins.len().to_string(),
        range(&pts.iter().map(|p| p.0).collect::<Vec<_>>()),
        range(&pts.iter().map(|p| p.1).collect::<Vec<_>>()),
        range(&app),
        adh.as_deref().map(range).unwrap_or_else(|| "—".into()),
        ds.records
            .iter()
            .filter(|r| !r.stationary)
            .count()
            .to_string(),
    ]);
    Ok(vec![
        Block::Heading(format!("Dataset {name}")),
        Block::Table(t),
        Block::Row(figures),
    ])
}

fn correction_blocks(dir: &Path, p: &Path, text: &str) -> Result<Vec<Block>> {
    let c: Correction = serde_json::from_str(text).context("not a ploughing correction")?;
    let name = shown(dir, p);
    let mut t = Table::new(
        &format!("Ploughing correction per load ({name})"),
        &[
            "normal force (N)",
            "track width (µm)",
            "depth (µm)",
            "mu_ploughing (-)",
        ],
    );
    for l in &c.per_load {
        t.row(vec![
            num(l.normal_force_n, 4),
            num(l.width_um, 4),
            num(l.depth_um, 3),
            num(l.mu_plough, 3),
        ]);
    }
    let f: Vec<f64> = c.per_load.iter().map(|l| l.normal_force_n).collect();
    let mu: Vec<f64> = c.per_load.iter().map(|l| l.mu_plough).collect();
    let svg = lines(
        "Ploughing share per load",
        "normal force (N)",
        "mu_ploughing (-)",
        &[Line {
            label: "mu_ploughing",
            colour: "#1f77b4",
            x: &f,
            y: &mu,
        }],
        false,
        &[],
    );
    Ok(vec![
        Block::Heading("Ploughing correction".into()),
        Block::Text(format!(
            "{}; pin tip radius {} mm; mean share of μ_app: {} %.",
            c.method,
            num(c.pin_tip_radius_mm, 3),
            num(c.mean_reduction_percent, 3)
        )),
        Block::Row(vec![
            Block::Table(t),
            Block::Figure {
                svg,
                caption: format!("μ_ploughing against the normal force ({name})"),
            },
        ]),
    ])
}
