//! Stage 4: the article's learning protocol with honest validation — grid search, nested
//! cross-validation, bootstrap CIs, permutation importance — and its outputs (reports,
//! model files, plots).

use crate::output::{provenance, stage_out_dir};
use anyhow::{bail, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::plot;
use greybox_learn::protocol::{markdown, run_protocol, FitConfig, FitReport};
use greybox_learn::table::read_dataset;
use greybox_model::modelfile::{ForcePressure, ModelFile};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Options of [`fit`].
#[derive(Debug, Clone)]
pub struct FitOptions {
    /// Dataset CSV (from identification or the adhesive correction).
    pub data: PathBuf,
    /// Target column.
    pub target: String,
    /// Feature columns.
    pub features: Vec<String>,
    /// Integer column holding fold ids (replaces the seeded shuffled k-fold split).
    pub fold_column: Option<String>,
    /// Families, grids, folds, seeds.
    pub config: FitConfig,
    /// The study file the configuration came from, recorded in the provenance.
    pub study: Option<PathBuf>,
    /// Output directory: report.json, report.md, models/, plots/.
    pub out: PathBuf,
    /// Replace an existing, non-empty `out` (swapped out whole once the fit is complete).
    pub force: bool,
}

/// The target column when none is named: the adhesive coefficient where the dataset has it
/// (after the ploughing correction, what the article's models learn), else the apparent one.
pub fn default_target(data: &Path) -> Result<String> {
    let header = greybox_core::csvutil::Header::read(data)?;
    Ok(if header.find("cof_adhesive").is_some() {
        "cof_adhesive"
    } else {
        "cof_apparent"
    }
    .to_string())
}

/// The feature columns when none are named: normal force and sliding velocity.
pub const DEFAULT_FEATURES: [&str; 2] = ["normal_force_N", "sliding_velocity_m_per_min"];

impl FitOptions {
    /// The article's protocol and grids on `target` against normal force and sliding
    /// velocity, from `data` into `out`.
    pub fn article(data: PathBuf, target: &str, out: PathBuf) -> Self {
        FitOptions {
            data,
            target: target.into(),
            features: DEFAULT_FEATURES.map(String::from).to_vec(),
            fold_column: None,
            config: FitConfig::default(),
            study: None,
            out,
            force: false,
        }
    }
}

/// The files a fit wrote.
#[derive(Debug, Clone, Serialize)]
pub struct FitOutputs {
    pub report_json: String,
    pub report_md: String,
    pub models: Vec<String>,
    pub plots: Vec<String>,
}

/// What [`fit`] gives back.
pub struct FitResult {
    pub report: FitReport,
    pub outputs: FitOutputs,
    /// Warnings about the dataset (e.g. duplicate rows), one sentence each.
    pub warnings: Vec<String>,
}

/// Run the protocol and write every output into `out`.
pub fn fit(a: &FitOptions) -> Result<FitResult> {
    let cfg = &a.config;
    if cfg.families.is_empty() {
        bail!("no model family selected");
    }
    let data = read_dataset(&a.data, &a.features, &a.target, a.fold_column.as_deref())?;
    let mut inputs = vec![("data", a.data.as_path())];
    if let Some(s) = &a.study {
        inputs.push(("study", s.as_path()));
    }
    let staged = stage_out_dir(&a.out, a.force, &inputs)?;
    let (report, mut models) = run_protocol(&data, cfg)?;
    greybox_core::interrupt::check()?;
    // what a law built from a bare model needs, and where the model came from
    let force_to_pressure = greybox_core::dataset::FrictionDataset::read_csv(&a.data)
        .ok()
        .and_then(|ds| ForcePressure::of_dataset(&ds));
    let provenance = provenance(&inputs)?.with_seed(cfg.seed);
    for m in models.iter_mut() {
        m.force_to_pressure = force_to_pressure;
        m.provenance = Some(provenance.clone());
        *m = m.clone().seal()?;
    }
    let written = write_outputs(staged.path(), &report, &models, &data)?;
    provenance.write_into(staged.path())?;
    let shown = |v: &[String]| v.iter().map(|p| staged.shown_str(p)).collect();
    let outputs = FitOutputs {
        report_json: staged.shown_str(&written.report_json),
        report_md: staged.shown_str(&written.report_md),
        models: shown(&written.models),
        plots: shown(&written.plots),
    };
    staged.commit()?;
    Ok(FitResult {
        report,
        outputs,
        warnings: data.warnings,
    })
}

/// Write the fit's report into `out` as `report.json` and `report.md`; their paths.
pub fn write_report(out: &Path, report: &FitReport) -> Result<(PathBuf, PathBuf)> {
    let report_json = out.join("report.json");
    write_string_atomic(&report_json, &serde_json::to_string_pretty(report)?)?;
    let report_md = out.join("report.md");
    write_string_atomic(
        &report_md,
        &format!("# greybox fit report\n\n{}", markdown(report)),
    )?;
    Ok((report_json, report_md))
}

fn write_outputs(
    out: &Path,
    report: &FitReport,
    models: &[ModelFile],
    data: &greybox_learn::table::Dataset,
) -> Result<FitOutputs> {
    let (report_json, report_md) = write_report(out, report)?;
    let mut model_paths = Vec::new();
    let mut plots = Vec::new();
    for (fam, m) in report.families.iter().zip(models) {
        let p = out
            .join("models")
            .join(format!("{}.json", fam.family.name()));
        m.save(&p)?;
        model_paths.push(p.display().to_string());
        let mut series: Vec<(&str, &str, &[f64], &[f64])> = vec![(
            "training (final model)",
            "#1f77b4",
            &data.y,
            &fam.training_predictions,
        )];
        if let Some(h) = &fam.held_out {
            series.push(("held out (nested CV)", "#d62728", &data.y, &h.predictions));
        }
        let svg = plot::predicted_vs_measured(
            &format!("{} — {}", fam.family.title(), report.target),
            &format!("{} (-)", report.target),
            &series,
        );
        let p = out
            .join("plots")
            .join(format!("{}-predicted-vs-measured.svg", fam.family.name()));
        write_string_atomic(&p, &svg)?;
        plots.push(p.display().to_string());
        if data.x.n_cols >= 2 {
            let ranges = data.x.column_ranges();
            let medians: Vec<f64> = (0..data.x.n_cols)
                .map(|j| {
                    let mut c = data.x.column(j);
                    c.sort_by(f64::total_cmp);
                    c[c.len() / 2]
                })
                .collect();
            let f = |u: f64, v: f64| {
                let mut row = medians.clone();
                row[0] = u;
                row[1] = v;
                greybox_model::Predictor::predict_one(&m.model, &row)
            };
            let pts: Vec<(f64, f64)> = (0..data.x.n_rows)
                .map(|i| (data.x.get(i, 0), data.x.get(i, 1)))
                .collect();
            let svg = plot::surface(
                &format!("{} — {} surface", fam.family.title(), report.target),
                &report.features[0],
                &report.features[1],
                &format!("{} (-)", report.target),
                ranges[0],
                ranges[1],
                &f,
                &pts,
            );
            let p = out
                .join("plots")
                .join(format!("{}-surface.svg", fam.family.name()));
            write_string_atomic(&p, &svg)?;
            plots.push(p.display().to_string());
        }
    }
    Ok(FitOutputs {
        report_json: report_json.display().to_string(),
        report_md: report_md.display().to_string(),
        models: model_paths,
        plots,
    })
}
