//! The article's learning protocol, made honest (digest §7):
//!
//! 1. per family, grid search by k-fold CV MSE on all rows → selected hyperparameters;
//! 2. the selected configuration refitted on all rows → the model;
//! 3. **training metrics** as the article reports them (MAE, MSE, MAPE with percentile
//!    bootstrap 95 % CIs over 1000 resamples, R²) — optimistic by construction;
//! 4. **held-out metrics** from nested CV (the grid search repeated inside every outer
//!    fold), with the same bootstrap CIs over the out-of-fold predictions;
//! 5. permutation importance (30 repeats, seed 42, R²) on the training data, as the article;
//! 6. a CV-conformal prediction interval from the selected configuration's out-of-fold
//!    residuals of step 1.

use crate::cv::{check_folds, grid_search, kfold_ids, nested_cv, CvResult, OuterFold};
use crate::importance::{permutation_importance, Importance};
use crate::metrics::{metrics_with_ci, Metrics};
use crate::regressor::{GridSearch, Train};
use crate::table::Dataset;
use greybox_core::count::Count;
use greybox_core::{Error, Result};
use greybox_model::interval::{conformal_half_width, IntervalMethod, PredictionInterval};
use greybox_model::modelfile::{FeatureRange, ModelFile, SCHEMA, SCHEMA_VERSION};
use greybox_model::{Family, Hyperparameters, Predictor};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

pub use crate::boost::BoostGrid;
pub use crate::forest::ForestGrid;
pub use crate::mlp::MlpGrid;
pub use crate::svr::SvrGrid;

/// [`Grids`] from the registry's entries: one field per family, its [`GridSearch::Grid`].
macro_rules! define_grids {
    ($($v:ident { name: $n:literal, title: $t:literal, grid: $g:ident, params: $p:ty },)+) => {
        /// All grids (study TOML `[fit.grid.*]`), one per family of the registry.
        #[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
        #[serde(deny_unknown_fields, default)]
        pub struct Grids {
            $(
                #[doc = concat!("`", $n, "`")]
                pub $g: <$p as GridSearch>::Grid,
            )+
        }

        impl Grids {
            /// Every candidate of one family's grid (unvalidated).
            fn candidates(&self, family: Family) -> Vec<Hyperparameters> {
                match family {
                    $(Family::$v => <$p as GridSearch>::candidates(&self.$g)
                        .into_iter()
                        .map(Hyperparameters::$v)
                        .collect(),)+
                }
            }
        }
    };
}
greybox_model::for_each_family!(define_grids);

impl Grids {
    /// Every candidate of one family, validated.
    pub fn expand(&self, family: Family) -> Result<Vec<Hyperparameters>> {
        let out = self.candidates(family);
        if out.is_empty() {
            return Err(Error::invalid(
                "grid",
                format!("the {} grid is empty", family.name()),
            ));
        }
        for hp in &out {
            hp.validate()?;
        }
        Ok(out)
    }
}

/// Cross-validation folds (outer and inner): at least two; at most one per row of any
/// dataset greybox is meant for.
pub type Folds = Count<2, 10_000>;
/// Bootstrap resamples of the 95 % CIs (1000 in the article); each costs a pass over the rows.
/// 0 skips them: the metrics stand without intervals, and say so.
pub type Resamples = Count<0, 100_000>;
/// Permutation-importance repeats (30 in the article); each holds a permuted column in memory.
/// 0 skips the importance: the report says it was skipped.
pub type Repeats = Count<0, 10_000>;

/// Protocol settings (study TOML `[fit]`). The counts are bounded types ([`Folds`],
/// [`Resamples`], [`Repeats`]): a study file or Python's JSON beyond a cap is refused when
/// read, with the range.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FitConfig {
    pub families: Vec<Family>,
    pub folds: Folds,
    pub inner_folds: Folds,
    pub seed: u64,
    pub bootstrap_resamples: Resamples,
    pub importance_repeats: Repeats,
    pub importance_seed: u64,
    pub interval_coverage: f64,
    /// Skip nested CV (the held-out estimate) — for quick looks only.
    pub skip_nested: bool,
    pub grid: Grids,
}

impl Default for FitConfig {
    fn default() -> Self {
        FitConfig {
            families: Family::ALL.to_vec(),
            folds: Folds::of(5),
            inner_folds: Folds::of(5),
            seed: 42,
            bootstrap_resamples: Resamples::of(1000),
            importance_repeats: Repeats::of(30),
            importance_seed: 42,
            interval_coverage: 0.95,
            skip_nested: false,
            grid: Grids::default(),
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    pub hyperparameters: String,
    pub cv_mse: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct HeldOut {
    /// Metrics of the pooled out-of-fold predictions of nested CV.
    pub metrics: Metrics,
    pub r2_per_fold: Vec<f64>,
    pub selected_per_fold: Vec<String>,
    /// Out-of-fold prediction of every row.
    pub predictions: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FamilyReport {
    pub family: Family,
    pub selected: Hyperparameters,
    pub selected_label: String,
    pub cv_mse: f64,
    pub grid: Vec<Candidate>,
    /// Metrics on the training data (the article's Table 7 — optimistic).
    pub training: Metrics,
    /// Predictions of the final model on the training rows.
    pub training_predictions: Vec<f64>,
    /// Metrics from nested cross-validation (held out).
    pub held_out: Option<HeldOut>,
    pub importance: Vec<Importance>,
    pub interval: PredictionInterval,
    pub seconds: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    pub source: String,
    pub n_rows: usize,
    pub features: Vec<String>,
    pub target: String,
    pub config: FitConfig,
    pub families: Vec<FamilyReport>,
}

/// Run the protocol for every configured family; returns the report and one model file each.
pub fn run_protocol(data: &Dataset, cfg: &FitConfig) -> Result<(FitReport, Vec<ModelFile>)> {
    let n = data.y.len();
    let ids = match &data.folds {
        Some(f) => f.clone(),
        None => {
            check_folds(n, cfg.folds.get())?;
            kfold_ids(n, cfg.folds.get(), cfg.seed)
        }
    };
    if !(cfg.interval_coverage > 0.0 && cfg.interval_coverage < 1.0) {
        return Err(Error::invalid("fit", "interval_coverage must be in (0, 1)"));
    }
    let names: Vec<String> = data.features.iter().map(|c| c.name.clone()).collect();
    // Families run concurrently (their jobs share one rayon pool, which evens out the long
    // SVR fits); every fit's seed is independent of scheduling, so results are identical.
    // progress: three stages per family (grid search, nested CV, importance)
    let progress =
        greybox_core::progress::task("fit", Some(3 * cfg.families.len() as u64), "stages");
    let per_family: Vec<(FamilyReport, ModelFile)> = cfg
        .families
        .par_iter()
        .map(|&family| run_family(data, cfg, &ids, &names, family, &progress))
        .collect::<Result<_>>()?;
    progress.finish("done");
    let (reports, files): (Vec<_>, Vec<_>) = per_family.into_iter().unzip();
    Ok((
        FitReport {
            source: data.source.clone(),
            n_rows: n,
            features: names,
            target: data.target.name.clone(),
            config: cfg.clone(),
            families: reports,
        },
        files,
    ))
}

/// Steps 1–6 for one family.
fn run_family(
    data: &Dataset,
    cfg: &FitConfig,
    ids: &[usize],
    names: &[String],
    family: Family,
    progress: &greybox_core::progress::Task,
) -> Result<(FamilyReport, ModelFile)> {
    let t0 = std::time::Instant::now();
    let grid = cfg.grid.expand(family)?;
    let Searched {
        results,
        best,
        model,
    } = search_and_fit(data, cfg, ids, &grid)?;
    let selected = grid[best].clone();
    let pred = model.predict(&data.x);
    let training = metrics_with_ci(&data.y, &pred, cfg.bootstrap_resamples.get(), cfg.seed);
    progress.inc(1);
    greybox_core::interrupt::check()?;
    let held_out = if cfg.skip_nested {
        None
    } else {
        Some(held_out(data, cfg, ids, &grid)?)
    };
    progress.inc(1);
    greybox_core::interrupt::check()?;
    let importance = permutation_importance(
        &model,
        &data.x,
        &data.y,
        names,
        cfg.importance_repeats.get(),
        cfg.importance_seed,
    );
    progress.inc(1);
    let interval = PredictionInterval {
        coverage: cfg.interval_coverage,
        half_width: conformal_half_width(&data.y, &results[best].oof, cfg.interval_coverage),
        method: IntervalMethod::CvConformal,
    };
    let report = FamilyReport {
        family,
        selected_label: selected.label(),
        selected: selected.clone(),
        cv_mse: results[best].mse,
        grid: grid
            .iter()
            .zip(&results)
            .map(|(h, r)| Candidate {
                hyperparameters: h.label(),
                cv_mse: r.mse,
            })
            .collect(),
        training,
        training_predictions: pred,
        held_out,
        importance,
        interval,
        seconds: t0.elapsed().as_secs_f64(),
    };
    let file = model_file(data, &report, model)?;
    Ok((report, file))
}

/// Step 1 and 2's outcome: the grid's CV results, the best candidate and its model refitted
/// on all rows.
struct Searched {
    results: Vec<CvResult>,
    best: usize,
    model: greybox_model::FittedModel,
}

/// Steps 1–2: grid search by k-fold CV, then the selected configuration fitted on all rows.
/// A one-candidate grid's final fit does not wait for its CV: both run at once (the same
/// fit, seed and data either way, so the same model).
fn search_and_fit(
    data: &Dataset,
    cfg: &FitConfig,
    ids: &[usize],
    grid: &[Hyperparameters],
) -> Result<Searched> {
    let fit_all = |h: &Hyperparameters| h.fit(&data.x, &data.y, cfg.seed);
    let (searched, early) = if grid.len() == 1 {
        let (s, m) = rayon::join(
            || grid_search(grid, &data.x, &data.y, ids, cfg.seed),
            || fit_all(&grid[0]),
        );
        (s, Some(m))
    } else {
        (grid_search(grid, &data.x, &data.y, ids, cfg.seed), None)
    };
    let (results, best) = searched?;
    let model = match early {
        Some(m) => m?,
        None => fit_all(&grid[best])?,
    };
    Ok(Searched {
        results,
        best,
        model,
    })
}

/// Step 4: held-out metrics from nested CV.
fn held_out(
    data: &Dataset,
    cfg: &FitConfig,
    ids: &[usize],
    grid: &[Hyperparameters],
) -> Result<HeldOut> {
    let (oof, folds): (Vec<f64>, Vec<OuterFold>) =
        nested_cv(grid, &data.x, &data.y, ids, cfg.inner_folds.get(), cfg.seed)?;
    Ok(HeldOut {
        metrics: metrics_with_ci(&data.y, &oof, cfg.bootstrap_resamples.get(), cfg.seed),
        r2_per_fold: folds.iter().map(|f| f.r2).collect(),
        selected_per_fold: folds.iter().map(|f| f.selected.label()).collect(),
        predictions: oof,
    })
}

/// The family's model file: the selected model with its training domain and interval, sealed.
fn model_file(
    data: &Dataset,
    report: &FamilyReport,
    model: greybox_model::FittedModel,
) -> Result<ModelFile> {
    ModelFile {
        schema: SCHEMA.into(),
        schema_version: SCHEMA_VERSION,
        family: report.family,
        hyperparameters: report.selected.clone(),
        features: data.features.clone(),
        target: data.target.clone(),
        training_domain: data
            .x
            .column_ranges()
            .into_iter()
            .map(|(min, max)| FeatureRange { min, max })
            .collect(),
        n_train: data.y.len(),
        prediction_interval: report.interval,
        held_out_r2: report.held_out.as_ref().map(|h| h.metrics.r2.value),
        model,
        force_to_pressure: None,
        provenance: None,
        content_hash: String::new(),
    }
    .seal()
}

/// The report as Markdown tables shaped like the article's Tables 7 and 8.
pub fn markdown(report: &FitReport) -> String {
    let fams = &report.families;
    let mut s = String::new();
    // names and paths from the user's files, escaped where they land in markdown
    let md = greybox_core::escape::markdown_text;
    s.push_str(&format!(
        "Dataset {}: {} rows, features {}, target {}.\n\n",
        md(&report.source),
        report.n_rows,
        report
            .features
            .iter()
            .map(|f| md(f))
            .collect::<Vec<_>>()
            .join(", "),
        md(&report.target)
    ));
    s.push_str("**Selected hyperparameters** (k-fold CV MSE):\n\n");
    table_head(&mut s, fams, "family");
    s.push_str("| selected |");
    for f in fams {
        s.push_str(&format!(
            " {} |",
            greybox_core::escape::markdown_text(&f.selected_label)
        ));
    }
    s.push_str("\n| CV MSE |");
    for f in fams {
        s.push_str(&format!(" {:.3e} |", f.cv_mse));
    }
    s.push_str("\n\n");
    s.push_str("**Training metrics** (as in the article's Table 7: on the training data, optimistic; 95 % bootstrap CIs):\n\n");
    table_head(&mut s, fams, "metric");
    metric_rows(&mut s, fams, &|f| Some(f.training));
    s.push_str("\n**Held-out metrics** (nested cross-validation; the honest estimate):\n\n");
    table_head(&mut s, fams, "metric");
    metric_rows(&mut s, fams, &|f| f.held_out.as_ref().map(|h| h.metrics));
    importance_and_interval(&mut s, report);
    s
}

/// A table's head: `title` and one column per family (its title).
fn table_head(s: &mut String, fams: &[FamilyReport], title: &str) {
    s.push_str(&format!("| {title} |"));
    for f in fams {
        s.push_str(&format!(" {} |", f.family.title()));
    }
    s.push_str("\n|---|");
    for _ in fams {
        s.push_str("---|");
    }
    s.push('\n');
}

/// MAE, MSE and MAPE with their CIs, then R², of the metrics `pick` gives per family
/// ("–" where none).
fn metric_rows(
    s: &mut String,
    fams: &[FamilyReport],
    pick: &dyn Fn(&FamilyReport) -> Option<Metrics>,
) {
    for (name, get) in [
        (
            "MAE",
            (|m: &Metrics| m.mae) as fn(&Metrics) -> crate::metrics::WithCi,
        ),
        ("MSE", |m: &Metrics| m.mse),
        ("MAPE", |m: &Metrics| m.mape),
    ] {
        s.push_str(&format!("| {name} |"));
        for f in fams {
            match pick(f) {
                Some(m) => {
                    let v = get(&m);
                    let cell = if name == "MSE" {
                        v.display(|x| format!("{x:.2e}"))
                    } else {
                        v.display(|x| format!("{x:.4}"))
                    };
                    s.push_str(&format!(" {cell} |"));
                }
                None => s.push_str(" – |"),
            }
        }
        s.push('\n');
    }
    s.push_str("| R² |");
    for f in fams {
        match pick(f) {
            Some(m) => s.push_str(&format!(" {:.4} |", m.r2.value)),
            None => s.push_str(" – |"),
        }
    }
    s.push('\n');
}

/// The permutation-importance table (Table 8) and the prediction intervals.
fn importance_and_interval(s: &mut String, report: &FitReport) {
    let fams = &report.families;
    s.push_str("\n**Permutation importance** (Table 8: R² drop, mean ± std over repeats):\n\n");
    if fams.iter().any(|f| f.importance.is_empty()) {
        s.push_str("skipped (`importance_repeats` 0)\n");
    } else {
        importance_rows(s, report);
    }
    interval_rows(s, report);
}

/// The importance table's rows, one per feature.
fn importance_rows(s: &mut String, report: &FitReport) {
    let fams = &report.families;
    table_head(s, fams, "feature");
    for (j, name) in report.features.iter().enumerate() {
        s.push_str(&format!(
            "| {} |",
            greybox_core::escape::markdown_text(name)
        ));
        for f in fams {
            let i = &f.importance[j];
            s.push_str(&format!(" {:.4} ± {:.4} |", i.mean, i.std));
        }
        s.push('\n');
    }
}

/// The prediction-interval table.
fn interval_rows(s: &mut String, report: &FitReport) {
    let fams = &report.families;
    s.push_str("\n**Prediction interval** (CV-conformal):\n\n");
    table_head(s, fams, "interval");
    s.push_str("| ± half-width |");
    for f in fams {
        s.push_str(&format!(
            " {:.4} ({:.0} %) |",
            f.interval.half_width,
            f.interval.coverage * 100.0
        ));
    }
    s.push('\n');
}
