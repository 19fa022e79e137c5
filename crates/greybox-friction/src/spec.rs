//! Law files: JSON documents that describe any friction law. Units are in the field names.
//!
//! ```json
//! {"law": "grey-box",
//!  "inner": {"law": "learned", "model": "models/gradient-boosting.json"},
//!  "outside": {"law": "power-fit"},
//!  "blend_fraction": 0.1, "shear_cap_k_MPa": 450, "clamp": [0.05, 1.0]}
//! ```
//! A model file from `greybox fit` can be given directly wherever a law file is expected; it
//! is read as `{"law": "learned", "model": <that file>}`. Relative paths are resolved against
//! the directory of the file that names them.

use crate::classical::{
    Coulomb, ExponentialVelocity, ShearFactor, ThermalSoftening, UsuiChilds, Zorev,
};
use crate::compose::{Scaled, ShearCapped};
use crate::greybox::{GreyBoxLaw, PowerLaw};
use crate::learned::LearnedLaw;
use crate::table_file::{parse_table, read_table, TABLE_SCHEMA};
use greybox_contact::PinContact;
use greybox_core::physics::Quantity;
use greybox_core::rules::Rules;
use greybox_core::{units, Error, FrictionLaw, Result, SourcePos};
use greybox_model::modelfile::{ModelFile, SCHEMA as MODEL_SCHEMA};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "law", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LawSpec {
    Coulomb {
        mu: f64,
    },
    ShearFactor {
        m: f64,
        #[serde(rename = "k_MPa")]
        k_mpa: f64,
    },
    Zorev {
        mu: f64,
        #[serde(rename = "k_MPa")]
        k_mpa: f64,
    },
    UsuiChilds {
        mu: f64,
        m: f64,
        n: f64,
        #[serde(rename = "k_MPa")]
        k_mpa: f64,
    },
    ExponentialVelocity {
        mu_static: f64,
        mu_dynamic: f64,
        v_c_m_per_min: f64,
    },
    ThermalSoftening {
        mu0: f64,
        #[serde(rename = "t0_K")]
        t0_k: f64,
        #[serde(rename = "tm_K")]
        tm_k: f64,
        q: f64,
    },
    /// A model file; `contact` maps pressure to normal force for models trained on forces.
    Learned {
        model: PathBuf,
        #[serde(default)]
        contact: Option<PinContact>,
    },
    /// The power law μ = μ_ref (p/p_ref)^a (v/v_ref)^b fitted to the grey-box inner law.
    PowerFit,
    /// The power law μ = μ_ref (p/p_ref)^a (v/v_ref)^b with its parameters given; `a = 0` is a
    /// law of sliding velocity alone, and with `shear_cap_k_MPa` μ ≤ k/p (the pressure-dependent
    /// form of the article's grey-box composition).
    Power {
        mu_ref: f64,
        #[serde(rename = "p_ref_MPa")]
        p_ref_mpa: f64,
        v_ref_m_per_min: f64,
        #[serde(default)]
        a: f64,
        #[serde(default)]
        b: f64,
        #[serde(default, rename = "shear_cap_k_MPa")]
        shear_cap_k_mpa: Option<f64>,
        /// Floor and ceiling of μ (a power law of speed grows without bound as v → 0).
        #[serde(default)]
        clamp: Option<(f64, f64)>,
    },
    /// `factor` × the μ of `inner` (one calibrated correction of a measured law).
    Scaled {
        factor: f64,
        inner: Box<LawSpec>,
    },
    GreyBox {
        inner: Box<LawSpec>,
        outside: Box<LawSpec>,
        #[serde(default = "default_blend")]
        blend_fraction: f64,
        #[serde(default, rename = "shear_cap_k_MPa")]
        shear_cap_k_mpa: Option<f64>,
        #[serde(default)]
        clamp: Option<(f64, f64)>,
    },
    /// A table written by `greybox export --format table` (any kind and schema version, see
    /// [`crate::table_file`]).
    Table {
        file: PathBuf,
    },
}

/// Check law parameters against the physics table ([`greybox_core::physics`]): each
/// `(field, quantity, SI value)` must lie in its possible range.
fn physical(fields: &[(&str, Quantity, f64)]) -> Result<()> {
    let mut r = Rules::new("law");
    for &(f, q, v) in fields {
        r.physics(f, q, v);
    }
    r.finish()
}

fn default_blend() -> f64 {
    0.1
}

fn positive(what: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            "law",
            format!("{what} must be positive, got {v}"),
        ))
    }
}

/// Usui–Childs' law from its spec's numbers (k in MPa), checked.
fn usui_childs(mu: f64, m: f64, n: f64, k_mpa: f64) -> Result<Box<dyn FrictionLaw>> {
    let mpa = units::PA_PER_MPA;
    positive("k_MPa", k_mpa)?;
    positive("m", m)?;
    positive("n", n)?;
    physical(&[
        ("mu", Quantity::Mu, mu),
        ("m", Quantity::ShearFactor, m),
        ("k_MPa", Quantity::ShearFlowStress, k_mpa * mpa),
    ])?;
    Ok(Box::new(UsuiChilds {
        mu,
        m,
        n,
        k_pa: k_mpa * mpa,
    }))
}

/// The exponential decay with sliding speed from its spec's numbers (v_c in m/min), checked.
fn exponential_velocity(
    mu_static: f64,
    mu_dynamic: f64,
    v_c_m_per_min: f64,
) -> Result<Box<dyn FrictionLaw>> {
    positive("v_c_m_per_min", v_c_m_per_min)?;
    physical(&[
        ("mu_static", Quantity::Mu, mu_static),
        ("mu_dynamic", Quantity::Mu, mu_dynamic),
    ])?;
    Ok(Box::new(ExponentialVelocity {
        mu_static,
        mu_dynamic,
        v_c_m_s: units::m_per_min_to_m_per_s(v_c_m_per_min),
    }))
}

/// The largest power-law exponent accepted: |a|, |b| beyond it make μ change by more than a
/// factor 10⁵ over one decade of pressure or speed, which no measured law does.
const MAX_POWER_EXPONENT: f64 = 5.0;

/// The power law from its spec's numbers (p_ref and k in MPa, v_ref in m/min), checked;
/// without a clamp μ is unbounded (the simulator's sticking bounds τ where μ grows large).
fn power(
    mu_ref: f64,
    p_ref_mpa: f64,
    v_ref_m_per_min: f64,
    [a, b]: [f64; 2],
    shear_cap_k_mpa: Option<f64>,
    clamp: Option<(f64, f64)>,
) -> Result<Box<dyn FrictionLaw>> {
    let mpa = units::PA_PER_MPA;
    positive("p_ref_MPa", p_ref_mpa)?;
    positive("v_ref_m_per_min", v_ref_m_per_min)?;
    physical(&[
        ("mu_ref", Quantity::Mu, mu_ref),
        ("p_ref_MPa", Quantity::ContactPressure, p_ref_mpa * mpa),
        (
            "v_ref_m_per_min",
            Quantity::SlidingVelocity,
            units::m_per_min_to_m_per_s(v_ref_m_per_min),
        ),
    ])?;
    for (name, e) in [("a", a), ("b", b)] {
        if !(e.abs() <= MAX_POWER_EXPONENT) {
            return Err(Error::invalid(
                "law",
                format!("power law: {name} must lie in [-{MAX_POWER_EXPONENT}, {MAX_POWER_EXPONENT}], got {e}"),
            ));
        }
    }
    let law = Box::new(PowerLaw {
        mu_ref,
        p_ref_pa: p_ref_mpa * mpa,
        v_ref_m_s: units::m_per_min_to_m_per_s(v_ref_m_per_min),
        a,
        b,
        mu_min: clamp.map_or(0.0, |c| c.0),
        mu_max: clamp.map_or(f64::INFINITY, |c| c.1),
    });
    if let Some((lo, hi)) = clamp {
        physical(&[
            ("clamp[0]", Quantity::Mu, lo),
            ("clamp[1]", Quantity::Mu, hi),
        ])?;
        if !(lo <= hi) {
            return Err(Error::invalid(
                "law",
                format!("power law: clamp needs min ≤ max, got [{lo}, {hi}]"),
            ));
        }
    }
    Ok(match shear_cap_k_mpa {
        None => law,
        Some(k) => {
            positive("shear_cap_k_MPa", k)?;
            physical(&[("shear_cap_k_MPa", Quantity::ShearFlowStress, k * mpa)])?;
            Box::new(ShearCapped {
                k_pa: k * mpa,
                inner: law,
            })
        }
    })
}

/// Thermal softening from its spec's numbers (temperatures in K), checked.
fn thermal_softening(mu0: f64, t0_k: f64, tm_k: f64, q: f64) -> Result<Box<dyn FrictionLaw>> {
    physical(&[
        ("mu0", Quantity::Mu, mu0),
        ("t0_K", Quantity::Temperature, t0_k),
        ("tm_K", Quantity::Temperature, tm_k),
    ])?;
    if !(tm_k > t0_k) {
        return Err(Error::invalid("law", "thermal softening needs tm_K > t0_K"));
    }
    Ok(Box::new(ThermalSoftening { mu0, t0_k, tm_k, q }))
}

impl LawSpec {
    /// Build the law; relative paths are resolved against `base`.
    pub fn build(&self, base: &Path) -> Result<Box<dyn FrictionLaw>> {
        let mpa = units::PA_PER_MPA;
        Ok(match self {
            LawSpec::Coulomb { mu } => {
                physical(&[("mu", Quantity::Mu, *mu)])?;
                Box::new(Coulomb { mu: *mu })
            }
            LawSpec::ShearFactor { m, k_mpa } => {
                positive("k_MPa", *k_mpa)?;
                physical(&[
                    ("m", Quantity::ShearFactor, *m),
                    ("k_MPa", Quantity::ShearFlowStress, k_mpa * mpa),
                ])?;
                Box::new(ShearFactor {
                    m: *m,
                    k_pa: k_mpa * mpa,
                })
            }
            LawSpec::Zorev { mu, k_mpa } => {
                positive("k_MPa", *k_mpa)?;
                physical(&[
                    ("mu", Quantity::Mu, *mu),
                    ("k_MPa", Quantity::ShearFlowStress, k_mpa * mpa),
                ])?;
                Box::new(Zorev {
                    mu: *mu,
                    k_pa: k_mpa * mpa,
                })
            }
            LawSpec::UsuiChilds { mu, m, n, k_mpa } => usui_childs(*mu, *m, *n, *k_mpa)?,
            LawSpec::ExponentialVelocity {
                mu_static,
                mu_dynamic,
                v_c_m_per_min,
            } => exponential_velocity(*mu_static, *mu_dynamic, *v_c_m_per_min)?,
            LawSpec::ThermalSoftening { mu0, t0_k, tm_k, q } => {
                thermal_softening(*mu0, *t0_k, *tm_k, *q)?
            }
            LawSpec::Learned { model, contact } => {
                let path = resolve(base, model);
                learned(ModelFile::load(&path)?, contact.as_ref(), &path)?
            }
            LawSpec::PowerFit => {
                return Err(Error::invalid(
                    "law",
                    "power-fit is only valid as the 'outside' law of a grey-box law",
                ))
            }
            LawSpec::GreyBox {
                inner,
                outside,
                blend_fraction,
                shear_cap_k_mpa,
                clamp,
            } => {
                let inner = inner.build(base)?;
                let outside: Box<dyn FrictionLaw> = match **outside {
                    LawSpec::PowerFit => Box::new(PowerLaw::fit_to(inner.as_ref(), 25)?),
                    ref o => o.build(base)?,
                };
                Box::new(GreyBoxLaw::new(
                    inner,
                    outside,
                    *blend_fraction,
                    shear_cap_k_mpa.map(|k| k * mpa),
                    *clamp,
                )?)
            }
            LawSpec::Table { file } => read_table(&resolve(base, file))?.into_law(),
            LawSpec::Power {
                mu_ref,
                p_ref_mpa,
                v_ref_m_per_min,
                a,
                b,
                shear_cap_k_mpa,
                clamp,
            } => power(
                *mu_ref,
                *p_ref_mpa,
                *v_ref_m_per_min,
                [*a, *b],
                *shear_cap_k_mpa,
                *clamp,
            )?,
            LawSpec::Scaled { factor, inner } => {
                positive("factor", *factor)?;
                Box::new(Scaled {
                    factor: *factor,
                    inner: inner.build(base)?.into(),
                })
            }
        })
    }
}

impl LawSpec {
    /// The files this law reads (model files and tables, nested laws included), relative
    /// paths resolved against `base`.
    pub fn files(&self, base: &Path) -> Vec<PathBuf> {
        match self {
            LawSpec::Learned { model, .. } => vec![resolve(base, model)],
            LawSpec::Table { file } => vec![resolve(base, file)],
            LawSpec::GreyBox { inner, outside, .. } => {
                let mut v = inner.files(base);
                v.extend(outside.files(base));
                v
            }
            LawSpec::Scaled { inner, .. } => inner.files(base),
            _ => Vec::new(),
        }
    }

    /// The same law with every relative path it names resolved against `base` and made
    /// absolute: a law that builds the same from any directory (e.g. written inline into a
    /// set-up that runs elsewhere).
    pub fn resolved(&self, base: &Path) -> LawSpec {
        let abs = |p: &Path| {
            let p = resolve(base, p);
            std::path::absolute(&p).unwrap_or(p)
        };
        let boxed = |l: &LawSpec| Box::new(l.resolved(base));
        match self {
            LawSpec::Learned { model, contact } => LawSpec::Learned {
                model: abs(model),
                contact: *contact,
            },
            LawSpec::Table { file } => LawSpec::Table { file: abs(file) },
            LawSpec::GreyBox {
                inner,
                outside,
                blend_fraction,
                shear_cap_k_mpa,
                clamp,
            } => LawSpec::GreyBox {
                inner: boxed(inner),
                outside: boxed(outside),
                blend_fraction: *blend_fraction,
                shear_cap_k_mpa: *shear_cap_k_mpa,
                clamp: *clamp,
            },
            LawSpec::Scaled { factor, inner } => LawSpec::Scaled {
                factor: *factor,
                inner: boxed(inner),
            },
            other => other.clone(),
        }
    }
}

fn resolve(base: &Path, p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

/// A learned law from a loaded model file (`path` names it in errors).
fn learned(
    model: ModelFile,
    contact: Option<&PinContact>,
    path: &Path,
) -> Result<Box<dyn FrictionLaw>> {
    Ok(Box::new(LearnedLaw::new(model, contact).map_err(|e| {
        Error::input(SourcePos::path(path), e.to_string())
    })?))
}

/// Load a law from a law file, a model file or a table file.
pub fn load_law(path: &Path) -> Result<Box<dyn FrictionLaw>> {
    LawFile::read(path)?.build()
}

/// Every file loading the law at `path` reads: the file itself and the model files and
/// tables it names. All are inputs of a command that takes the law: an output must not
/// replace any of them.
pub fn law_inputs(path: &Path) -> Result<Vec<PathBuf>> {
    Ok(LawFile::read(path)?.inputs())
}

/// A law file read once: a command that first checks its outputs against the law's inputs
/// ([`LawFile::inputs`]) and then builds the law ([`LawFile::build`]) reads the file one time,
/// which matters for a model file of hundreds of MB given as the law (before, such a file
/// was read three times: for its inputs, for its schema and by the model loader).
#[derive(Debug)]
pub struct LawFile {
    path: PathBuf,
    /// The directory relative paths are resolved against.
    base: PathBuf,
    content: LawContent,
}

#[derive(Debug)]
enum LawContent {
    /// A model file from `greybox fit`, its text kept for the model loader.
    Model(String),
    /// A table file, its text kept for the table reader.
    Table(String),
    /// A law file proper.
    Spec(LawSpec),
}

impl LawFile {
    /// Reads the file at `path` and tells a model file, a table file and a law file apart by
    /// their schema (a model or table file is not parsed here: it can be hundreds of MB).
    pub fn read(path: &Path) -> Result<Self> {
        let text = greybox_core::input::read_regular_text(path, "law file")?;
        let at_line = |e: &serde_json::Error| SourcePos::path(path).line(e.line() as u64);
        let head = greybox_core::json_head::read(&text)
            .map_err(|e| Error::input(at_line(&e), format!("not JSON: {e}")))?;
        let content = match head.schema() {
            Some(s) if s == MODEL_SCHEMA => LawContent::Model(text),
            Some(s) if s == TABLE_SCHEMA => LawContent::Table(text),
            _ => LawContent::Spec(
                serde_json::from_str(&text)
                    .map_err(|e| Error::input(at_line(&e), format!("invalid law file: {e}")))?,
            ),
        };
        Ok(LawFile {
            path: path.to_path_buf(),
            base: path.parent().map(Path::to_path_buf).unwrap_or_default(),
            content,
        })
    }

    /// The law file itself, then the model files and tables it names (see [`law_inputs`]).
    pub fn inputs(&self) -> Vec<PathBuf> {
        let mut files = vec![self.path.clone()];
        if let LawContent::Spec(spec) = &self.content {
            files.extend(
                spec.files(&self.base)
                    .into_iter()
                    .filter(|f| f != &self.path),
            );
        }
        files
    }

    /// The law as a spec that names its files by absolute path: a model file as a learned
    /// law, a table file as a table law, a law file's spec with its paths resolved.
    pub fn spec(&self) -> LawSpec {
        let path = std::path::absolute(&self.path).unwrap_or_else(|_| self.path.clone());
        match &self.content {
            LawContent::Model(_) => LawSpec::Learned {
                model: path,
                contact: None,
            },
            LawContent::Table(_) => LawSpec::Table { file: path },
            LawContent::Spec(spec) => spec.resolved(&self.base),
        }
    }

    /// Builds the law: a model or table file from the text already read, a law file through
    /// [`LawSpec::build`] (which reads the files it names).
    pub fn build(self) -> Result<Box<dyn FrictionLaw>> {
        match self.content {
            LawContent::Model(text) => learned(
                ModelFile::parse(&text, &self.path.display().to_string())?,
                None,
                &self.path,
            ),
            LawContent::Table(text) => Ok(parse_table(&text, &self.path)?.into_law()),
            LawContent::Spec(spec) => spec.build(&self.base),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_resolved_law_names_its_files_by_absolute_path_at_every_depth() {
        let law: LawSpec = serde_json::from_str(
            r#"{"law": "scaled", "factor": 0.8, "inner": {"law": "grey-box",
                "inner": {"law": "learned", "model": "models/svr.json"},
                "outside": {"law": "table", "file": "/abs/t.json"}}}"#,
        )
        .unwrap();
        let r = law.resolved(Path::new("/campaign"));
        assert_eq!(
            r.files(Path::new("/elsewhere")),
            [
                PathBuf::from("/campaign/models/svr.json"),
                PathBuf::from("/abs/t.json")
            ]
        );
        // numbers and the law's shape are kept
        let LawSpec::Scaled { factor, .. } = r else {
            panic!("{r:?}")
        };
        assert_eq!(factor, 0.8);
    }
}
