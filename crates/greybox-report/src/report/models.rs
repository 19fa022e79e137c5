//! Models section: the article-style tables (training metrics as its Table 7, held-out
//! metrics of nested cross-validation beside them), permutation importance,
//! predicted-against-measured plots, and each friction law's μ surface with the training
//! domain drawn in and the physics-based law outside it.

use super::page::{Block, Section, Table};
use super::scan::Found;
use super::{num, shown, svg_figure, Ctx};
use anyhow::{Context, Result};
use greybox_core::plot::{heatmap, Heatmap};
use greybox_core::ContactState;
use greybox_friction::spec::LawSpec;
use greybox_learn::metrics::WithCi;
use greybox_learn::protocol::FitReport;
use std::path::Path;

pub fn section(dir: &Path, found: &Found, w: &mut Ctx) -> Option<Section> {
    let mut s = Section::new("models", "Models");
    for p in &found.fit_reports {
        {
            let r = fit_blocks(dir, p, w);
            s.add_from(p, r, w);
        }
    }
    let mut seen = Vec::new();
    for p in &found.laws {
        // the same law copied beside other outputs is drawn once
        let bytes = match w.read(p) {
            Ok(b) => b,
            Err(e) => {
                s.push(w.note(p, &e));
                continue;
            }
        };
        let digest = greybox_core::provenance::sha256_bytes(&bytes);
        if seen.contains(&digest) {
            continue;
        }
        seen.push(digest);
        match law_block(dir, p, &bytes) {
            Ok(b) => s.push(b),
            Err(e) => s.push(w.note(p, &e)),
        }
    }
    (!s.blocks.is_empty()).then_some(s)
}

/// `value [low, high]`.
fn with_ci(m: &WithCi, digits: usize) -> String {
    m.display(|x| num(x, digits))
}

/// A fit report's blocks: what was fitted, the training, held-out and importance tables,
/// and the predicted-against-measured plots beside it.
fn fit_blocks(dir: &Path, p: &Path, w: &mut Ctx) -> Result<Vec<Block>> {
    let text = w.read_text(p)?;
    let r: FitReport = serde_json::from_str(&text).context("not a greybox fit report")?;
    let name = shown(dir, p);
    let mut out = vec![
        Block::Heading(format!("Fit {name}")),
        Block::Text(format!(
            "{} rows of {}; features: {}; target: {}; {}-fold cross-validation, seed {}.",
            r.n_rows,
            r.source,
            r.features.join(", "),
            r.target,
            r.config.folds,
            r.config.seed
        )),
    ];
    out.push(Block::Table(training_table(&r)));
    for t in [held_out_table(&r), importance_table(&r)] {
        if !t.rows.is_empty() {
            out.push(Block::Table(t));
        }
    }
    let figures = predicted_figures(dir, p, &r, w);
    if !figures.is_empty() {
        out.push(Block::Row(figures));
    }
    Ok(out)
}

/// The metrics on the training data, one row per family (the article's Table 7).
fn training_table(r: &FitReport) -> Table {
    let mut train = Table::new(
        "Training data (optimistic, as the article's Table 7)",
        &[
            "model",
            "R²",
            "MAE",
            "MSE",
            "MAPE (%)",
            "selected hyper-parameters",
        ],
    );
    for f in &r.families {
        train.row(vec![
            f.family.name().to_string(),
            num(f.training.r2.value, 4),
            num(f.training.mae.value, 3),
            num(f.training.mse.value, 3),
            num(100.0 * f.training.mape.value, 3),
            f.selected_label.clone(),
        ]);
    }
    train
}

/// The held-out metrics of nested cross-validation with their bootstrap intervals, one row
/// per family that has them (none when the fit skipped them).
fn held_out_table(r: &FitReport) -> Table {
    let mut held = Table::new(
        "Held out: nested cross-validation, with 95 % bootstrap intervals",
        &[
            "model",
            "R²",
            "MAE",
            "MAPE (%)",
            "R² per fold",
            "interval ± (coverage)",
            "fit time (s)",
        ],
    );
    for f in &r.families {
        let Some(h) = &f.held_out else { continue };
        let (lo, hi) = h
            .r2_per_fold
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(*v), b.max(*v))
            });
        held.row(vec![
            f.family.name().to_string(),
            with_ci(&h.metrics.r2, 4),
            with_ci(&h.metrics.mae, 3),
            with_ci(&h.metrics.mape.scaled(100.0), 3),
            format!("{} … {}", num(lo, 3), num(hi, 3)),
            format!(
                "{} ({} %)",
                num(f.interval.half_width, 3),
                num(100.0 * f.interval.coverage, 3)
            ),
            num(f.seconds, 3),
        ]);
    }
    held
}

/// Permutation importance (increase of the MSE when a feature is shuffled), one row per
/// family and feature.
fn importance_table(r: &FitReport) -> Table {
    let mut imp = Table::new(
        "Permutation importance (increase of MSE when a feature is shuffled)",
        &["model", "feature", "mean", "std"],
    );
    for f in &r.families {
        for i in &f.importance {
            imp.row(vec![
                f.family.name().to_string(),
                i.feature.clone(),
                num(i.mean, 3),
                num(i.std, 3),
            ]);
        }
    }
    imp
}

/// The predicted-against-measured plots of the fit report at `p` (in `plots/` beside it),
/// one per family whose plot is there.
fn predicted_figures(dir: &Path, p: &Path, r: &FitReport, w: &mut Ctx) -> Vec<Block> {
    let plots = p.parent().unwrap_or(dir).join("plots");
    r.families
        .iter()
        .map(|f| plots.join(format!("{}-predicted-vs-measured.svg", f.family.name())))
        .filter(|f| f.exists())
        .map(|f| svg_figure(dir, &f, "Predicted against measured", w))
        .collect()
}

/// Where the law's learned part was fitted: a grey-box law is defined everywhere (its
/// `domain` is `None`), its inner law's domain is the box that matters here.
fn training_domain(
    p: &Path,
    text: &[u8],
    law: &dyn greybox_core::FrictionLaw,
) -> Result<Option<greybox_core::law::ValidityDomain>> {
    if let Ok(LawSpec::GreyBox { inner, .. }) = serde_json::from_slice::<LawSpec>(text) {
        let base = p.parent().unwrap_or(Path::new("."));
        return Ok(inner.build(base)?.domain());
    }
    Ok(law.domain())
}

/// μ over (pressure, velocity) from 0 to 1.6× the domain's upper ends, the domain boxed.
fn law_block(dir: &Path, p: &Path, text: &[u8]) -> Result<Block> {
    let law = greybox_friction::spec::load_law(p)?;
    let name = shown(dir, p);
    let Some(d) = training_domain(p, text, law.as_ref())? else {
        return Ok(Block::Text(format!(
            "{name}: law {} states no training domain; its μ does not depend on where it was measured.",
            law.name()
        )));
    };
    let t = d
        .temperature_k
        .map(|r| 0.5 * (r.min + r.max))
        .unwrap_or(293.15);
    let (p_lo, p_hi) = (d.pressure_pa.min * 1e-6, d.pressure_pa.max * 1e-6);
    let (v_lo, v_hi) = (
        d.sliding_velocity_m_s.min * 60.0,
        d.sliding_velocity_m_s.max * 60.0,
    );
    let f = |pmpa: f64, vmin: f64| {
        let mut s = ContactState::new(pmpa * 1e6, vmin / 60.0);
        s.temperature_k = t;
        law.mu(&s)
    };
    let svg = heatmap(&Heatmap {
        title: "Friction law: mu over pressure and velocity",
        x_label: "contact pressure (MPa)",
        y_label: "sliding velocity (m/min)",
        z_label: "mu (-)",
        x_range: (0.0, 1.6 * p_hi),
        y_range: (0.0, 1.6 * v_hi),
        background: Some(&f),
        points: &[],
        point_values: None,
        boxes: &[((p_lo, p_hi), (v_lo, v_hi), "training domain")],
    });
    Ok(Block::Figure {
        svg,
        caption: format!(
            "{name}: {} at {} °C. Inside the dashed box the learned model (fitted there); outside it the law's physics-based part takes over.",
            law.name(),
            num(t - 273.15, 3)
        ),
    })
}
