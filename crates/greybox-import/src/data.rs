//! Training and calibration rows from CSV files: the training domain per feature, and rows
//! with their target for the split-conformal interval.

use greybox_core::csvutil::{csv_error, parse_f64, record_line, Header};
use greybox_core::dataset::FrictionDataset;
use greybox_core::{Error, Result, SourcePos};
use greybox_model::modelfile::{FeatureRange, ForcePressure};
use std::path::Path;

/// The training domain and what else the training data tells.
pub struct TrainingDomain {
    pub ranges: Vec<FeatureRange>,
    /// Training rows (0 when the domain was stated).
    pub rows: usize,
    /// The force-to-pressure map of a greybox friction dataset.
    pub force_to_pressure: Option<ForcePressure>,
}

pub fn domain(d: &crate::Domain, names: &[String]) -> Result<TrainingDomain> {
    match d {
        crate::Domain::Stated(ranges) => {
            if ranges.len() != names.len() {
                return Err(Error::invalid(
                    "import domain",
                    format!("{} ranges for {} features", ranges.len(), names.len()),
                ));
            }
            Ok(TrainingDomain {
                ranges: ranges.clone(),
                rows: 0,
                force_to_pressure: None,
            })
        }
        crate::Domain::Data(path) => {
            let (x, _) = rows(path, names, None)?;
            let force_to_pressure = FrictionDataset::read_csv(path)
                .ok()
                .and_then(|ds| ForcePressure::of_dataset(&ds));
            Ok(TrainingDomain {
                ranges: ranges(&x, names.len()),
                rows: x.len(),
                force_to_pressure,
            })
        }
        crate::Domain::Rows {
            x,
            force_to_pressure,
        } => {
            check_rows(x, names.len(), "training rows")?;
            Ok(TrainingDomain {
                ranges: ranges(x, names.len()),
                rows: x.len(),
                force_to_pressure: *force_to_pressure,
            })
        }
    }
}

/// Per feature, the smallest and largest value of the rows.
fn ranges(x: &[Vec<f64>], n: usize) -> Vec<FeatureRange> {
    (0..n)
        .map(|f| FeatureRange {
            min: x.iter().map(|r| r[f]).fold(f64::INFINITY, f64::min),
            max: x.iter().map(|r| r[f]).fold(f64::NEG_INFINITY, f64::max),
        })
        .collect()
}

/// At least one row, each of `n` finite values.
pub fn check_rows(x: &[Vec<f64>], n: usize, what: &str) -> Result<()> {
    if x.is_empty() {
        return Err(Error::invalid(what, "no rows"));
    }
    for (i, r) in x.iter().enumerate() {
        if r.len() != n {
            return Err(Error::invalid(
                what,
                format!("row {i} has {} values for {n} features", r.len()),
            ));
        }
        if let Some(j) = r.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                what,
                format!("row {i}, feature {j} is {}", r[j]),
            ));
        }
    }
    Ok(())
}

/// Feature rows and, when asked for, the target column.
pub type Rows = (Vec<Vec<f64>>, Option<Vec<f64>>);

/// The named feature columns of every row (and the target's, when asked).
pub fn rows(path: &Path, names: &[String], target: Option<&str>) -> Result<Rows> {
    let source = path.display().to_string();
    let what = if target.is_some() {
        "training data"
    } else {
        "feature table"
    };
    let mut reader =
        greybox_core::input::data_csv(path, what, csv::ReaderBuilder::new().trim(csv::Trim::All))?;
    let header = Header::new(
        &source,
        reader.headers().map_err(|e| csv_error(&source, e))?,
    );
    let cols: Vec<usize> = names
        .iter()
        .map(|n| header.require(n))
        .collect::<Result<_>>()?;
    let target_col = target.map(|t| header.require(t)).transpose()?;
    let mut x = Vec::new();
    let mut y = target.map(|_| Vec::new());
    for (i, record) in reader.records().enumerate() {
        let record = record.map_err(|e| csv_error(&source, e))?;
        let line = record_line(record.position(), i as u64 + 2);
        let field =
            |c: usize, name: &str| parse_f64(record.get(c).unwrap_or(""), &source, line, name);
        x.push(
            cols.iter()
                .zip(names)
                .map(|(c, n)| field(*c, n))
                .collect::<Result<Vec<f64>>>()?,
        );
        if let (Some(c), Some(y)) = (target_col, y.as_mut()) {
            y.push(field(c, target.unwrap_or_default())?);
        }
    }
    if x.is_empty() {
        return Err(Error::input(SourcePos::file(&source), "no data rows"));
    }
    Ok((x, y))
}
