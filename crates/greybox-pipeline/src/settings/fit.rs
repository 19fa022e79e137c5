//! The settings of one fit: the dataset, the columns, and overrides of the study's `[fit]`
//! section (families, folds, seeds, grids).
//!
//! ```
//! use greybox_pipeline::settings::fit::FitSettings;
//! use greybox_learn::protocol::FitConfig;
//! let s: FitSettings = greybox_pipeline::settings::from_json("fit",
//!     r#"{"folds": 3, "svr_kernel": ["rbf"], "mlp_hidden": ["8x4"]}"#)?;
//! let mut c = FitConfig::default();
//! s.apply(&mut c);
//! assert_eq!((c.folds.get(), c.grid.mlp.hidden_layers.clone()), (3, vec![vec![8, 4]]));
//! // a choice is typed where it is read: a kernel or a layer spec refused by name
//! let bad = greybox_pipeline::settings::from_json::<FitSettings>("fit",
//!     r#"{"svr_kernel": ["rbf", "gauss"]}"#).unwrap_err();
//! assert!(format!("{bad:#}").starts_with("fit.svr_kernel: 'gauss' is not one of linear"));
//! let bad = greybox_pipeline::settings::from_json::<FitSettings>("fit",
//!     r#"{"mlp_hidden": ["8y4"]}"#).unwrap_err();
//! assert!(format!("{bad:#}").starts_with("fit.mlp_hidden[0]: '8y4' is not layer sizes"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::fit::{default_target, FitOptions, DEFAULT_FEATURES};
use crate::study::Study;
use anyhow::Result;
#[cfg(feature = "cli")]
use greybox_core::choice::clap_parsers::choice;
use greybox_learn::protocol::{FitConfig, Folds, Repeats, Resamples};
use greybox_model::ensemble::{BoostDepth, Trees};
use greybox_model::family::Family;
use greybox_model::mlp::{Activation, Epochs, LayerWidth};
use greybox_model::svr::Kernel;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The output directory when no `out` is given.
pub const DEFAULT_FIT_DIR: &str = "fit-out";

/// One fit as a user states it; `None` keeps the study's (or the article's) value.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct FitSettings {
    /// Dataset CSV (e.g. from `greybox identify` or `greybox adhesive`).
    #[cfg_attr(feature = "cli", arg(long))]
    pub data: PathBuf,
    /// Target column [default: cof_adhesive where the dataset has it, else cof_apparent].
    #[cfg_attr(feature = "cli", arg(long))]
    pub target: Option<String>,
    /// Feature columns, comma-separated [default: normal_force_N,sliding_velocity_m_per_min].
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub features: Option<Vec<String>>,
    /// Study TOML with a [fit] section (grids, folds, seeds); the settings below override it.
    #[cfg_attr(feature = "cli", arg(long))]
    pub study: Option<PathBuf>,
    /// Model families, comma-separated.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ',', value_parser = choice::<Family>()))]
    #[serde(with = "greybox_core::choice::names")]
    pub families: Option<Vec<Family>>,
    /// Folds of the grid search and of the outer nested-CV loop.
    #[cfg_attr(feature = "cli", arg(long))]
    pub folds: Option<Folds>,
    /// Folds of the inner nested-CV loop.
    #[cfg_attr(feature = "cli", arg(long))]
    pub inner_folds: Option<Folds>,
    /// Integer column holding fold ids (replaces the seeded shuffled k-fold split).
    #[cfg_attr(feature = "cli", arg(long))]
    pub fold_column: Option<String>,
    /// Seed of folds and fits.
    #[cfg_attr(feature = "cli", arg(long))]
    pub seed: Option<u64>,
    /// Bootstrap resamples for the 95 % CIs.
    #[cfg_attr(feature = "cli", arg(long))]
    pub bootstrap: Option<Resamples>,
    /// Permutation-importance repeats.
    #[cfg_attr(feature = "cli", arg(long))]
    pub importance_repeats: Option<Repeats>,
    /// Skip nested cross-validation (no held-out metrics; quick looks only).
    #[cfg_attr(feature = "cli", arg(long))]
    pub skip_nested: bool,
    /// Random-forest grid: n_estimators values.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub rf_n_estimators: Option<Vec<Trees>>,
    /// SVR grid: C values.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub svr_c: Option<Vec<f64>>,
    /// SVR grid: kernels.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ',', value_parser = choice::<Kernel>()))]
    #[serde(with = "greybox_core::choice::names")]
    pub svr_kernel: Option<Vec<Kernel>>,
    /// SVR grid: epsilon values.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub svr_epsilon: Option<Vec<f64>>,
    /// Boosting grid: n_estimators values.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub gb_n_estimators: Option<Vec<Trees>>,
    /// Boosting grid: max_depth values.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub gb_max_depth: Option<Vec<BoostDepth>>,
    /// Boosting grid: learning_rate values.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub gb_learning_rate: Option<Vec<f64>>,
    /// MLP grid: hidden layers, e.g. 64x32,32x16.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub mlp_hidden: Option<Vec<HiddenLayers>>,
    /// MLP grid: activations.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ',', value_parser = choice::<Activation>()))]
    #[serde(with = "greybox_core::choice::names")]
    pub mlp_activation: Option<Vec<Activation>>,
    /// MLP grid: Adam learning rates.
    #[cfg_attr(feature = "cli", arg(long, value_delimiter = ','))]
    pub mlp_learning_rate: Option<Vec<f64>>,
    /// MLP epoch limit.
    #[cfg_attr(feature = "cli", arg(long))]
    pub mlp_max_epochs: Option<Epochs>,
    /// Output directory: report.json, report.md, models/, plots/ [default: fit-out].
    #[cfg_attr(feature = "cli", arg(long))]
    pub out: Option<PathBuf>,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[cfg_attr(feature = "cli", arg(long))]
    pub force: bool,
}

/// An MLP's hidden layer sizes, written `64x32` (each a [`LayerWidth`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HiddenLayers(pub Vec<usize>);

impl std::str::FromStr for HiddenLayers {
    type Err = String;
    fn from_str(spec: &str) -> Result<Self, String> {
        spec.split('x')
            .map(|n| n.parse::<LayerWidth>().map(LayerWidth::get))
            .collect::<Result<Vec<_>, _>>()
            .map(HiddenLayers)
            .map_err(|e| format!("'{spec}' is not layer sizes joined by x, e.g. 64x32 ({e})"))
    }
}

impl std::fmt::Display for HiddenLayers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sizes: Vec<String> = self.0.iter().map(usize::to_string).collect();
        f.write_str(&sizes.join("x"))
    }
}

greybox_core::text_serde!(HiddenLayers);

/// Grid values as plain lengths.
fn counts<const MIN: u64, const MAX: u64>(
    values: &Option<Vec<greybox_core::count::Count<MIN, MAX>>>,
) -> Option<Vec<usize>> {
    values.as_ref().map(|v| v.iter().map(|c| c.get()).collect())
}

impl FitSettings {
    /// The settings with the protocol's values where `None` stands for them (the article's:
    /// 5 × 5 folds, seed 42, 1000 bootstrap resamples, 30 importance repeats, every family),
    /// as Python's `settings_defaults("fit")` shows them; a study's `[fit]` overrides them.
    pub fn shown_defaults() -> Self {
        let c = FitConfig::default();
        FitSettings {
            families: Some(c.families.clone()),
            folds: Some(c.folds),
            inner_folds: Some(c.inner_folds),
            seed: Some(c.seed),
            bootstrap: Some(c.bootstrap_resamples),
            importance_repeats: Some(c.importance_repeats),
            ..Default::default()
        }
    }

    /// Apply the overrides to a protocol configuration.
    pub fn apply(&self, c: &mut FitConfig) {
        fn set<T: Clone>(dst: &mut T, src: &Option<T>) {
            if let Some(v) = src {
                *dst = v.clone();
            }
        }
        set(&mut c.families, &self.families);
        set(&mut c.folds, &self.folds);
        set(&mut c.inner_folds, &self.inner_folds);
        set(&mut c.seed, &self.seed);
        set(&mut c.bootstrap_resamples, &self.bootstrap);
        set(&mut c.importance_repeats, &self.importance_repeats);
        c.skip_nested |= self.skip_nested;
        let g = &mut c.grid;
        set(
            &mut g.random_forest.n_estimators,
            &counts(&self.rf_n_estimators),
        );
        set(&mut g.svr.c, &self.svr_c);
        set(&mut g.svr.epsilon, &self.svr_epsilon);
        set(&mut g.svr.kernel, &self.svr_kernel);
        set(
            &mut g.gradient_boosting.n_estimators,
            &counts(&self.gb_n_estimators),
        );
        set(
            &mut g.gradient_boosting.max_depth,
            &counts(&self.gb_max_depth),
        );
        set(
            &mut g.gradient_boosting.learning_rate,
            &self.gb_learning_rate,
        );
        if let Some(h) = &self.mlp_hidden {
            g.mlp.hidden_layers = h.iter().map(|l| l.0.clone()).collect();
        }
        set(&mut g.mlp.activation, &self.mlp_activation);
        set(&mut g.mlp.learning_rate, &self.mlp_learning_rate);
        set(
            &mut g.mlp.base.max_epochs,
            &self.mlp_max_epochs.map(Epochs::get),
        );
    }

    /// The fit's options: the study's `[fit]` section (or the article's protocol) with these
    /// overrides, the library's default target and features where none are named.
    pub fn options(&self) -> Result<FitOptions> {
        let mut config = match &self.study {
            Some(p) => Study::load(p)?.fit,
            None => FitConfig::default(),
        };
        self.apply(&mut config);
        Ok(FitOptions {
            data: self.data.clone(),
            target: match &self.target {
                Some(t) => t.clone(),
                None => default_target(&self.data)?,
            },
            features: self
                .features
                .clone()
                .unwrap_or_else(|| DEFAULT_FEATURES.map(String::from).to_vec()),
            fold_column: self.fold_column.clone(),
            config,
            study: self.study.clone(),
            out: self.out.clone().unwrap_or_else(|| DEFAULT_FIT_DIR.into()),
            force: self.force,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every width of a layer spec is a bounded count: a hostile width is refused where the
    /// spec is read, not sized into a network.
    #[test]
    fn a_layer_width_beyond_its_cap_is_refused() {
        for spec in ["64x1000000000", "0", "64x-1", "x", ""] {
            let e = spec.parse::<HiddenLayers>().unwrap_err();
            assert!(
                e.contains(&format!("'{spec}' is not layer sizes")),
                "{spec}: {e}"
            );
        }
        assert_eq!(
            "64x32".parse::<HiddenLayers>().unwrap(),
            HiddenLayers(vec![64, 32])
        );
        assert_eq!(HiddenLayers(vec![8, 4]).to_string(), "8x4");
    }
}
