//! Strict numeric tables read from CSV: chosen feature columns and a target column.

use greybox_core::csvutil::{csv_error, parse_f64, parse_u64, record_line, Header};
use greybox_core::{Error, Result, SourcePos};
use greybox_model::Matrix;

use std::path::Path;

use greybox_model::column::{unit_of, Column};

/// Features, target and optional fold ids read from a CSV.
#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    pub source: String,
    pub features: Vec<Column>,
    pub target: Column,
    pub x: Matrix,
    pub y: Vec<f64>,
    /// Fold id per row, if a fold column was read.
    pub folds: Option<Vec<usize>>,
    /// What the reader noticed but did not refuse (duplicated rows), for the user and the
    /// fit report.
    pub warnings: Vec<String>,
}

/// Units whose quantities are positive in any friction experiment (forces, pressures,
/// speeds, absolute temperatures, lengths): a zero or negative value there is not physical.
const POSITIVE_UNITS: [&str; 10] = [
    "N", "kN", "Pa", "MPa", "GPa", "m/s", "m/min", "K", "µm", "mm",
];

/// Why a value of column `name` is not physical, if it is not: a quantity of a
/// [`POSITIVE_UNITS`] unit ≤ 0, or a friction coefficient (`cof…`, `mu…`) < 0.
fn non_physical(name: &str, v: f64) -> Option<String> {
    // Sums of squares (standardising, MSE) overflow past about 1e154; no force, speed,
    // pressure or coefficient in any unit comes near MAX_MAGNITUDE.
    if v.abs() > MAX_MAGNITUDE {
        return Some(format!(
            "{v:e} is not physical: beyond {MAX_MAGNITUDE:e} in any unit (check the column's unit)"
        ));
    }
    let unit = unit_of(name);
    if POSITIVE_UNITS.contains(&unit) && !(v > 0.0) {
        return Some(format!(
            "{v} {unit} is not physical: a quantity in {unit} must be positive"
        ));
    }
    let lower = name.to_ascii_lowercase();
    if (lower.starts_with("cof") || lower.starts_with("mu")) && v < 0.0 {
        return Some(format!(
            "{v} is not physical: a friction coefficient cannot be negative"
        ));
    }
    None
}

/// Largest magnitude a training value may have.
const MAX_MAGNITUDE: f64 = 1e100;

/// Exact duplicates (same features and target): each later row with the first one it
/// repeats, as 0-based row indices.
fn duplicate_rows(x: &Matrix, y: &[f64]) -> Vec<(usize, usize)> {
    let mut seen: std::collections::HashMap<Vec<u64>, usize> = std::collections::HashMap::new();
    let mut dups = Vec::new();
    for (i, yi) in y.iter().enumerate() {
        let mut key: Vec<u64> = (0..x.n_cols).map(|j| x.get(i, j).to_bits()).collect();
        key.push(yi.to_bits());
        match seen.get(&key) {
            Some(&first) => dups.push((first, i)),
            None => {
                seen.insert(key, i);
            }
        }
    }
    dups
}

/// Read `features` and `target` (and optionally an integer `fold_column`) from a CSV file.
/// Other columns are ignored. Every value must be a finite number.
pub fn read_dataset(
    path: &Path,
    features: &[String],
    target: &str,
    fold_column: Option<&str>,
) -> Result<Dataset> {
    let file =
        greybox_core::input::open(path, "training data", greybox_core::budget::Cap::DataBytes)?;
    read_dataset_from(
        file,
        &path.display().to_string(),
        features,
        target,
        fold_column,
    )
}

/// The target and feature names (`--target`, `--features`) become a model file's names:
/// words, not lines ([`greybox_core::escape::check_name`]); the error names `source`.
fn check_column_names(source: &str, features: &[String], target: &str) -> Result<()> {
    let named = std::iter::once(("target", target))
        .chain(features.iter().map(|f| ("features", f.as_str())));
    for (field, name) in named {
        greybox_core::escape::check_name(SourcePos::file(source).field(field), name)?;
    }
    Ok(())
}

/// A dataset from CSV text: the `features` and `target` columns (and the fold ids of
/// `fold_column`), checked for physical values, at least two rows, a varying target and at
/// least two folds; duplicated rows become warnings. `source` names the text in errors.
pub fn read_dataset_from(
    reader: impl std::io::Read,
    source: &str,
    features: &[String],
    target: &str,
    fold_column: Option<&str>,
) -> Result<Dataset> {
    if features.is_empty() {
        return Err(Error::invalid(
            "features",
            "give at least one feature column",
        ));
    }
    check_column_names(source, features, target)?;
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(reader);
    let header = Header::new(source, rdr.headers().map_err(|e| csv_error(source, e))?);
    let (fi, ti) = column_indices(&header, source, features, target)?;
    let foldi = fold_column.map(|c| header.require(c)).transpose()?;
    let mut data = Vec::new();
    let mut y = Vec::new();
    let mut folds = foldi.map(|_| Vec::new());
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| csv_error(source, e))?;
        let line = record_line(rec.position(), k as u64 + 2);
        for (&i, name) in fi
            .iter()
            .zip(features)
            .chain(std::iter::once((&ti, &target.to_string())))
        {
            let v = parse_f64(&rec[i], source, line, name)?;
            if let Some(why) = non_physical(name, v) {
                return Err(Error::input(
                    SourcePos::file(source).line(line).field(name.clone()),
                    format!("{why}; a training domain must hold only physical values (remove or fix the row)"),
                ));
            }
            if i == ti {
                y.push(v);
            } else {
                data.push(v);
            }
        }
        if let (Some(i), Some(f)) = (foldi, folds.as_mut()) {
            f.push(parse_u64(&rec[i], source, line, fold_column.unwrap_or_default())? as usize);
        }
    }
    check_target(&y, source, target)?;
    if let (Some(f), Some(name)) = (&folds, fold_column) {
        check_fold_ids(f, source, name)?;
    }
    let x = Matrix::new(y.len(), features.len(), data);
    let warnings = duplicate_warnings(&x, &y, source);
    Ok(Dataset {
        source: source.to_string(),
        features: features.iter().map(|f| Column::new(f)).collect(),
        target: Column::new(target),
        x,
        y,
        folds,
        warnings,
    })
}

/// The columns of the features and of the target; a target that is also a feature, or a
/// name the header lacks (listing the header's names), is an error.
fn column_indices(
    header: &Header,
    source: &str,
    features: &[String],
    target: &str,
) -> Result<(Vec<usize>, usize)> {
    let fi: Vec<usize> = features
        .iter()
        .map(|f| {
            header.find(f).ok_or_else(|| {
                Error::input(
                    SourcePos::file(source).line(1).field(f.clone()),
                    format!(
                        "unknown feature '{f}'; the file has: {}",
                        header.names().join(", ")
                    ),
                )
            })
        })
        .collect::<Result<_>>()?;
    if features.iter().any(|f| f == target) {
        return Err(Error::invalid(
            "features",
            format!("the target '{target}' cannot also be a feature"),
        ));
    }
    let ti = header.find(target).ok_or_else(|| {
        Error::input(
            SourcePos::file(source).line(1).field(target),
            format!(
                "unknown target '{target}'; the file has: {}",
                header.names().join(", ")
            ),
        )
    })?;
    Ok((fi, ti))
}

/// At least two rows, and a target that varies (a constant one leaves nothing to learn).
fn check_target(y: &[f64], source: &str, target: &str) -> Result<()> {
    let n = y.len();
    if n < 2 {
        return Err(Error::input(
            SourcePos::file(source),
            format!("need at least 2 data rows, found {n}"),
        ));
    }
    let (lo, hi) = y
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    if lo == hi {
        return Err(Error::input(
            SourcePos::file(source).field(target),
            format!("the target is constant ({lo}): there is nothing to learn"),
        ));
    }
    Ok(())
}

/// The fold column `name` holds at least two distinct fold ids.
fn check_fold_ids(folds: &[usize], source: &str, name: &str) -> Result<()> {
    let mut ids = folds.to_vec();
    ids.sort_unstable();
    ids.dedup();
    if ids.len() < 2 {
        return Err(Error::input(
            SourcePos::file(source).field(name),
            format!(
                "the fold column has {} distinct value(s) ({}): cross-validation needs at least two folds",
                ids.len(),
                ids.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(", ")
            ),
        ));
    }
    Ok(())
}

/// A warning naming the duplicated rows (the first five), if any.
fn duplicate_warnings(x: &Matrix, y: &[f64], source: &str) -> Vec<String> {
    let dups = duplicate_rows(x, y);
    let mut warnings = Vec::new();
    if !dups.is_empty() {
        let shown: Vec<String> = dups
            .iter()
            .take(5)
            .map(|(a, b)| format!("row {} repeats row {}", b + 1, a + 1))
            .collect();
        warnings.push(format!(
            "{source}: {} duplicated row(s) ({}{}): a row and its copy in different CV folds inflate the held-out scores and narrow the intervals; remove duplicates unless they are real repeats",
            dups.len(),
            shown.join(", "),
            if dups.len() > 5 { ", …" } else { "" }
        ));
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    const CSV: &str = "a_N,b_m_per_min,mu,fold\n1,2,0.3,0\n2,3,0.4,1\n3,4,0.5,0\n";

    fn read(text: &str, feats: &[&str], target: &str) -> Result<Dataset> {
        let f: Vec<String> = feats.iter().map(|s| s.to_string()).collect();
        read_dataset_from(text.as_bytes(), "d.csv", &f, target, None)
    }

    #[test]
    fn reads_and_names_units() {
        let d = read(CSV, &["a_N", "b_m_per_min"], "mu").unwrap();
        assert_eq!(d.x.row(1), &[2.0, 3.0]);
        assert_eq!(d.features[1].unit, "m/min");
        assert_eq!(d.target.unit, "1");
    }

    /// A speed of 10³⁰⁸ m/min is finite, but its square is not: the fuzz campaign's mutant
    /// made every error of the fit ∞ and its intervals NaN.
    #[test]
    fn values_too_large_for_their_statistics_are_refused() {
        let e = read(
            &CSV.replace(",3,0.4,", ",1e308,0.4,"),
            &["a_N", "b_m_per_min"],
            "mu",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("d.csv, line 3") && e.contains("b_m_per_min") && e.contains("1e308"),
            "{e}"
        );
    }

    #[test]
    fn bad_inputs() {
        let e = read(CSV, &["a_N", "pressure"], "mu")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown feature 'pressure'") && e.contains("a_N, b_m_per_min, mu, fold"),
            "{e}"
        );
        let e = read(CSV, &["a_N"], "cof").unwrap_err().to_string();
        assert!(e.contains("unknown target 'cof'"), "{e}");
        let e = read(&CSV.replace("0.4", "NaN"), &["a_N"], "mu")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 3") && e.contains("'mu'") && e.contains("finite"),
            "{e}"
        );
        let e = read(
            &CSV.replace("0.4", "0.3").replace("0.5", "0.3"),
            &["a_N"],
            "mu",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("constant"), "{e}");
    }

    #[test]
    fn folds_physics_and_duplicates() {
        let folds = |text: &str| {
            let f = vec!["a_N".to_string()];
            read_dataset_from(text.as_bytes(), "d.csv", &f, "mu", Some("fold"))
        };
        folds(CSV).unwrap();
        let e = folds(&CSV.replace(",1\n", ",0\n")).unwrap_err().to_string();
        assert!(
            e.contains("field 'fold'") && e.contains("at least two folds"),
            "{e}"
        );
        let e = read(
            &CSV.replace("2,3,0.4", "-2,3,0.4"),
            &["a_N", "b_m_per_min"],
            "mu",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("line 3") && e.contains("'a_N'") && e.contains("not physical"),
            "{e}"
        );
        let e = read(&CSV.replace("0.4", "-0.4"), &["a_N"], "mu")
            .unwrap_err()
            .to_string();
        assert!(e.contains("friction coefficient cannot be negative"), "{e}");
        // a dimensionless or time feature may be anything
        read("x,t_s,mu\n-1,-2,0.3\n1,2,0.4\n", &["x", "t_s"], "mu").unwrap();
        let d = read(CSV, &["a_N"], "mu").unwrap();
        assert!(d.warnings.is_empty());
        let d = read(&format!("{CSV}2,3,0.4,1\n"), &["a_N", "b_m_per_min"], "mu").unwrap();
        assert_eq!(d.warnings.len(), 1);
        assert!(
            d.warnings[0].contains("row 4 repeats row 2"),
            "{:?}",
            d.warnings
        );
    }
}
