//! `greybox fit`: the article's learning protocol with honest validation.

use crate::output::{print_json, stage_out_dir};
use crate::study::Study;
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_learn::mlp::Activation;
use greybox_learn::model::Family;
use greybox_learn::modelfile::{ForcePressure, ModelFile};
use greybox_learn::plot;
use greybox_learn::protocol::{markdown, run_protocol, FitConfig, FitReport};
use greybox_learn::svr::Kernel;
use greybox_learn::table::read_dataset;
use serde::Serialize;
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug, Clone)]
pub struct Args {
    /// Dataset CSV (e.g. from `greybox identify` or `greybox adhesive`).
    #[arg(long)]
    pub data: PathBuf,
    /// Target column.
    #[arg(long, default_value = "cof_apparent")]
    pub target: String,
    /// Feature columns, comma-separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "normal_force_N,sliding_velocity_m_per_min"
    )]
    pub features: Vec<String>,
    /// Study TOML with a [fit] section (grids, folds, seeds); flags override it.
    #[arg(long)]
    pub study: Option<PathBuf>,
    /// Model families, comma-separated (random-forest, svr, gradient-boosting, mlp).
    #[arg(long, value_delimiter = ',')]
    pub families: Option<Vec<String>>,
    /// Folds of the grid search and of the outer nested-CV loop.
    #[arg(long)]
    pub folds: Option<usize>,
    /// Folds of the inner nested-CV loop.
    #[arg(long)]
    pub inner_folds: Option<usize>,
    /// Integer column holding fold ids (replaces the seeded shuffled k-fold split).
    #[arg(long)]
    pub fold_column: Option<String>,
    /// Seed of folds and fits.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Bootstrap resamples for the 95 % CIs.
    #[arg(long)]
    pub bootstrap: Option<usize>,
    /// Permutation-importance repeats.
    #[arg(long)]
    pub importance_repeats: Option<usize>,
    /// Skip nested cross-validation (no held-out metrics; quick looks only).
    #[arg(long)]
    pub skip_nested: bool,
    /// Random-forest grid: n_estimators values.
    #[arg(long, value_delimiter = ',')]
    pub rf_n_estimators: Option<Vec<usize>>,
    /// SVR grid: C values.
    #[arg(long, value_delimiter = ',')]
    pub svr_c: Option<Vec<f64>>,
    /// SVR grid: kernels (linear, poly, rbf, sigmoid).
    #[arg(long, value_delimiter = ',')]
    pub svr_kernel: Option<Vec<String>>,
    /// SVR grid: epsilon values.
    #[arg(long, value_delimiter = ',')]
    pub svr_epsilon: Option<Vec<f64>>,
    /// Boosting grid: n_estimators values.
    #[arg(long, value_delimiter = ',')]
    pub gb_n_estimators: Option<Vec<usize>>,
    /// Boosting grid: max_depth values.
    #[arg(long, value_delimiter = ',')]
    pub gb_max_depth: Option<Vec<usize>>,
    /// Boosting grid: learning_rate values.
    #[arg(long, value_delimiter = ',')]
    pub gb_learning_rate: Option<Vec<f64>>,
    /// MLP grid: hidden layers, e.g. 64x32,32x16.
    #[arg(long, value_delimiter = ',')]
    pub mlp_hidden: Option<Vec<String>>,
    /// MLP grid: activations (relu, tanh).
    #[arg(long, value_delimiter = ',')]
    pub mlp_activation: Option<Vec<String>>,
    /// MLP grid: Adam learning rates.
    #[arg(long, value_delimiter = ',')]
    pub mlp_learning_rate: Option<Vec<f64>>,
    /// MLP epoch limit.
    #[arg(long)]
    pub mlp_max_epochs: Option<usize>,
    /// Output directory: report.json, report.md, models/, plots/.
    #[arg(long, default_value = "fit-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    /// Print the report as JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}

impl Args {
    /// Defaults for `data` → `out` (the article's grids and protocol), as the demo uses them.
    pub fn defaults(data: PathBuf, out: PathBuf) -> Self {
        Args {
            data,
            target: "cof_apparent".into(),
            features: vec!["normal_force_N".into(), "sliding_velocity_m_per_min".into()],
            study: None,
            families: None,
            folds: None,
            inner_folds: None,
            fold_column: None,
            seed: None,
            bootstrap: None,
            importance_repeats: None,
            skip_nested: false,
            rf_n_estimators: None,
            svr_c: None,
            svr_kernel: None,
            svr_epsilon: None,
            gb_n_estimators: None,
            gb_max_depth: None,
            gb_learning_rate: None,
            mlp_hidden: None,
            mlp_activation: None,
            mlp_learning_rate: None,
            mlp_max_epochs: None,
            out,
            force: false,
            json: false,
        }
    }
}

fn parse_list<T>(
    values: &[String],
    what: &str,
    expected: &str,
    parse: impl Fn(&str) -> Option<T>,
) -> Result<Vec<T>> {
    values
        .iter()
        .map(|v| parse(v).with_context(|| format!("unknown {what} '{v}'; expected {expected}")))
        .collect()
}

/// The protocol configuration: study [fit] section, then flags.
pub fn config(a: &Args) -> Result<FitConfig> {
    let mut c = match &a.study {
        Some(p) => Study::load(p)?.fit,
        None => FitConfig::default(),
    };
    if let Some(f) = &a.families {
        c.families = parse_list(
            f,
            "model family",
            "random-forest, svr, gradient-boosting or mlp",
            Family::parse,
        )?;
    }
    macro_rules! set {
        ($dst:expr, $src:expr) => {
            if let Some(v) = $src.clone() {
                $dst = v;
            }
        };
    }
    set!(c.folds, a.folds);
    set!(c.inner_folds, a.inner_folds);
    set!(c.seed, a.seed);
    set!(c.bootstrap_resamples, a.bootstrap);
    set!(c.importance_repeats, a.importance_repeats);
    c.skip_nested |= a.skip_nested;
    set!(c.grid.random_forest.n_estimators, a.rf_n_estimators);
    set!(c.grid.svr.c, a.svr_c);
    set!(c.grid.svr.epsilon, a.svr_epsilon);
    if let Some(k) = &a.svr_kernel {
        c.grid.svr.kernel = parse_list(k, "kernel", "linear, poly, rbf or sigmoid", |s| match s {
            "linear" => Some(Kernel::Linear),
            "poly" => Some(Kernel::Poly),
            "rbf" => Some(Kernel::Rbf),
            "sigmoid" => Some(Kernel::Sigmoid),
            _ => None,
        })?;
    }
    set!(c.grid.gradient_boosting.n_estimators, a.gb_n_estimators);
    set!(c.grid.gradient_boosting.max_depth, a.gb_max_depth);
    set!(c.grid.gradient_boosting.learning_rate, a.gb_learning_rate);
    if let Some(h) = &a.mlp_hidden {
        c.grid.mlp.hidden_layers = parse_list(
            h,
            "hidden layer spec",
            "sizes joined by x, e.g. 64x32",
            |s| s.split('x').map(|n| n.parse().ok()).collect(),
        )?;
    }
    if let Some(act) = &a.mlp_activation {
        c.grid.mlp.activation = parse_list(act, "activation", "relu or tanh", |s| match s {
            "relu" => Some(Activation::Relu),
            "tanh" => Some(Activation::Tanh),
            _ => None,
        })?;
    }
    set!(c.grid.mlp.learning_rate, a.mlp_learning_rate);
    set!(c.grid.mlp.base.max_epochs, a.mlp_max_epochs);
    if c.families.is_empty() {
        bail!("no model family selected");
    }
    Ok(c)
}

#[derive(Serialize)]
pub struct FitOutputs {
    pub report_json: String,
    pub report_md: String,
    pub models: Vec<String>,
    pub plots: Vec<String>,
}

/// Run the protocol and write every output into `out`.
pub fn fit(a: &Args) -> Result<(FitReport, FitOutputs)> {
    let cfg = config(a)?;
    let data = read_dataset(&a.data, &a.features, &a.target, a.fold_column.as_deref())?;
    for w in &data.warnings {
        eprintln!("warning: {w}");
    }
    let mut inputs = vec![("--data", a.data.as_path())];
    if let Some(s) = &a.study {
        inputs.push(("--study", s.as_path()));
    }
    let staged = stage_out_dir(&a.out, a.force, &inputs)?;
    let (report, mut models) = run_protocol(&data, &cfg)?;
    // what a law built from a bare model needs, and where the model came from
    let force_to_pressure = greybox_core::dataset::FrictionDataset::read_csv(&a.data)
        .ok()
        .and_then(|ds| ForcePressure::of_dataset(&ds));
    let provenance = crate::output::provenance(&inputs)?.with_seed(cfg.seed);
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
    Ok((report, outputs))
}

fn write_outputs(
    out: &Path,
    report: &FitReport,
    models: &[ModelFile],
    data: &greybox_learn::table::Dataset,
) -> Result<FitOutputs> {
    let report_json = out.join("report.json");
    write_string_atomic(&report_json, &serde_json::to_string_pretty(report)?)?;
    let report_md = out.join("report.md");
    write_string_atomic(
        &report_md,
        &format!("# greybox fit report\n\n{}", markdown(report)),
    )?;
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
            &report.target,
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
                greybox_learn::Predictor::predict_one(&m.model, &row)
            };
            let pts: Vec<(f64, f64)> = (0..data.x.n_rows)
                .map(|i| (data.x.get(i, 0), data.x.get(i, 1)))
                .collect();
            let svg = plot::surface(
                &format!("{} — {} surface", fam.family.title(), report.target),
                &report.features[0],
                &report.features[1],
                &report.target,
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

pub fn run(a: Args) -> Result<()> {
    let (report, outputs) = fit(&a)?;
    if a.json {
        return print_json(&report);
    }
    println!("{}", markdown(&report));
    for f in &report.families {
        println!("{}: {:.1} s", f.family.name(), f.seconds);
    }
    println!(
        "wrote {}, {}, {} models, {} plots",
        outputs.report_json,
        outputs.report_md,
        outputs.models.len(),
        outputs.plots.len()
    );
    Ok(())
}
