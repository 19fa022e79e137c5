//! `greybox fit`: the article's learning protocol with honest validation.

use crate::output::print_json;
use anyhow::{Context, Result};
use greybox_learn::model::Family;
use greybox_learn::protocol::FitConfig;
use greybox_pipeline::fit::{fit, FitOptions, FitResult};
use greybox_pipeline::study::Study;
use std::path::PathBuf;

#[derive(clap::Args, Debug, Clone)]
pub struct Args {
    /// Dataset CSV (e.g. from `greybox identify` or `greybox adhesive`).
    #[arg(long)]
    pub data: PathBuf,
    /// Target column [default: cof_adhesive where the dataset has it, else cof_apparent].
    #[arg(long)]
    pub target: Option<String>,
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

/// A value of a lowercase-named enum (kernels, activations) by its name in files.
fn by_name<T: serde::de::DeserializeOwned>(name: &str) -> Option<T> {
    serde_json::from_value(serde_json::Value::String(name.into())).ok()
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
        c.grid.svr.kernel = parse_list(k, "kernel", "linear, poly, rbf or sigmoid", by_name)?;
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
        c.grid.mlp.activation = parse_list(act, "activation", "relu or tanh", by_name)?;
    }
    set!(c.grid.mlp.learning_rate, a.mlp_learning_rate);
    set!(c.grid.mlp.base.max_epochs, a.mlp_max_epochs);
    Ok(c)
}

impl Args {
    /// The library's options for these flags.
    pub fn options(&self) -> Result<FitOptions> {
        Ok(FitOptions {
            data: self.data.clone(),
            target: match &self.target {
                Some(t) => t.clone(),
                None => greybox_pipeline::fit::default_target(&self.data)?,
            },
            features: self.features.clone(),
            fold_column: self.fold_column.clone(),
            config: config(self)?,
            study: self.study.clone(),
            out: self.out.clone(),
            force: self.force,
        })
    }
}

pub fn run(a: Args) -> Result<()> {
    let FitResult {
        report,
        outputs,
        warnings,
    } = fit(&a.options()?)?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    if a.json {
        return print_json(&report);
    }
    print!("{}", greybox_pipeline::text::fit(&report, &outputs));
    Ok(())
}
