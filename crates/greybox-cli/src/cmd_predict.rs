//! `greybox predict`: evaluate a model file at points.

use crate::output::print_json;
use anyhow::{bail, Context, Result};
use greybox_model::modelfile::ModelFile;
use greybox_pipeline::predict::{predict_points, read_points};
use greybox_pipeline::settings::predict::DomainCheck;
use std::path::PathBuf;

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
    #[command(flatten)]
    pub check: DomainCheck,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let check = a.check.checked()?;
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
        points.extend(read_points(csv, &names)?);
    }
    if points.is_empty() {
        bail!("give points with --at or --csv");
    }
    let rows = predict_points(&m, points, check.outside, check.margin)?;
    if let Some(o) = m.outside_domain(rows.iter().map(|r| r.features.as_slice()), check.margin) {
        eprintln!("warning: {}", crate::flags::shown(&o.to_string()));
    }
    if a.json {
        return print_json(&rows);
    }
    print!("{}", greybox_report::text::predictions(&m, &rows));
    Ok(())
}
