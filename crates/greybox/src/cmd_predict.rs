//! `greybox predict`: evaluate a model file at points.

use crate::output::{print_json, Table};
use anyhow::{bail, Context, Result};
use greybox_learn::modelfile::{DomainPolicy, ModelFile, Prediction};
use serde::Serialize;
use std::path::PathBuf;

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outside {
    /// Predict and warn.
    Warn,
    /// Refuse with an error.
    Refuse,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Model file from `greybox fit`.
    #[arg(long)]
    pub model: PathBuf,
    /// A point: feature values in the model's feature order, comma-separated (repeatable).
    #[arg(long = "at", allow_hyphen_values = true)]
    pub at: Vec<String>,
    /// CSV with the model's feature columns (by name).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Points outside the training domain: warn or refuse.
    #[arg(long, value_enum, default_value_t = Outside::Warn)]
    pub outside: Outside,
    /// Tolerated distance outside the training domain, as a fraction of each feature's range.
    #[arg(long, default_value_t = 0.05)]
    pub margin: f64,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct Row {
    features: Vec<f64>,
    #[serde(flatten)]
    prediction: Prediction,
}

pub fn run(a: Args) -> Result<()> {
    let m = ModelFile::load(&a.model)?;
    let names: Vec<String> = m.features.iter().map(|f| f.name.clone()).collect();
    let mut points: Vec<Vec<f64>> = Vec::new();
    for s in &a.at {
        let v: Vec<f64> = s
            .split(',')
            .map(|t| {
                t.trim()
                    .parse::<f64>()
                    .with_context(|| format!("--at '{s}': '{t}' is not a number"))
            })
            .collect::<Result<_>>()?;
        if v.len() != names.len() {
            bail!(
                "--at '{s}': expected {} values ({})",
                names.len(),
                names.join(", ")
            );
        }
        points.push(v);
    }
    if let Some(csv) = &a.csv {
        let data = read_points(csv, &names)?;
        points.extend(data);
    }
    if points.is_empty() {
        bail!("give points with --at or --csv");
    }
    let policy = match a.outside {
        Outside::Warn => DomainPolicy::Warn,
        Outside::Refuse => DomainPolicy::Refuse,
    };
    let mut rows = Vec::new();
    for p in points {
        let pred = m.predict(&p, policy, a.margin)?;
        if !pred.in_domain {
            eprintln!("warning: point {p:?} lies outside the training domain; the prediction is an extrapolation");
        }
        rows.push(Row {
            features: p,
            prediction: pred,
        });
    }
    if a.json {
        return print_json(&rows);
    }
    let mut head: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
    let target = format!("{} ({})", m.target.name, m.family.name());
    let low = format!("{:.0} % low", m.prediction_interval.coverage * 100.0);
    let high = format!("{:.0} % high", m.prediction_interval.coverage * 100.0);
    head.extend([target.as_str(), low.as_str(), high.as_str(), "in domain"]);
    let mut t = Table::new(&head);
    for r in &rows {
        let mut cells: Vec<String> = r.features.iter().map(|v| format!("{v}")).collect();
        cells.push(format!("{:.5}", r.prediction.value));
        cells.push(format!("{:.5}", r.prediction.low));
        cells.push(format!("{:.5}", r.prediction.high));
        cells.push(r.prediction.in_domain.to_string());
        t.row(cells);
    }
    print!("{}", t.render());
    Ok(())
}

/// Feature rows of a CSV (strict, by column name).
fn read_points(path: &std::path::Path, names: &[String]) -> Result<Vec<Vec<f64>>> {
    let mut rdr =
        csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
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
