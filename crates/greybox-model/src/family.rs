//! The registry of model families for inference: which families exist, their hyperparameters
//! (plain serde data) and their fitted models, each predicting single points without
//! allocating. Training (the `Regressor` seam, the grids) lives in `greybox-learn`.
//!
//! # The registry
//!
//! Every family is listed once, in [`for_each_family!`]: its variant, its name (command line,
//! Python, study files, model files), its column title in the report's tables, the field of
//! its grid in a study's `[fit.grid.*]` and its hyperparameter type. The macro hands that list
//! to a macro of the caller's, which generates the per-family code from it: here [`Family`]
//! (with its [`Choice`](greybox_core::choice::Choice) and titles) and [`Hyperparameters`];
//! in `greybox-learn` the grids (`protocol::Grids`) and training (`model::Train`). No other
//! code matches on the families one by one.
//!
//! Adding a family takes these files (plus a `mod` line in each crate's `lib.rs`):
//!
//! 1. `crates/greybox-model/src/family.rs` — one line in [`for_each_family!`] (and, when the
//!    family brings a new kind of fitted model, a [`FittedModel`] variant with its `Kind`);
//! 2. `crates/greybox-model/src/<family>.rs` — its hyperparameters (serde data with a
//!    `label()`) and, if new, its fitted model (a [`Predictor`]);
//! 3. `crates/greybox-learn/src/<family>.rs` — its `Regressor` (validate, fit) and its grid
//!    (`GridSearch`: the grid type and the candidates it expands to).
//!
//! The test `registry_tests::every_consumer_lists_the_registry` checks that the lists of
//! families outside Rust code (the `--families` help, the Python docstring, the docs) name
//! the registry's families, in its order.

use crate::mlp::MlpModel;
use crate::svr::SvrModel;
use crate::tree::TreeEnsemble;
use serde::{Deserialize, Serialize};

pub use crate::predictor::Predictor;

/// The registry of model families (see the [module doc](self)): calls `$then! { … }` with one
/// entry per family, in the order they are listed to users and fitted by default:
///
/// `Variant { name: "…", title: "…", grid: field, params: Type },`
///
/// ```
/// macro_rules! names {
///     ($($v:ident { name: $n:literal, title: $t:literal, grid: $g:ident, params: $p:ty },)+) => {
///         [$($n),+]
///     };
/// }
/// let names = greybox_model::for_each_family!(names);
/// assert_eq!(names, ["random-forest", "svr", "gradient-boosting", "mlp"]);
/// ```
#[macro_export]
macro_rules! for_each_family {
    ($then:ident) => {
        $then! {
            RandomForest {
                name: "random-forest",
                title: "RF",
                grid: random_forest,
                params: $crate::ensemble::ForestParams
            },
            Svr {
                name: "svr",
                title: "SV",
                grid: svr,
                params: $crate::svr::SvrParams
            },
            GradientBoosting {
                name: "gradient-boosting",
                title: "XGBoost-style",
                grid: gradient_boosting,
                params: $crate::ensemble::BoostParams
            },
            Mlp {
                name: "mlp",
                title: "FFNN",
                grid: mlp,
                params: $crate::mlp::MlpParams
            },
        }
    };
}

/// [`Family`], its titles and [`Hyperparameters`] from the registry's entries.
macro_rules! define_families {
    ($($v:ident { name: $n:literal, title: $t:literal, grid: $g:ident, params: $p:ty },)+) => {
        /// The model families (the registry: [`for_each_family!`]).
        #[derive(
            Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
        )]
        pub enum Family {
            $(
                #[doc = concat!("`", $n, "` (", $t, ")")]
                #[serde(rename = $n)]
                $v,
            )+
        }

        greybox_core::choice!(Family, "family", [$($v => $n),+], text);

        impl Family {
            /// Column title as in the article's tables.
            pub fn title(self) -> &'static str {
                match self {
                    $(Family::$v => $t),+
                }
            }
        }

        /// Hyperparameters of any family (the unit a grid enumerates and a model file stores).
        #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
        #[serde(tag = "family")]
        pub enum Hyperparameters {
            $(
                #[doc = concat!("`", $n, "`")]
                #[serde(rename = $n)]
                $v($p),
            )+
            /// A model trained elsewhere and imported (`greybox import`): no greybox training
            /// parameters, only where it came from.
            #[serde(rename = "imported")]
            Imported(ImportedFrom),
        }

        impl Hyperparameters {
            /// The family these hyperparameters belong to.
            pub fn family(&self) -> Family {
                match self {
                    $(Hyperparameters::$v(_) => Family::$v,)+
                    Hyperparameters::Imported(i) => i.as_family,
                }
            }
            /// Short description of the grid-relevant values, e.g. `n_estimators=100`.
            pub fn label(&self) -> String {
                match self {
                    $(Hyperparameters::$v(p) => p.label(),)+
                    Hyperparameters::Imported(i) => {
                        format!("imported {} ({})", i.estimator, i.library)
                    }
                }
            }
        }
    };
}

crate::for_each_family!(define_families);

impl Family {
    /// Every family, in the registry's order.
    pub const ALL: &'static [Family] = <Family as greybox_core::choice::Choice>::ALL;
    /// The family's name (its [`Choice`](greybox_core::choice::Choice) name).
    pub fn name(self) -> &'static str {
        greybox_core::choice::Choice::name(self)
    }
    /// The family named `s` (surrounding blanks ignored), if any.
    pub fn parse(s: &str) -> Option<Self> {
        <Self as greybox_core::choice::Choice>::parse_choice(s.trim()).ok()
    }
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

impl From<TreeEnsemble> for FittedModel {
    fn from(m: TreeEnsemble) -> Self {
        FittedModel::TreeEnsemble(m)
    }
}
impl From<SvrModel> for FittedModel {
    fn from(m: SvrModel) -> Self {
        FittedModel::Svr(m)
    }
}
impl From<MlpModel> for FittedModel {
    fn from(m: MlpModel) -> Self {
        FittedModel::Mlp(m)
    }
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

#[cfg(test)]
mod registry_tests {
    use super::*;
    use greybox_core::choice::Choice;

    /// A file of the workspace, relative to its root.
    fn workspace_file(path: &str) -> String {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        std::fs::read_to_string(root.join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
    }

    /// The text between `before` and the next `after` on the line holding `before`.
    fn between<'a>(text: &'a str, before: &str, after: &str, path: &str) -> &'a str {
        let start = text
            .find(before)
            .unwrap_or_else(|| panic!("{path}: no '{before}'"))
            + before.len();
        let len = text[start..]
            .find(after)
            .unwrap_or_else(|| panic!("{path}: no '{after}' after '{before}'"));
        &text[start..start + len]
    }

    /// The registry's names as a list in prose: "a, b, c or d".
    fn prose_list() -> String {
        let names = Family::names();
        let (last, rest) = names.split_last().unwrap();
        format!("{} or {last}", rest.join(", "))
    }

    /// The lists of families outside the registry's Rust code name its families, in order:
    /// the `--families` flag takes the registry's parser (its help and errors list
    /// [`Family::names`]; `cli/tests/cli_learn.rs` sees them) and the Python `Model.family`
    /// docstring; and the extension table of docs/architecture.md names the registry.
    /// Adding a family without updating them fails here.
    #[test]
    fn every_consumer_lists_the_registry() {
        let path = "crates/greybox-pipeline/src/settings/fit.rs";
        let flag = between(
            &workspace_file(path),
            "/// Model families,",
            "pub families",
            path,
        )
        .to_string();
        assert!(
            flag.contains("value_parser = choice::<Family>()"),
            "{path}: {flag}"
        );
        let path = "crates/greybox-py/python/greybox/__init__.py";
        let py = workspace_file(path);
        let doc = between(
            &py,
            "def family(self) -> str:\n        \"\"\"",
            ".\"\"\"",
            path,
        );
        assert_eq!(doc, prose_list(), "{path}");
        let path = "docs/architecture.md";
        let row = between(&workspace_file(path), "| a model family |", "\n", path).to_string();
        assert!(row.contains("`for_each_family!`"), "{path}: {row}");
    }

    /// Every family's name, title and hyperparameter tag come from the one list.
    #[test]
    fn names_titles_and_tags_agree() {
        assert_eq!(Family::ALL.len(), 4);
        for &f in Family::ALL {
            assert_eq!(Family::parse(f.name()), Some(f));
            assert_eq!(f.name().parse::<Family>().unwrap(), f);
            assert_eq!(
                serde_json::to_string(&f).unwrap(),
                format!("\"{}\"", f.name())
            );
            assert!(!f.title().is_empty());
        }
        let titles: Vec<_> = Family::ALL.iter().map(|f| f.title()).collect();
        assert_eq!(titles, ["RF", "SV", "XGBoost-style", "FFNN"]);
        let hp = Hyperparameters::Svr(crate::svr::SvrParams::default());
        let json = serde_json::to_value(&hp).unwrap();
        assert_eq!(json["family"], "svr");
        assert_eq!(hp.family(), Family::Svr);
    }
}
