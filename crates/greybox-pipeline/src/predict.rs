//! Evaluate a model file at points, with prediction intervals and the domain check.

use anyhow::{bail, Context, Result};
use greybox_model::modelfile::{DomainPolicy, ModelFile, Prediction};
use serde::Serialize;
use std::path::Path;

/// One evaluated point.
#[derive(Debug, Clone, Serialize)]
pub struct PredictedPoint {
    /// Feature values, in the model's feature order.
    pub features: Vec<f64>,
    #[serde(flatten)]
    pub prediction: Prediction,
}

/// Evaluate `model` at `points` (feature values in the model's order). Points outside the
/// training domain by more than `margin` (a fraction of each feature's range) are
/// extrapolations: predicted and flagged (`in_domain = false`) under
/// [`DomainPolicy::Warn`], an error under [`DomainPolicy::Refuse`].
pub fn predict_points(
    model: &ModelFile,
    points: Vec<Vec<f64>>,
    policy: DomainPolicy,
    margin: f64,
) -> Result<Vec<PredictedPoint>> {
    let n = model.features.len();
    points
        .into_iter()
        .map(|p| {
            if p.len() != n {
                bail!("a point needs {n} feature values, got {}", p.len());
            }
            let prediction = model.predict(&p, policy, margin)?;
            Ok(PredictedPoint {
                features: p,
                prediction,
            })
        })
        .collect()
}

/// Feature rows of a CSV (strict, by column name).
pub fn read_points(path: &Path, names: &[String]) -> Result<Vec<Vec<f64>>> {
    let mut rdr =
        greybox_core::input::data_csv(path, "prediction points", &csv::ReaderBuilder::new())?;
    let header = rdr.headers()?.clone();
    let idx: Vec<usize> = names
        .iter()
        .map(|n| {
            header.iter().position(|h| h.trim() == n).with_context(|| {
                format!(
                    "{}: missing feature column '{n}' (the model needs {})",
                    path.display(),
                    names.join(", ")
                )
            })
        })
        .collect::<Result<_>>()?;
    let mut out = Vec::new();
    for (k, r) in rdr.records().enumerate() {
        let r =
            r.with_context(|| format!("{}: malformed CSV near line {}", path.display(), k + 2))?;
        let row: Vec<f64> = idx
            .iter()
            .zip(names)
            .map(|(&i, n)| {
                let v: f64 = r[i].trim().parse().with_context(|| {
                    format!(
                        "{}, line {}, field '{n}': not a number",
                        path.display(),
                        k + 2
                    )
                })?;
                if !v.is_finite() {
                    bail!(
                        "{}, line {}, field '{n}': not finite",
                        path.display(),
                        k + 2
                    );
                }
                Ok(v)
            })
            .collect::<Result<_>>()?;
        out.push(row);
    }
    Ok(out)
}
