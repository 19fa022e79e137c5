#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-import: models trained elsewhere as greybox model files, usable everywhere a
//! greybox model is (friction laws, tables, the C ABI, the cutting simulation).
//!
//! * [`sklearn`] — scikit-learn forests, extra trees, gradient boosting, SVR and MLP, with
//!   `StandardScaler`/`MinMaxScaler` pipelines (exported by `greybox.from_sklearn` in Python).
//! * [`xgboost`] — XGBoost boosters saved as JSON or UBJSON ([`ubjson`]).
//! * [`onnx`] — ONNX graphs of tree ensembles, SVMs, linear models and networks, converted
//!   into greybox models (no ONNX runtime at run time).
//! * [`trees`], [`scaler`] — exact restatement of the libraries' splits and scalers.
//!
//! A source library's model knows nothing of units or of where it may be trusted, so the
//! user states the feature names (their suffixes give the units, `normal_force_N`), the target,
//! and the training domain — or gives the training data, from which the domain is taken. Rows
//! the model was not trained on (`calibration`) give it a split-conformal prediction
//! interval and a held-out R²; without them the model file says it has no interval.
//!
//! ```no_run
//! use greybox_import::{import_file, Domain, ImportOptions};
//! let opts = ImportOptions::new(Domain::Data("campaign.csv".into()))
//!     .with_features(&["normal_force_N", "sliding_velocity_m_per_min"]);
//! let model = import_file("booster.ubj".as_ref(), &opts).unwrap();
//! model.save("model.json".as_ref()).unwrap();
//! ```

pub mod onnx;
pub mod scaler;
pub mod sklearn;
pub mod trees;
pub mod ubjson;
pub mod xgboost;

mod data;

use greybox_contact::PinContact;
use greybox_core::provenance::sha256_bytes;
use greybox_core::{Error, Result, SourcePos};
use greybox_model::column::{Column, FeatureQuantity};
use greybox_model::family::{FittedModel, Hyperparameters, ImportedFrom};
use greybox_model::interval::{conformal_half_width, IntervalMethod, PredictionInterval};
use greybox_model::modelfile::{FeatureRange, ForcePressure, ModelFile, SCHEMA, SCHEMA_VERSION};
use greybox_model::Predictor;
use std::path::{Path, PathBuf};

/// A model read from another library, before it meets units and a domain.
#[derive(Debug, Clone)]
pub struct Imported {
    pub model: FittedModel,
    pub from: ImportedFrom,
    pub n_features: usize,
    /// The feature names the source recorded, if any.
    pub feature_names: Option<Vec<String>>,
}

/// The target an imported model is taken to predict when none is named.
pub const DEFAULT_TARGET: &str = "cof_adhesive";
/// The nominal coverage of an imported model's prediction interval.
pub const DEFAULT_COVERAGE: f64 = 0.95;

/// Where the training domain comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum Domain {
    /// Per feature, the range the model was trained on (feature units).
    Stated(Vec<FeatureRange>),
    /// The training data: a CSV with a column per feature (a greybox friction dataset also
    /// gives the force-to-pressure map of its contact).
    Data(PathBuf),
    /// The training rows themselves (feature units, one row per sample), with the
    /// force-to-pressure map of their contact when the table they came from records one
    /// ([`ForcePressure::of_rows`] of a friction dataset's columns).
    Rows {
        x: Vec<Vec<f64>>,
        force_to_pressure: Option<ForcePressure>,
    },
}

/// Rows the model was not trained on, with their target.
#[derive(Debug, Clone, PartialEq)]
pub enum Calibration {
    /// A CSV with the feature columns and the target column.
    File(PathBuf),
    /// Feature rows and targets.
    Rows(Vec<Vec<f64>>, Vec<f64>),
}

/// What the source model does not know: names, units, domain, interval.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportOptions {
    /// Feature names with unit suffixes, in the model's input order (`None`: the names the
    /// source recorded).
    pub features: Option<Vec<String>>,
    /// The target column's name.
    pub target: String,
    pub domain: Domain,
    /// Rows not used in training: a split-conformal interval and a held-out R².
    pub calibration: Option<Calibration>,
    /// Nominal coverage of the interval.
    pub coverage: f64,
    /// The tribometer's pin contact (the study's `[contact]` table): for a model trained on
    /// a normal force (`normal_force_N`, `_kN`), the Hertz map p = c·F^(1/3) under its
    /// pressure convention that turns a contact pressure into the force the model takes.
    /// Recorded in the model file's `force_to_pressure`, as `greybox fit` records its
    /// dataset's. `None`: the training data's map when it is a greybox friction dataset,
    /// else none (the model predicts on forces but is no friction law until a law file
    /// states the contact).
    pub contact: Option<PinContact>,
}

impl ImportOptions {
    /// Features as the source names them, target [`DEFAULT_TARGET`], intervals of
    /// [`DEFAULT_COVERAGE`].
    pub fn new(domain: Domain) -> Self {
        ImportOptions {
            features: None,
            target: DEFAULT_TARGET.into(),
            domain,
            calibration: None,
            coverage: DEFAULT_COVERAGE,
            contact: None,
        }
    }
    /// State the tribometer's pin contact ([`ImportOptions::contact`]).
    pub fn with_contact(mut self, contact: PinContact) -> Self {
        self.contact = Some(contact);
        self
    }
    pub fn with_features(mut self, names: &[&str]) -> Self {
        self.features = Some(names.iter().map(|s| s.to_string()).collect());
        self
    }
}

/// The kind of a model file, from its content: a UBJSON object starts with `{` and a
/// length marker for its first key (or a `$`/`#` header); a JSON object with `{` and a quote.
fn detect(bytes: &[u8]) -> &'static str {
    match bytes {
        [b'{', b'i' | b'U' | b'I' | b'l' | b'L' | b'$' | b'#', ..] => "ubjson",
        // ONNX: a protobuf ModelProto, which starts with field 1 (ir_version, varint)
        [0x08, ..] => "onnx",
        _ if std::str::from_utf8(bytes).is_ok_and(|t| t.trim_start().starts_with('{')) => "json",
        _ => "unknown",
    }
}

/// Read a model file of another library: an XGBoost booster (`.json` or `.ubj`) or a
/// scikit-learn export (`greybox-sklearn` JSON).
pub fn read_model(path: &Path) -> Result<Imported> {
    let bytes =
        greybox_core::input::read_bytes(path, "model file", greybox_core::budget::Cap::DataBytes)?;
    let source = path.display().to_string();
    let hash = sha256_bytes(&bytes);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| source.clone());
    let mut imported = match detect(&bytes) {
        "json" => {
            let text = std::str::from_utf8(&bytes).expect("checked by detect");
            let v: serde_json::Value = serde_json::from_str(text).map_err(|e| {
                Error::input(
                    SourcePos::file(&source).line(e.line() as u64),
                    format!("not JSON: {e}"),
                )
            })?;
            from_json(v, &source)?
        }
        "ubjson" => from_xgboost(&ubjson::parse(&bytes, &source)?, &source)?,
        "onnx" => from_onnx(&bytes, &source)?,
        _ => {
            return Err(Error::input(
                SourcePos::file(&source),
                "not a model greybox can import: expected an XGBoost booster saved as JSON or UBJSON, a scikit-learn model exported by greybox.export_sklearn (JSON), or an ONNX model",
            ))
        }
    };
    for (k, n) in imported.feature_names.iter().flatten().enumerate() {
        let pos = SourcePos::file(&source).field(format!("feature_names[{k}]"));
        greybox_core::escape::check_name(pos, n)?;
    }
    imported.from.source = Some(format!("{name} (sha256 {hash})"));
    Ok(imported)
}

/// A JSON document: a scikit-learn export or an XGBoost booster.
pub fn from_json(v: serde_json::Value, source: &str) -> Result<Imported> {
    if v.get("schema").and_then(|s| s.as_str()) == Some(sklearn::SCHEMA) {
        let e: sklearn::Export = serde_json::from_value(v).map_err(|e| {
            Error::input(
                SourcePos::file(source),
                format!("invalid scikit-learn export: {e}"),
            )
        })?;
        return from_sklearn(&e, source);
    }
    if v.get("learner").is_some() {
        return from_xgboost(&v, source);
    }
    Err(Error::input(
        SourcePos::file(source),
        format!(
            "a JSON document that is neither an XGBoost booster (no 'learner') nor a scikit-learn export (schema '{}')",
            sklearn::SCHEMA
        ),
    ))
}

/// A scikit-learn export (`greybox.from_sklearn`).
pub fn from_sklearn(e: &sklearn::Export, source: &str) -> Result<Imported> {
    let (model, family) =
        sklearn::convert(e).map_err(|m| Error::input(SourcePos::file(source), m))?;
    Ok(Imported {
        model,
        from: ImportedFrom {
            as_family: family,
            library: format!("scikit-learn {}", e.library_version),
            estimator: e.estimator.clone(),
            source: None,
        },
        n_features: e.n_features,
        feature_names: e.feature_names.clone(),
    })
}

/// An XGBoost booster's JSON document (parsed from JSON or UBJSON).
pub fn from_xgboost(v: &serde_json::Value, source: &str) -> Result<Imported> {
    let b = xgboost::convert(v).map_err(|m| Error::input(SourcePos::file(source), m))?;
    Ok(Imported {
        n_features: b.ensemble.n_features,
        model: FittedModel::TreeEnsemble(b.ensemble),
        from: ImportedFrom {
            as_family: greybox_model::Family::GradientBoosting,
            library: format!("xgboost {}", b.version),
            estimator: format!("xgboost.Booster (gbtree, {})", b.objective),
            source: None,
        },
        feature_names: b.feature_names,
    })
}

/// An ONNX model ([`onnx`]).
pub fn from_onnx(bytes: &[u8], source: &str) -> Result<Imported> {
    let m = onnx::convert(bytes).map_err(|e| Error::input(SourcePos::file(source), e))?;
    Ok(Imported {
        n_features: m.n_features,
        model: m.model,
        from: ImportedFrom {
            as_family: m.family,
            library: format!("ONNX ({})", m.producer),
            estimator: m.operators,
            source: None,
        },
        feature_names: None,
    })
}

/// Read and convert a model file of another library in one call ([`read_model`] then
/// [`model_file`]).
pub fn import_file(path: &Path, opts: &ImportOptions) -> Result<ModelFile> {
    model_file(read_model(path)?, opts)
}

/// The greybox model file of an imported model: names with units, domain, interval, hash.
pub fn model_file(imported: Imported, opts: &ImportOptions) -> Result<ModelFile> {
    check_options(opts)?;
    let names = feature_names(&imported, opts)?;
    let domain = data::domain(&opts.domain, &names)?;
    let force_to_pressure = force_to_pressure(opts.contact.as_ref(), domain.force_to_pressure)?;
    let mut file = ModelFile {
        schema: SCHEMA.into(),
        schema_version: SCHEMA_VERSION,
        family: imported.from.as_family,
        hyperparameters: Hyperparameters::Imported(imported.from),
        features: names.iter().map(|n| Column::new(n)).collect(),
        target: Column::new(&opts.target),
        training_domain: domain.ranges,
        n_train: domain.rows,
        prediction_interval: PredictionInterval::NONE,
        held_out_r2: None,
        model: imported.model,
        force_to_pressure,
        provenance: None,
        content_hash: String::new(),
    };
    file.check_structure("imported model")?;
    greybox_model::column::check_law_features(&file.features)
        .map_err(|m| Error::invalid("imported model", m))?;
    check_domain_physics(&file)?;
    if let Some(calibration) = &opts.calibration {
        let (x, y) = match calibration {
            Calibration::File(path) => {
                let (x, y) = data::rows(path, &names, Some(&opts.target))?;
                (x, y.expect("target requested"))
            }
            Calibration::Rows(x, y) => {
                data::check_rows(x, names.len(), "calibration rows")?;
                if y.len() != x.len() || y.iter().any(|v| !v.is_finite()) {
                    return Err(Error::invalid(
                        "calibration",
                        format!(
                            "{} finite targets needed for {} rows, got {}",
                            x.len(),
                            x.len(),
                            y.len()
                        ),
                    ));
                }
                (x.clone(), y.clone())
            }
        };
        let pred: Vec<f64> = x.iter().map(|r| file.model.predict_one(r)).collect();
        file.prediction_interval = PredictionInterval {
            coverage: opts.coverage,
            half_width: conformal_half_width(&y, &pred, opts.coverage),
            method: IntervalMethod::SplitConformal,
        };
        file.held_out_r2 = Some(r2(&y, &pred));
    }
    file.seal()
}

/// The training domain against the physics table, feature by feature in SI: an end no
/// contact can have (a domain of 5·10⁸ MPa) is refused naming the feature and the likely unit
/// slip; one outside the usual range is said as a note. Stated domains and ones read from
/// data alike.
fn check_domain_physics(file: &ModelFile) -> Result<()> {
    use greybox_model::column::FeatureQuantity;
    for (c, r) in file.features.iter().zip(&file.training_domain) {
        let Ok(q) = FeatureQuantity::of_column(c) else {
            continue; // refused with its reason by check_law_features
        };
        for (end, v) in [("min", r.min), ("max", r.max)] {
            let what = format!(
                "the training domain's {end} of '{}' ({v} {})",
                c.name, c.unit
            );
            match greybox_core::physics::check(q.physics(), q.to_si(v), &what) {
                Ok(None) => {}
                Ok(Some(flag)) => greybox_core::notes::note(flag.text),
                Err(e) => return Err(Error::invalid("import domain", e)),
            }
        }
    }
    Ok(())
}

/// The force-to-pressure map to record: the stated contact's (c = its pressure at 1 N), which
/// must agree with the training dataset's when that records one, else the dataset's.
fn force_to_pressure(
    contact: Option<&PinContact>,
    dataset: Option<ForcePressure>,
) -> Result<Option<ForcePressure>> {
    let Some(contact) = contact else {
        return Ok(dataset);
    };
    contact
        .validate()
        .map_err(|e| Error::invalid("import contact", e.to_string()))?;
    let stated = ForcePressure {
        pressure_convention: contact.convention,
        pressure_pa_at_1_n: contact.pressure_pa(1.0)?,
    };
    match dataset {
        Some(d)
            if d.pressure_convention != stated.pressure_convention
                || (d.pressure_pa_at_1_n / stated.pressure_pa_at_1_n - 1.0).abs() > 1e-6 =>
        {
            Err(Error::invalid(
                "import contact",
                format!(
                    "the stated contact gives {:.6e} Pa at 1 N ({} convention), but the training dataset's pressures were computed with {:.6e} Pa at 1 N ({} convention): state the dataset's contact, or leave the contact out to take the dataset's",
                    stated.pressure_pa_at_1_n,
                    stated.pressure_convention.name(),
                    d.pressure_pa_at_1_n,
                    d.pressure_convention.name()
                ),
            ))
        }
        _ => Ok(Some(stated)),
    }
}

fn r2(y: &[f64], pred: &[f64]) -> f64 {
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let ss_res: f64 = y.iter().zip(pred).map(|(a, b)| (a - b).powi(2)).sum();
    let ss_tot: f64 = y.iter().map(|a| (a - mean).powi(2)).sum();
    1.0 - ss_res / ss_tot
}

/// The options that hold whatever the model: the target is a fraction, and the coverage lies in
/// (0, 1) whether or not calibration data come with it (a coverage of 5 is a mistake even
/// where it is not used yet).
fn check_options(opts: &ImportOptions) -> Result<()> {
    check_target_is_a_fraction(&opts.target)?;
    if !(opts.coverage > 0.0 && opts.coverage < 1.0) {
        return Err(Error::invalid(
            "import",
            format!("coverage {} is not in (0, 1)", opts.coverage),
        ));
    }
    Ok(())
}

/// A target named in per cent (`cof_pct`, `COF (%)`, `mu_percent`): a friction law gives μ
/// as a fraction, and greybox cannot tell from the name whether the model predicts 38.5 or
/// 0.385, so it refuses rather than exporting either without a word.
fn check_target_is_a_fraction(target: &str) -> Result<()> {
    let t = target.to_ascii_lowercase();
    let percent = t.contains('%')
        || t.contains("percent")
        || t.split(|c: char| !c.is_ascii_alphanumeric())
            .any(|w| w == "pct");
    if percent {
        return Err(Error::input(
            SourcePos::file("import").field("target"),
            format!(
                "the target '{}' is stated in per cent, but a friction law takes μ as a fraction: name the target as the fraction the model predicts (e.g. cof_adhesive), or train the model on μ rather than μ × 100",
                greybox_core::escape::excerpt(target)
            ),
        ));
    }
    Ok(())
}

/// The stated names, or the source's; their number must match the model's inputs, and
/// stated names must match recorded ones when both exist.
fn feature_names(imported: &Imported, opts: &ImportOptions) -> Result<Vec<String>> {
    let n = imported.n_features;
    let given = opts.features.iter().flatten().map(|f| ("features", f));
    for (field, name) in std::iter::once(("target", &opts.target)).chain(given) {
        greybox_core::escape::check_name(SourcePos::file("import").field(field), name)?;
    }

    let names = match (&opts.features, &imported.feature_names) {
        (Some(given), Some(recorded)) if given != recorded => {
            return Err(Error::invalid(
                "import features",
                format!("the model was trained on features {recorded:?}, not {given:?}"),
            ))
        }
        (Some(given), _) => given.clone(),
        (None, Some(recorded)) => recorded.clone(),
        (None, None) => {
            return Err(Error::invalid(
                "import features",
                format!("the model records no feature names: state its {n} features with units, e.g. normal_force_N,sliding_velocity_m_per_min"),
            ))
        }
    };
    if names.len() != n {
        return Err(Error::invalid(
            "import features",
            format!("{} names for a model of {n} features", names.len()),
        ));
    }
    for name in &names {
        FeatureQuantity::of_column(&Column::new(name))
            .map_err(|m| Error::invalid("import features", m))?;
    }
    Ok(names)
}

#[cfg(test)]
mod tests {
    use super::*;
    use greybox_core::dataset::PressureConvention;

    #[test]
    fn a_coverage_outside_0_1_is_refused_without_calibration_data_too() {
        let with = |c: f64| ImportOptions {
            coverage: c,
            ..ImportOptions::new(Domain::Stated(Vec::new()))
        };
        for c in [0.0, 1.0, 5.0, -0.5, f64::NAN] {
            let e = check_options(&with(c)).unwrap_err().to_string();
            assert!(e.contains("coverage") && e.contains("(0, 1)"), "{c}: {e}");
        }
        assert!(check_options(&with(DEFAULT_COVERAGE)).is_ok());
    }

    #[test]
    fn a_target_in_per_cent_is_refused() {
        for t in ["cof_pct", "COF (%)", "mu_percent", "Friction_Percent"] {
            let e = check_target_is_a_fraction(t).unwrap_err().to_string();
            assert!(e.contains("target") && e.contains("per cent"), "{t}: {e}");
        }
        for t in ["cof_adhesive", "mu", "cof_apparent", "script"] {
            assert!(check_target_is_a_fraction(t).is_ok(), "{t}");
        }
    }

    fn eq7() -> PinContact {
        PinContact {
            convention: PressureConvention::ArticleEq7,
            ..PinContact::default()
        }
    }

    /// A stated contact must agree with the map the training dataset records; either alone
    /// is recorded as it is.
    #[test]
    fn stated_contact_and_dataset_map_must_agree() {
        let c = eq7();
        let map = ForcePressure {
            pressure_convention: PressureConvention::ArticleEq7,
            pressure_pa_at_1_n: c.pressure_pa(1.0).unwrap(),
        };
        assert_eq!(force_to_pressure(Some(&c), Some(map)).unwrap(), Some(map));
        assert_eq!(force_to_pressure(None, Some(map)).unwrap(), Some(map));
        assert_eq!(force_to_pressure(Some(&c), None).unwrap(), Some(map));
        assert_eq!(force_to_pressure(None, None).unwrap(), None);
        let e = force_to_pressure(Some(&PinContact::default()), Some(map))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("textbook-max") && e.contains("article-eq7"),
            "{e}"
        );
    }
}
