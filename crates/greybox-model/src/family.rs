//! The registry of model families for inference: which families exist, their hyperparameters
//! (plain serde data) and their fitted models, each predicting single points without
//! allocating. Training (the `Regressor` seam) lives in `greybox-learn`.

use crate::ensemble::{BoostParams, ForestParams};
use crate::mlp::{MlpModel, MlpParams};
use crate::svr::{SvrModel, SvrParams};
use crate::tree::TreeEnsemble;
use serde::{Deserialize, Serialize};

pub use crate::predictor::Predictor;

/// The four model families.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    RandomForest,
    Svr,
    GradientBoosting,
    Mlp,
}

impl Family {
    pub const ALL: [Family; 4] = [
        Family::RandomForest,
        Family::Svr,
        Family::GradientBoosting,
        Family::Mlp,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Family::RandomForest => "random-forest",
            Family::Svr => "svr",
            Family::GradientBoosting => "gradient-boosting",
            Family::Mlp => "mlp",
        }
    }
    /// Column title as in the article's tables.
    pub fn title(self) -> &'static str {
        match self {
            Family::RandomForest => "RF",
            Family::Svr => "SV",
            Family::GradientBoosting => "XGBoost-style",
            Family::Mlp => "FFNN",
        }
    }
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == s.trim())
    }
}

impl greybox_core::choice::Choice for Family {
    const FIELD: &'static str = "family";
    const ALL: &'static [Self] = &[
        Family::RandomForest,
        Family::Svr,
        Family::GradientBoosting,
        Family::Mlp,
    ];
    fn name(self) -> &'static str {
        Family::name(self)
    }
}
greybox_core::choice_traits!(Family, text);

/// Hyperparameters of any family (the unit a grid enumerates and a model file stores).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "family", rename_all = "kebab-case")]
pub enum Hyperparameters {
    RandomForest(ForestParams),
    Svr(SvrParams),
    GradientBoosting(BoostParams),
    Mlp(MlpParams),
    /// A model trained elsewhere and imported (`greybox import`): no greybox training
    /// parameters, only where it came from.
    Imported(ImportedFrom),
}

/// Where an imported model came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImportedFrom {
    /// The greybox family it belongs to (tree ensembles: random forest or boosting).
    pub as_family: Family,
    /// The library and its version, e.g. "scikit-learn 1.9.1", "xgboost 3.2.0".
    pub library: String,
    /// The estimator, e.g. "Pipeline(StandardScaler, SVR)", "xgboost.Booster (gbtree)".
    pub estimator: String,
    /// The source file's name and SHA-256, when imported from a file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source: Option<String>,
}

/// A fitted model of any family. In JSON, an object whose `kind` names the family beside the
/// model's own fields (serde's internally tagged form; read by [`FittedModel`]'s
/// `Deserialize`, below).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum FittedModel {
    TreeEnsemble(TreeEnsemble),
    Svr(SvrModel),
    Mlp(MlpModel),
}

/// The `kind` of a [`FittedModel`].
#[derive(Deserialize)]
#[serde(rename_all = "kebab-case")]
enum Kind {
    TreeEnsemble,
    Svr,
    Mlp,
}

/// Reads the internally tagged form without serde's generic buffering of the whole object
/// (which holds a forest's millions of nodes as a tree of boxed values, several times the
/// file's size): when `kind` comes first, as greybox writes it, the other fields go straight
/// to the family's model; otherwise the object is collected first.
impl<'de> Deserialize<'de> for FittedModel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_map(FittedVisitor)
    }
}

struct FittedVisitor;

impl<'de> serde::de::Visitor<'de> for FittedVisitor {
    type Value = FittedModel;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a fitted model: an object with \"kind\" and the model's fields")
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<FittedModel, A::Error> {
        use serde::de::{value::MapAccessDeserializer, Error};
        let first: Option<String> = map.next_key()?;
        if first.as_deref() == Some("kind") {
            let kind: Kind = map.next_value()?;
            return model_of(kind, MapAccessDeserializer::new(map));
        }
        let mut fields = serde_json::Map::new();
        if let Some(key) = first {
            fields.insert(key, map.next_value()?);
        }
        while let Some((key, value)) = map.next_entry::<String, serde_json::Value>()? {
            fields.insert(key, value);
        }
        let kind = fields
            .remove("kind")
            .ok_or_else(|| A::Error::missing_field("kind"))?;
        let kind = Kind::deserialize(kind).map_err(A::Error::custom)?;
        model_of(kind, serde_json::Value::Object(fields)).map_err(A::Error::custom)
    }
}

/// The model of family `kind` from the object's other fields.
fn model_of<'de, D: serde::Deserializer<'de>>(
    kind: Kind,
    rest: D,
) -> Result<FittedModel, D::Error> {
    Ok(match kind {
        Kind::TreeEnsemble => FittedModel::TreeEnsemble(TreeEnsemble::deserialize(rest)?),
        Kind::Svr => FittedModel::Svr(SvrModel::deserialize(rest)?),
        Kind::Mlp => FittedModel::Mlp(MlpModel::deserialize(rest)?),
    })
}

impl Predictor for FittedModel {
    #[inline]
    fn predict_one(&self, x: &[f64]) -> f64 {
        match self {
            FittedModel::TreeEnsemble(m) => m.predict_one(x),
            FittedModel::Svr(m) => m.predict_one(x),
            FittedModel::Mlp(m) => m.predict_one(x),
        }
    }
    fn predict(&self, x: &crate::matrix::Matrix) -> Vec<f64> {
        match self {
            FittedModel::TreeEnsemble(m) => m.predict_rows(x),
            FittedModel::Svr(m) => m.predict(x),
            FittedModel::Mlp(m) => m.predict(x),
        }
    }
}

impl Hyperparameters {
    pub fn family(&self) -> Family {
        match self {
            Hyperparameters::RandomForest(_) => Family::RandomForest,
            Hyperparameters::Svr(_) => Family::Svr,
            Hyperparameters::GradientBoosting(_) => Family::GradientBoosting,
            Hyperparameters::Mlp(_) => Family::Mlp,
            Hyperparameters::Imported(i) => i.as_family,
        }
    }
    /// Short description of the grid-relevant values, e.g. `n_estimators=100`.
    pub fn label(&self) -> String {
        match self {
            Hyperparameters::RandomForest(p) => format!("n_estimators={}", p.n_estimators),
            Hyperparameters::Svr(p) => format!(
                "kernel={}, C={}, epsilon={}",
                p.kernel.name(),
                p.c,
                p.epsilon
            ),
            Hyperparameters::GradientBoosting(p) => {
                format!(
                    "n_estimators={}, max_depth={}, learning_rate={}",
                    p.n_estimators, p.max_depth, p.learning_rate
                )
            }
            Hyperparameters::Mlp(p) => format!(
                "hidden=({}), activation={}, learning_rate={}",
                p.hidden_layers
                    .iter()
                    .map(|h| h.to_string())
                    .collect::<Vec<_>>()
                    .join(","),
                p.activation.name(),
                p.learning_rate
            ),
            Hyperparameters::Imported(i) => format!("imported {} ({})", i.estimator, i.library),
        }
    }
}

#[cfg(test)]
mod fitted_json_tests {
    use super::*;

    fn small_forest() -> FittedModel {
        let mut e = TreeEnsemble::new(2, 0.25, 0.5);
        let nodes = vec![
            crate::tree::Node {
                value: 1.5,
                feature: 1,
                left: 1,
            },
            crate::tree::Node {
                value: -2.0,
                feature: crate::tree::LEAF,
                left: 0,
            },
            crate::tree::Node {
                value: 3.0,
                feature: crate::tree::LEAF,
                left: 0,
            },
        ];
        e.push_tree(nodes, 0);
        FittedModel::TreeEnsemble(e)
    }

    /// `kind` first (as written), last, or absent; an unknown kind is named.
    #[test]
    fn reads_kind_anywhere_and_names_what_is_wrong() {
        let m = small_forest();
        let written = serde_json::to_string(&m).unwrap();
        assert!(
            written.starts_with(r#"{"kind":"tree-ensemble""#),
            "{written}"
        );
        assert_eq!(serde_json::from_str::<FittedModel>(&written).unwrap(), m);
        let mut fields = match serde_json::to_value(&m).unwrap() {
            serde_json::Value::Object(f) => f,
            _ => unreachable!(),
        };
        let kind = fields.remove("kind").unwrap();
        fields.insert("kind".into(), kind);
        let kind_last = serde_json::Value::Object(fields.clone()).to_string();
        assert!(!kind_last.starts_with(r#"{"kind""#), "{kind_last}");
        assert_eq!(serde_json::from_str::<FittedModel>(&kind_last).unwrap(), m);
        fields.remove("kind");
        let none = serde_json::Value::Object(fields).to_string();
        let e = serde_json::from_str::<FittedModel>(&none)
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing field `kind`"), "{e}");
        let other = written.replacen("tree-ensemble", "forest", 1);
        let e = serde_json::from_str::<FittedModel>(&other)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown variant `forest`"), "{e}");
        let e = serde_json::from_str::<FittedModel>("[1, 2]")
            .unwrap_err()
            .to_string();
        assert!(e.contains("invalid type"), "{e}");
    }
}
