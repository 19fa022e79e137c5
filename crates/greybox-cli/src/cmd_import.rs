//! `greybox import`: a model trained elsewhere as a greybox model file.

use crate::output::print_json;
use anyhow::{bail, Context, Result};
use greybox_model::modelfile::FeatureRange;
use greybox_pipeline::import::{import, Calibration, Domain, ImportOptions};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// The model: an XGBoost booster saved as JSON (.json) or UBJSON (.ubj), an ONNX model
    /// (.onnx), or a scikit-learn model exported by greybox's Python package
    /// (greybox.export_sklearn).
    pub model: PathBuf,
    /// Feature names with unit suffixes in the model's input order, comma-separated
    /// (e.g. normal_force_N,sliding_velocity_m_per_min); default: the names the model records.
    #[arg(long, value_delimiter = ',')]
    pub features: Vec<String>,
    /// Target name.
    #[arg(long, default_value = "cof_adhesive")]
    pub target: String,
    /// Training data (CSV with the feature columns): the training domain is taken from it.
    #[arg(long, conflicts_with = "domain")]
    pub training_data: Option<PathBuf>,
    /// The training domain per feature, MIN:MAX comma-separated in feature order
    /// (e.g. 150:2000,20:250).
    #[arg(long, allow_hyphen_values = true)]
    pub domain: Option<String>,
    /// Rows the model was not trained on (CSV with features and target): a split-conformal
    /// prediction interval and a held-out R².
    #[arg(long)]
    pub calibration: Option<PathBuf>,
    /// Nominal coverage of the prediction interval.
    #[arg(long, default_value_t = 0.95)]
    pub coverage: f64,
    /// The greybox model file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

fn parse_domain(text: &str) -> Result<Vec<FeatureRange>> {
    text.split(',')
        .map(|r| {
            let (a, b) = r
                .split_once(':')
                .with_context(|| format!("--domain '{r}': expected MIN:MAX"))?;
            let num = |s: &str| {
                s.trim()
                    .parse::<f64>()
                    .with_context(|| format!("--domain '{r}': '{s}' is not a number"))
            };
            let (min, max) = (num(a)?, num(b)?);
            if !(min.is_finite() && max.is_finite() && min <= max) {
                bail!("--domain '{r}': {min}..{max} is not a range");
            }
            Ok(FeatureRange { min, max })
        })
        .collect()
}

pub fn run(a: Args) -> Result<()> {
    let domain = match (&a.training_data, &a.domain) {
        (Some(p), None) => Domain::Data(p.clone()),
        (None, Some(d)) => Domain::Stated(parse_domain(d)?),
        _ => bail!("state the training domain: --training-data FILE.csv or --domain MIN:MAX,…"),
    };
    let opts = ImportOptions {
        features: (!a.features.is_empty()).then(|| a.features.clone()),
        target: a.target.clone(),
        domain,
        calibration: a.calibration.clone().map(Calibration::File),
        coverage: a.coverage,
    };
    let m = import(&a.model, &opts, &a.out)?;
    if a.json {
        return print_json(&m.hyperparameters);
    }
    println!(
        "{}: {} ({} → {}), interval {}, written to {}",
        a.model.display(),
        m.hyperparameters.label(),
        m.features
            .iter()
            .map(|f| format!("{} [{}]", f.name, f.unit))
            .collect::<Vec<_>>()
            .join(", "),
        m.target.name,
        match m.prediction_interval.method {
            greybox_model::interval::IntervalMethod::None => "none (no calibration data)".into(),
            _ => format!(
                "±{:.4} at {:.0} %",
                m.prediction_interval.half_width,
                m.prediction_interval.coverage * 100.0
            ),
        },
        a.out.display()
    );
    Ok(())
}
