//! The friction models a suite material is cut with, each run on the same conditions and
//! reported side by side:
//!
//! * `coulomb-calibrated` — one constant μ\* calibrated on the calibration conditions (the
//!   suite's original model; see the module docs of [`super`]);
//! * `law` — a law file (any law greybox loads: a grey-box law from a tribometer campaign, a
//!   model or table file, a classical law) used as it is, or with one factor on its μ
//!   calibrated (`scale = [low, high]`);
//! * `calibrated` — a law with few parameters (an inline law spec, e.g. μ(v) as a power law
//!   of sliding velocity, μ(p, v) with a shear cap): its shape over a grid of its named
//!   numeric fields and its level as a factor, fitted on the calibration conditions only
//!   ([`super::fit`]).

use anyhow::{bail, Context, Result};
use greybox_core::FrictionLaw;
use greybox_friction::spec::{LawFile, LawSpec};
use greybox_friction::spec_fields::LawFields;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The kinds of friction model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VariantKind {
    CoulombCalibrated,
    Law,
    Calibrated,
}

greybox_core::choice!(VariantKind, "friction.kind", [CoulombCalibrated => "coulomb-calibrated", Law => "law", Calibrated => "calibrated"]);

/// The most shapes a calibrated law's grid may have (each costs two cuts per calibration
/// condition).
pub const MAX_SHAPES: usize = 64;
/// The factor's bracket of a calibrated law without `scale`.
pub const DEFAULT_SCALE: [f64; 2] = [0.5, 2.0];

/// One field of a calibrated law's grid: a dotted path of the law and the values tried.
#[derive(Debug, Clone, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct GridField {
    pub field: String,
    pub values: Vec<f64>,
}

/// One `[[material.friction]]` entry of a suite file: its `kind` and the fields that kind
/// takes (a field another kind takes is an unknown field here, named by the reader).
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum FrictionVariant {
    /// One constant μ\* calibrated over the material's `mu_bracket`.
    CoulombCalibrated {
        /// How the results name it (default: the kind).
        #[serde(default)]
        name: Option<String>,
    },
    /// A law file used as it is, or with one factor on its μ calibrated.
    Law {
        /// Default: the file's name (`… (scaled)` with `scale`).
        #[serde(default)]
        name: Option<String>,
        /// The law file, relative to the suite file.
        file: String,
        /// The bracket of the calibrated factor on the law's μ (without it the law runs as
        /// it is).
        #[serde(default)]
        scale: Option<[f64; 2]>,
    },
    /// A law with few parameters: its shape over a grid of its numeric fields and its level
    /// as a factor.
    Calibrated {
        /// Default: the kind.
        #[serde(default)]
        name: Option<String>,
        /// The law, as a law file's content (relative paths against the suite's directory).
        law: serde_json::Value,
        /// The grid of the law's numeric fields (dotted paths) whose shapes are tried; every
        /// combination of their values is one shape.
        #[serde(default)]
        grid: Vec<GridField>,
        /// The bracket of the factor on μ (default [`DEFAULT_SCALE`]).
        #[serde(default)]
        scale: Option<[f64; 2]>,
    },
}

impl FrictionVariant {
    /// Today's model, what a suite material without `friction` runs.
    pub fn coulomb_calibrated() -> Self {
        FrictionVariant::CoulombCalibrated { name: None }
    }

    /// The variant's kind.
    pub fn kind(&self) -> VariantKind {
        match self {
            FrictionVariant::CoulombCalibrated { .. } => VariantKind::CoulombCalibrated,
            FrictionVariant::Law { .. } => VariantKind::Law,
            FrictionVariant::Calibrated { .. } => VariantKind::Calibrated,
        }
    }

    /// The name the results give it, where the suite states one.
    pub fn name(&self) -> Option<&str> {
        match self {
            FrictionVariant::CoulombCalibrated { name }
            | FrictionVariant::Law { name, .. }
            | FrictionVariant::Calibrated { name, .. } => name.as_deref(),
        }
    }

    /// The law file this variant reads, resolved against `base`.
    pub fn file_path(&self, base: &Path) -> Option<PathBuf> {
        match self {
            FrictionVariant::Law { file, .. } => Some(base.join(file)),
            _ => None,
        }
    }
}

/// How a model's law is made from a shape's values and the factor: as a spec that names its
/// files by absolute path (so that it builds the same in a case that runs elsewhere).
type MakeLaw = Box<dyn Fn(&[f64], f64) -> Result<LawSpec> + Send + Sync>;

/// A model's law at one shape and factor: its spec (what a sweep case is given) and the law
/// built from it (what a cut in this process runs).
#[derive(Clone)]
pub struct ModelLaw {
    pub spec: Arc<LawSpec>,
    pub law: Arc<dyn FrictionLaw>,
}

/// A variant ready to run: its label, its shapes and factor bracket, and how its law is
/// made (see [`super::fit`]).
pub struct Model {
    pub label: String,
    pub kind: VariantKind,
    /// The grid's fields (none but for a calibrated law).
    pub fields: Vec<String>,
    /// The shapes tried, one value per field each (one empty shape without a grid).
    pub shapes: Vec<Vec<f64>>,
    /// The bracket of the factor on μ (`None`: the law runs as it is).
    pub factor: Option<[f64; 2]>,
    make: MakeLaw,
}

impl Model {
    /// The law of `shape` at factor `s` (ignored without a factor).
    pub fn law(&self, shape: &[f64], s: f64) -> Result<ModelLaw> {
        let spec = (self.make)(shape, s)?;
        // every path of the spec is absolute: the directory is not used
        let law = spec.build(Path::new("."))?;
        Ok(ModelLaw {
            spec: Arc::new(spec),
            law: law.into(),
        })
    }

    /// Builds the variant of material `material` (Coulomb μ searched over `mu_bracket`),
    /// relative paths against `base`.
    pub fn build(
        v: &FrictionVariant,
        material: &str,
        mu_bracket: [f64; 2],
        base: &Path,
    ) -> Result<Model> {
        let e = Entry { v, material };
        let label = v
            .name()
            .map_or_else(|| v.kind().to_string(), str::to_string);
        let (label, fields, shapes, factor, make) = match v {
            FrictionVariant::CoulombCalibrated { .. } => {
                let make: MakeLaw = Box::new(|_: &[f64], s: f64| Ok(LawSpec::Coulomb { mu: s }));
                (label, Vec::new(), vec![Vec::new()], Some(mu_bracket), make)
            }
            FrictionVariant::Law { file, scale, .. } => {
                let (label, factor, make) = e.law_file(&base.join(file), *scale)?;
                (label, Vec::new(), vec![Vec::new()], factor, make)
            }
            FrictionVariant::Calibrated {
                law, grid, scale, ..
            } => {
                let (fields, shapes, factor, make) = e.calibrated(law, grid, *scale, base)?;
                (label, fields, shapes, Some(factor), make)
            }
        };
        Ok(Model {
            label,
            kind: v.kind(),
            fields,
            shapes,
            factor,
            make,
        })
    }
}

/// A calibrated law's grid fields, shapes, factor bracket and law.
type Calibrated = (Vec<String>, Vec<Vec<f64>>, [f64; 2], MakeLaw);

/// A suite entry being built, for its error messages.
struct Entry<'a> {
    v: &'a FrictionVariant,
    material: &'a str,
}

impl Entry<'_> {
    fn at(&self, what: &str) -> String {
        format!(
            "material {}: friction {} ({what})",
            self.material,
            self.v.kind()
        )
    }

    fn scale(&self, r: [f64; 2]) -> Result<[f64; 2]> {
        if !(r[0] > 0.0 && r[1] > r[0] && r[1].is_finite()) {
            bail!(
                "{}: expected [low, high] with 0 < low < high, got {r:?}",
                self.at("scale")
            );
        }
        Ok(r)
    }

    /// A `law` entry (its file at `path`): its label, factor bracket and law.
    fn law_file(
        &self,
        path: &Path,
        scale: Option<[f64; 2]>,
    ) -> Result<(String, Option<[f64; 2]>, MakeLaw)> {
        let file = LawFile::read(path)
            .with_context(|| format!("{}: {}", self.at("file"), path.display()))?;
        let law = file.spec();
        // a law that does not build fails before any cut
        law.build(Path::new("."))
            .with_context(|| format!("{}: {}", self.at("file"), path.display()))?;
        let label = self.v.name().map(str::to_string).unwrap_or_else(|| {
            let stem = path
                .file_stem()
                .map_or("law".into(), |s| s.to_string_lossy().into_owned());
            if scale.is_some() {
                format!("{stem} (scaled)")
            } else {
                stem
            }
        });
        let factor = scale.map(|r| self.scale(r)).transpose()?;
        let make: MakeLaw = Box::new(move |_: &[f64], s: f64| {
            Ok(match factor {
                None => law.clone(),
                Some(_) => LawSpec::Scaled {
                    factor: s,
                    inner: Box::new(law.clone()),
                },
            })
        });
        Ok((label, factor, make))
    }

    /// A `calibrated` entry: its grid's fields and shapes, factor bracket and law.
    fn calibrated(
        &self,
        law: &serde_json::Value,
        grid: &[GridField],
        scale: Option<[f64; 2]>,
        base: &Path,
    ) -> Result<Calibrated> {
        let value = law.clone();
        let spec: LawSpec = serde_json::from_value(value).with_context(|| self.at("law"))?;
        let fields = LawFields::new(&spec.resolved(base))?;
        let shapes = grid_shapes(grid).with_context(|| self.at("grid"))?;
        for g in grid {
            fields.get(&g.field).with_context(|| self.at("grid"))?;
        }
        let names: Vec<String> = grid.iter().map(|g| g.field.clone()).collect();
        let make: MakeLaw = {
            let names = names.clone();
            Box::new(move |shape: &[f64], s: f64| {
                let values: Vec<(String, f64)> =
                    names.iter().cloned().zip(shape.iter().copied()).collect();
                Ok(LawSpec::Scaled {
                    factor: s,
                    inner: Box::new(fields.with(&values)?),
                })
            })
        };
        // every shape must build: a bad grid fails before any cut
        for shape in &shapes {
            make(shape, 1.0)
                .and_then(|spec| Ok(spec.build(Path::new("."))?))
                .with_context(|| format!("{}: shape {shape:?}", self.at("grid")))?;
        }
        let factor = self.scale(scale.unwrap_or(DEFAULT_SCALE))?;
        Ok((names, shapes, factor, make))
    }
}

/// Every combination of the grid's values (the first field varying slowest); one empty
/// shape without a grid.
fn grid_shapes(grid: &[GridField]) -> Result<Vec<Vec<f64>>> {
    let mut shapes: Vec<Vec<f64>> = vec![Vec::new()];
    for g in grid {
        if g.values.is_empty() || g.values.iter().any(|x| !x.is_finite()) {
            bail!("field '{}': expected finite values, at least one", g.field);
        }
        if shapes.len().saturating_mul(g.values.len()) > MAX_SHAPES {
            bail!("the grid has more than {MAX_SHAPES} shapes (each costs two cuts per calibration condition)");
        }
        shapes = shapes
            .iter()
            .flat_map(|s| {
                g.values.iter().map(move |&x| {
                    let mut t = s.clone();
                    t.push(x);
                    t
                })
            })
            .collect();
    }
    Ok(shapes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn variant(toml_text: &str) -> FrictionVariant {
        toml::from_str(toml_text).unwrap()
    }

    fn build(v: &FrictionVariant) -> Result<Model> {
        Model::build(v, "Ti6Al4V", [0.2, 0.8], Path::new("."))
    }

    #[test]
    fn a_calibrated_law_tries_every_shape_of_its_grid_times_a_factor() {
        let v = variant(
            "kind = \"calibrated\"\nname = \"mu(p,v)\"\nlaw = { law = \"power\", mu_ref = 0.5, p_ref_MPa = 1000.0, v_ref_m_per_min = 10.0 }\ngrid = [{ field = \"a\", values = [-0.2, 0.0] }, { field = \"b\", values = [-0.5, -0.25, 0.0] }]\n",
        );
        let m = build(&v).unwrap();
        assert_eq!(m.shapes.len(), 6);
        assert_eq!(m.shapes[1], vec![-0.2, -0.25]);
        assert_eq!(m.factor, Some(DEFAULT_SCALE));
        // a = 0, b = −0.5, factor 0.8: 0.8 · 0.5 · (40/10)^−0.5 = 0.2 at 40 m/min
        let law = m.law(&[0.0, -0.5], 0.8).unwrap().law;
        let s = greybox_core::ContactState::new(1e9, 40.0 / 60.0);
        assert!((law.mu(&s) - 0.2).abs() < 1e-12);
    }

    #[test]
    fn bad_entries_are_named_before_any_cut() {
        let e = |t: &str| format!("{:#}", build(&variant(t)).err().unwrap());
        let m = e("kind = \"calibrated\"\nlaw = { law = \"power\", mu_ref = 0.5, p_ref_MPa = 1000.0, v_ref_m_per_min = 10.0 }\ngrid = [{ field = \"c\", values = [0.0] }]\n");
        assert!(m.contains("'c'") && m.contains("mu_ref"), "{m}");
        let m = e("kind = \"calibrated\"\nlaw = { law = \"power\", mu_ref = 0.5, p_ref_MPa = 1000.0, v_ref_m_per_min = 10.0 }\ngrid = [{ field = \"b\", values = [9.0] }]\n");
        assert!(m.contains("shape [9.0]") && m.contains("b must lie"), "{m}");
        let many: Vec<String> = (0..9).map(|k| format!("{}", -0.05 * k as f64)).collect();
        let m = e(&format!("kind = \"calibrated\"\nlaw = {{ law = \"power\", mu_ref = 0.5, p_ref_MPa = 1000.0, v_ref_m_per_min = 10.0 }}\ngrid = [{{ field = \"a\", values = [{0}] }}, {{ field = \"b\", values = [{0}] }}]\n", many.join(", ")));
        assert!(m.contains("more than 64 shapes"), "{m}");
        // what a kind does not take, or lacks, is the reader's error, naming the field
        let read = |t: &str| {
            toml::from_str::<FrictionVariant>(t)
                .unwrap_err()
                .to_string()
        };
        let m = read("kind = \"coulomb-calibrated\"\nfile = \"x.json\"\n");
        assert!(m.contains("unknown field `file`"), "{m}");
        let m = read("kind = \"law\"\n");
        assert!(m.contains("missing field `file`"), "{m}");
        let m = read("kind = \"calibrated\"\nfile = \"x.json\"\n");
        assert!(m.contains("unknown field `file`"), "{m}");
        let m = e("kind = \"law\"\nfile = \"x.json\"\nscale = [1.0, 0.5]\n");
        assert!(m.contains("x.json"), "{m}");
    }
}
