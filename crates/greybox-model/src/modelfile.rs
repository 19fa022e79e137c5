//! Model files: JSON with a schema version, feature names and units, the training domain,
//! the prediction interval and a SHA-256 content hash over everything else.

use crate::column::Column;
use crate::family::{Family, FittedModel, Hyperparameters, Predictor};
use crate::interval::PredictionInterval;
use greybox_core::atomic::write_atomic;
use greybox_core::{Error, Result, SourcePos};
use serde::{Deserialize, Serialize};
use std::path::Path;

pub const SCHEMA: &str = "greybox-model";
/// Version 2 added `force_to_pressure` and `provenance`; version-1 files still load (they
/// lack both, so a law built from one needs its contact stated).
pub const SCHEMA_VERSION: u32 = 2;
const READABLE_VERSIONS: [u64; 2] = [1, 2];

/// How the training dataset's normal force maps to contact pressure: Hertz, p = c·F^(1/3),
/// under the dataset's convention. Recorded by `greybox fit` from a friction dataset so that a
/// law built from the bare model maps pressure to the force it was trained on exactly as the
/// dataset did (never a default convention).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ForcePressure {
    pub pressure_convention: greybox_core::dataset::PressureConvention,
    /// c: the contact pressure at 1 N, Pa.
    pub pressure_pa_at_1_n: f64,
}

/// Closed range of one feature in the training data.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FeatureRange {
    pub min: f64,
    pub max: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelFile {
    pub schema: String,
    pub schema_version: u32,
    pub family: Family,
    pub hyperparameters: Hyperparameters,
    pub features: Vec<Column>,
    pub target: Column,
    /// Per feature, the range seen in training.
    pub training_domain: Vec<FeatureRange>,
    pub n_train: usize,
    pub prediction_interval: PredictionInterval,
    /// Held-out R² from nested cross-validation (for information).
    pub held_out_r2: Option<f64>,
    pub model: FittedModel,
    /// The dataset's force-to-pressure map (friction datasets; absent in version-1 files).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub force_to_pressure: Option<ForcePressure>,
    /// What produced the model: command, version, the dataset with its SHA-256, seed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub provenance: Option<greybox_core::provenance::Provenance>,
    /// Hex SHA-256 of this file's JSON with `content_hash` empty.
    pub content_hash: String,
}

impl ForcePressure {
    /// The map a friction dataset used: its one pressure convention, and c = p / F^(1/3)
    /// agreeing over every row (to 1e-6) for the row's load (the measured one, or for files of
    /// the earlier schema the planned one). `None` when the rows do not share one map.
    pub fn of_dataset(ds: &greybox_core::dataset::FrictionDataset) -> Option<Self> {
        let loads: [fn(&greybox_core::dataset::FrictionRecord) -> Option<f64>; 2] =
            [|r| Some(r.normal_force_n), |r| r.normal_force_planned_n];
        loads.iter().find_map(|load| {
            let rows: Option<Vec<_>> = ds
                .records
                .iter()
                .map(|r| Some((r.pressure_convention, r.hertz_pressure_pa, load(r)?)))
                .collect();
            Self::of_rows(&rows?)
        })
    }

    /// The map of rows (pressure convention, Hertz pressure in Pa, normal force in N) of one
    /// convention and one contact (every p / F^(1/3) equal to 1 part in 10⁶), else `None`:
    /// the training data of an imported model, as columns of a table.
    pub fn of_rows(rows: &[(greybox_core::dataset::PressureConvention, f64, f64)]) -> Option<Self> {
        let (convention, _, _) = *rows.first()?;
        if rows.iter().any(|r| r.0 != convention) {
            return None;
        }
        let cs: Vec<f64> = rows.iter().map(|(_, p, f)| p / f.cbrt()).collect();
        let c = cs[0];
        (c.is_finite() && c > 0.0 && cs.iter().all(|x| (x / c - 1.0).abs() < 1e-6)).then_some(
            ForcePressure {
                pressure_convention: convention,
                pressure_pa_at_1_n: c,
            },
        )
    }
}

/// What to do when a point lies outside the training domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum DomainPolicy {
    /// Predict and flag the point.
    #[default]
    Warn,
    /// Return an error.
    Refuse,
}

greybox_core::choice!(DomainPolicy, "outside", [Warn => "warn", Refuse => "refuse"], text);

/// One prediction with its interval and domain status.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Prediction {
    pub value: f64,
    pub low: f64,
    pub high: f64,
    /// Whether the point lies within the training domain widened by the margin.
    pub in_domain: bool,
}

/// Points that lie outside the training domain widened by the margin: how many of how many,
/// and on which features (the warning of [`DomainPolicy::Warn`], worded once for every
/// surface).
#[derive(Debug, Clone, PartialEq)]
pub struct OutsideDomain {
    /// Points outside on at least one feature.
    pub outside: usize,
    /// Points checked.
    pub total: usize,
    /// The margin, as a fraction of each feature's range.
    pub margin: f64,
    /// Per feature with a point outside: name, trained range and unit.
    pub features: Vec<String>,
}

impl std::fmt::Display for OutsideDomain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} of {} points lie outside the training domain (widened by {} % of each range) on {}: their predictions are extrapolations",
            self.outside,
            self.total,
            self.margin * 100.0,
            self.features.join(", ")
        )
    }
}

impl ModelFile {
    /// Which of `points` (feature rows) lie outside the training domain widened by
    /// `margin` × range per feature; `None` when all lie inside.
    pub fn outside_domain<'a>(
        &self,
        points: impl IntoIterator<Item = &'a [f64]>,
        margin: f64,
    ) -> Option<OutsideDomain> {
        let n = self.features.len();
        let mut on_feature = vec![false; n];
        let (mut outside, mut total) = (0, 0);
        for x in points {
            total += 1;
            let mut out = false;
            for (k, (v, r)) in x.iter().zip(&self.training_domain).enumerate() {
                let w = (r.max - r.min) * margin;
                if *v < r.min - w || *v > r.max + w {
                    on_feature[k] = true;
                    out = true;
                }
            }
            outside += usize::from(out);
        }
        let features = (0..n)
            .filter(|&k| on_feature[k])
            .map(|k| {
                let (c, r) = (&self.features[k], self.training_domain[k]);
                format!("{} (trained on {}..{} {})", c.name, r.min, r.max, c.unit)
            })
            .collect();
        (outside > 0).then_some(OutsideDomain {
            outside,
            total,
            margin,
            features,
        })
    }

    /// SHA-256 of the compact JSON with `content_hash` empty, streamed (a forest of 10⁵ rows
    /// is hundreds of MB of JSON). `content_hash` is restored.
    fn hash(&mut self) -> Result<String> {
        let stated = std::mem::take(&mut self.content_hash);
        let digest = greybox_core::provenance::sha256_json(self);
        self.content_hash = stated;
        digest.map_err(|e| Error::invalid("model file", e.to_string()))
    }

    /// Fill in the content hash.
    pub fn seal(mut self) -> Result<Self> {
        self.content_hash = self.hash()?;
        Ok(self)
    }

    /// Write the file (pretty JSON), streamed into a temporary file that replaces `path`.
    pub fn save(&self, path: &Path) -> Result<()> {
        write_atomic(path, |w| {
            serde_json::to_writer_pretty(w, self).map_err(std::io::Error::other)
        })
    }

    /// Load and verify schema, version and hash.
    pub fn load(path: &Path) -> Result<Self> {
        let text = greybox_core::input::read_regular_text(path, "model file")?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parse and verify a model file's text. The schema and version are read first
    /// ([`greybox_core::json_head`]), then the file straight into its types: no generic JSON
    /// tree of a forest's millions of nodes is held.
    pub fn parse(text: &str, source: &str) -> Result<Self> {
        let pos = || SourcePos::file(source);
        let not_json = |e: serde_json::Error| {
            Error::input(pos().line(e.line() as u64), format!("not JSON: {e}"))
        };
        let head = greybox_core::json_head::read(text).map_err(not_json)?;
        if head.schema() != Some(SCHEMA) {
            return Err(Error::input(
                pos().field("schema"),
                format!("not a greybox model file (schema must be \"{SCHEMA}\")"),
            ));
        }
        let version = head.schema_version.as_ref();
        if !version
            .and_then(|s| s.as_u64())
            .is_some_and(|v| READABLE_VERSIONS.contains(&v))
        {
            let stated = version.map_or_else(|| "missing".to_string(), |v| v.to_string());
            return Err(Error::input(
                pos().field("schema_version"),
                format!("schema version {stated} is not supported (this greybox reads versions 1 and {SCHEMA_VERSION}; a newer greybox wrote it, or the file was edited)"),
            ));
        }
        let mut m: ModelFile = serde_json::from_str(text).map_err(|e| {
            Error::input(
                pos().line(e.line() as u64),
                format!("invalid model file: {e}"),
            )
        })?;
        if m.hash()? != m.content_hash {
            return Err(Error::input(
                pos().field("content_hash"),
                "content hash mismatch: the file was modified or corrupted",
            ));
        }
        m.check_structure(source)?;
        Ok(m)
    }

    /// Everything evaluation relies on (see [`crate::structure`]): indices in range, sizes
    /// consistent, trees acyclic, finite numbers; the error names the field.
    pub fn check_structure(&self, source: &str) -> Result<()> {
        let n = self.features.len();
        let bad = |field: String, message: String| {
            Error::input(SourcePos::file(source).field(field), message)
        };
        if n == 0 {
            return Err(bad(
                "features".into(),
                "a model needs at least one feature".into(),
            ));
        }
        self.check_names(source)?;
        if self.training_domain.len() != n {
            return Err(bad(
                "training_domain".into(),
                format!("{} ranges for {n} features", self.training_domain.len()),
            ));
        }
        for (k, r) in self.training_domain.iter().enumerate() {
            if !(r.min.is_finite() && r.max.is_finite() && r.min <= r.max) {
                return Err(bad(
                    format!("training_domain[{k}]"),
                    format!("{}..{} is not a range", r.min, r.max),
                ));
            }
        }
        let q = self.prediction_interval.half_width;
        if !(q.is_finite() && q >= 0.0) {
            return Err(bad(
                "prediction_interval.half_width".into(),
                format!("{q} is not a width"),
            ));
        }
        let c = self.prediction_interval.coverage;
        let no_interval = c == 0.0 && q == 0.0;
        if !(no_interval || (c > 0.0 && c < 1.0)) {
            return Err(bad(
                "prediction_interval.coverage".into(),
                format!("{c} is not a coverage: a fraction in (0, 1) such as 0.9 for 90 % (0 only with a half-width of 0, for no interval)"),
            ));
        }
        if let Some(fp) = &self.force_to_pressure {
            let c = fp.pressure_pa_at_1_n;
            if !(c.is_finite() && c > 0.0) {
                return Err(bad(
                    "force_to_pressure.pressure_pa_at_1_n".into(),
                    format!("{c} Pa at 1 N is not a contact pressure: Hertz pressure grows with the load, p = c·F^(1/3) with c > 0"),
                ));
            }
        }
        crate::structure::check_model(&self.model, n)
            .map_err(|e| bad(format!("model.{}", e.field), e.message))
    }

    /// Feature and target names (and their units) are words, not lines
    /// ([`greybox_core::escape::check_name`]): they land in deck comments, CSV headers and
    /// plot labels. The error names the file and the field (`features[1].name`).
    pub fn check_names(&self, source: &str) -> Result<()> {
        let named = self
            .features
            .iter()
            .enumerate()
            .map(|(k, c)| (format!("features[{k}]"), c))
            .chain(std::iter::once(("target".to_string(), &self.target)));
        for (field, c) in named {
            for (part, text) in [("name", &c.name), ("unit", &c.unit)] {
                let pos = SourcePos::file(source).field(format!("{field}.{part}"));
                greybox_core::escape::check_name(pos, text)?;
            }
        }
        Ok(())
    }

    /// Whether `x` lies inside the training domain widened by `margin` × range per feature.
    pub fn in_domain(&self, x: &[f64], margin: f64) -> bool {
        x.iter().zip(&self.training_domain).all(|(v, r)| {
            let w = (r.max - r.min) * margin;
            *v >= r.min - w && *v <= r.max + w
        })
    }

    /// Predict with interval and domain check.
    pub fn predict(&self, x: &[f64], policy: DomainPolicy, margin: f64) -> Result<Prediction> {
        if x.len() != self.features.len() {
            return Err(Error::invalid(
                "prediction",
                format!("expected {} features, got {}", self.features.len(), x.len()),
            ));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                "prediction",
                format!("feature '{}' is not finite", self.features[i].name),
            ));
        }
        let in_domain = self.in_domain(x, margin);
        if !in_domain && policy == DomainPolicy::Refuse {
            let detail: Vec<String> = x
                .iter()
                .zip(&self.features)
                .zip(&self.training_domain)
                .map(|((v, f), r)| {
                    format!(
                        "{} = {v} (trained on {}..{} {})",
                        f.name, r.min, r.max, f.unit
                    )
                })
                .collect();
            return Err(Error::invalid(
                "prediction",
                format!("point outside the training domain: {}", detail.join(", ")),
            ));
        }
        let value = self.model.predict_one(x);
        if !value.is_finite() {
            return Err(Error::invalid(
                "prediction",
                format!("the model gives {value} at this point (its weights overflow there)"),
            ));
        }
        let q = self.prediction_interval.half_width;
        Ok(Prediction {
            value,
            low: value - q,
            high: value + q,
            in_domain,
        })
    }
}
