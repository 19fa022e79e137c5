//! A model file from `greybox fit` as a friction law.
//!
//! Each model feature is mapped from the SI contact state by its unit: pressures (Pa, MPa,
//! GPa), sliding velocities (m/s, m/min), temperatures (K, °C), and normal forces (N, kN) —
//! the last through the inverse Hertz relation of the tribometer's pin contact
//! (p ∝ F^(1/3), so F = (p / p(1 N))³ under the contact's pressure convention).

use greybox_contact::PinContact;
use greybox_core::boundary::last_true;
use greybox_core::law::{Range, ValidityDomain};
use greybox_core::physics::Quantity;
use greybox_core::{units, Breaks, ContactState, Error, FrictionLaw, Result};
use greybox_model::column::FeatureQuantity;
use greybox_model::family::{FittedModel, Hyperparameters};
use greybox_model::modelfile::ModelFile;
use greybox_model::tree::{DecisionGrid, LEAF};
use greybox_model::Predictor;

/// Most features a learned law maps (stack buffer, no allocation per call).
pub const MAX_FEATURES: usize = 8;

/// How one model feature is computed from the contact state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input {
    /// Pressure in the model's unit: value = p / pa_per_unit.
    Pressure { pa_per_unit: f64 },
    /// Sliding velocity: value = v / m_s_per_unit.
    Velocity { m_s_per_unit: f64 },
    /// Temperature: value = T − offset_k.
    Temperature { offset_k: f64 },
    /// Normal force of the tribometer contact producing pressure p: F = (p / c)³ / n_per_unit.
    NormalForce {
        c_pa_per_cbrt_n: f64,
        n_per_unit: f64,
    },
}

impl Input {
    /// The input of a feature measuring `q`; `c_pa_per_cbrt_n` is c in p = c·F^(1/3) for
    /// normal forces (Pa at 1 N).
    pub fn of_quantity(q: FeatureQuantity, c_pa_per_cbrt_n: f64) -> Self {
        match q {
            FeatureQuantity::Pressure { pa_per_unit } => Input::Pressure { pa_per_unit },
            FeatureQuantity::Velocity { m_s_per_unit } => Input::Velocity { m_s_per_unit },
            FeatureQuantity::Temperature { offset_k } => Input::Temperature { offset_k },
            FeatureQuantity::NormalForce { n_per_unit } => Input::NormalForce {
                c_pa_per_cbrt_n,
                n_per_unit,
            },
        }
    }
    #[inline]
    pub fn value(&self, s: &ContactState) -> f64 {
        match *self {
            Input::Pressure { pa_per_unit } => s.pressure_pa / pa_per_unit,
            Input::Velocity { m_s_per_unit } => s.sliding_velocity_m_s.abs() / m_s_per_unit,
            Input::Temperature { offset_k } => s.temperature_k - offset_k,
            Input::NormalForce {
                c_pa_per_cbrt_n,
                n_per_unit,
            } => (s.pressure_pa.max(0.0) / c_pa_per_cbrt_n).powi(3) / n_per_unit,
        }
    }
    /// The SI contact variable value that gives model feature value `x`.
    fn inverse(&self, x: f64) -> f64 {
        match *self {
            Input::Pressure { pa_per_unit } => x * pa_per_unit,
            Input::Velocity { m_s_per_unit } => x * m_s_per_unit,
            Input::Temperature { offset_k } => x + offset_k,
            Input::NormalForce {
                c_pa_per_cbrt_n,
                n_per_unit,
            } => c_pa_per_cbrt_n * (x.max(0.0) * n_per_unit).cbrt(),
        }
    }
    /// The split `value <= t` restated on this input's SI contact variable: the largest `b`
    /// with `x <= b ⟺ value(x) <= t` (pressure in Pa, sliding speed |v| in m/s ≥ 0,
    /// temperature in K), exact bit for bit because every conversion is a monotone chain of
    /// roundings ([`last_true`]). `None` when the split sends every value the same way.
    pub fn boundary(&self, t: f64) -> Option<f64> {
        let at = |x: f64| ContactState {
            pressure_pa: x,
            sliding_velocity_m_s: x,
            temperature_k: x,
        };
        let b = match self {
            // the law sees |v|: the predicate is monotone only on v ≥ 0
            Input::Velocity { .. } => last_true(|x| x < 0.0 || self.value(&at(x)) <= t)?,
            _ => last_true(|x| self.value(&at(x)) <= t)?,
        };
        let speed = matches!(self, Input::Velocity { .. });
        (b.is_finite() && !(speed && b < 0.0)).then_some(b)
    }
    fn variable(&self) -> usize {
        match self {
            Input::Pressure { .. } | Input::NormalForce { .. } => 0,
            Input::Velocity { .. } => 1,
            Input::Temperature { .. } => 2,
        }
    }
}

/// c in p = c·F^(1/3) (Pa at 1 N) for a model's normal-force features, or NaN when it has
/// none; see [`LearnedLaw::new`].
fn force_pressure_constant(model: &ModelFile, contact: Option<&PinContact>) -> Result<f64> {
    let uses_force = model.features.iter().any(|f| {
        matches!(
            FeatureQuantity::of_unit(&f.unit),
            Some(FeatureQuantity::NormalForce { .. })
        )
    });
    let recorded = model.force_to_pressure;
    let given = contact.map(|c| c.pressure_pa(1.0)).transpose()?;
    match (given, recorded) {
        (Some(g), Some(r)) if (g / r.pressure_pa_at_1_n - 1.0).abs() > 1e-9 && uses_force => Err(Error::invalid(
            "learned law",
            format!(
                "the law's contact gives {:.6e} Pa at 1 N, but the model was trained on a dataset with {:.6e} Pa at 1 N ({} convention): state the dataset's contact, or drop it to use the model's",
                g,
                r.pressure_pa_at_1_n,
                r.pressure_convention.name()
            ),
        )),
        (Some(g), _) => Ok(g),
        (None, Some(r)) => Ok(r.pressure_pa_at_1_n),
        (None, None) if uses_force => Err(Error::invalid(
            "learned law",
            no_contact_message(model),
        )),
        (None, None) => Ok(f64::NAN),
    }
}

/// Why a model trained on a normal force cannot map pressure to that force, and how to fix
/// it: a file from before schema version 2, an imported model whose contact was not stated,
/// or a model fitted on data without one force-to-pressure map.
fn no_contact_message(model: &ModelFile) -> String {
    let law_file = "or use it through a law file that states the contact, e.g. {\"law\": \"learned\", \"model\": \"…\", \"contact\": {\"convention\": \"article-eq7\", …}}";
    let what = format!(
        "the {} model is trained on a normal force",
        model.family.name()
    );
    if model.schema_version < 2 {
        return format!("{what} but its file does not record the dataset's pressure convention and contact (a file from before schema version 2): re-fit it, {law_file}");
    }
    if matches!(model.hyperparameters, Hyperparameters::Imported(_)) {
        return format!("{what} but was imported without a contact, so nothing maps contact pressure to that force: re-import it stating the tribometer's pin contact: import's `contact` STUDY.toml for a study's [contact] table, or `convention`, `pin_tip_radius_mm`, … (in Python contact={{\"convention\": \"article-eq7\", …}} or contact=\"study.toml\"), {law_file}");
    }
    format!("{what} but its file does not record a contact's force-to-pressure map (the data it was fitted on did not share one pressure convention and contact): {law_file}")
}

/// Largest decision grid a tree-ensemble law compiles to (8 MB of cells).
pub const MAX_GRID_CELLS: usize = 1 << 20;

/// A learned friction law.
#[derive(Debug, Clone)]
pub struct LearnedLaw {
    pub model: ModelFile,
    pub inputs: Vec<Input>,
    domain: ValidityDomain,
    /// A tree ensemble compiled to its exact lookup table ([`DecisionGrid`]), when it has at
    /// most [`MAX_GRID_CELLS`] cells: the same μ bit for bit, one binary search per feature.
    grid: Option<DecisionGrid>,
}

impl LearnedLaw {
    /// Map the model's features onto the contact state. A model trained on a normal force
    /// (`normal_force_N`) needs the map from pressure back to that force: the one its file
    /// records from the training dataset, or `contact` when given (then both must agree). A
    /// model without either is an error, never a default convention.
    pub fn new(model: ModelFile, contact: Option<&PinContact>) -> Result<Self> {
        if model.features.len() > MAX_FEATURES {
            return Err(Error::invalid(
                "learned law",
                format!("at most {MAX_FEATURES} features"),
            ));
        }
        greybox_model::column::check_law_features(&model.features)
            .map_err(|m| Error::invalid("learned law", m))?;
        let c = force_pressure_constant(&model, contact)?;
        let inputs: Vec<Input> = model
            .features
            .iter()
            .map(|f| {
                FeatureQuantity::of_column(f)
                    .map(|q| Input::of_quantity(q, c))
                    .map_err(|m| Error::invalid("learned law", m))
            })
            .collect::<Result<_>>()?;
        let mut ranges: [Option<Range>; 3] = [None, None, None];
        for (inp, r) in inputs.iter().zip(&model.training_domain) {
            let (a, b) = (inp.inverse(r.min), inp.inverse(r.max));
            ranges[inp.variable()] = Some(Range {
                min: a.min(b),
                max: a.max(b),
            });
        }
        let domain = ValidityDomain {
            pressure_pa: ranges[0].ok_or_else(|| {
                Error::invalid(
                    "learned law",
                    "the model has no pressure or normal-force feature",
                )
            })?,
            sliding_velocity_m_s: ranges[1].ok_or_else(|| {
                Error::invalid("learned law", "the model has no sliding-velocity feature")
            })?,
            temperature_k: ranges[2],
        };
        let grid = match &model.model {
            FittedModel::TreeEnsemble(e) => DecisionGrid::build(e, MAX_GRID_CELLS),
            _ => None,
        };
        let law = LearnedLaw {
            model,
            inputs,
            domain,
            grid,
        };
        law.check_corners()?;
        Ok(law)
    }

    /// μ at the corners and the centre of the training domain must lie in the possible
    /// range of [`Quantity::Mu`]: a model trained on a target in % or a force ratio in the
    /// wrong unit is refused with the number, where it was predicted and the likely mistake.
    fn check_corners(&self) -> Result<()> {
        let d = self.domain;
        let t = d
            .temperature_k
            .map_or([ContactState::ROOM_TEMPERATURE_K; 2], |r| [r.min, r.max]);
        let mid = |r: Range| 0.5 * (r.min + r.max);
        let mut states = vec![ContactState {
            pressure_pa: mid(d.pressure_pa),
            sliding_velocity_m_s: mid(d.sliding_velocity_m_s),
            temperature_k: 0.5 * (t[0] + t[1]),
        }];
        for p in [d.pressure_pa.min, d.pressure_pa.max] {
            for v in [d.sliding_velocity_m_s.min, d.sliding_velocity_m_s.max] {
                for &tk in &t {
                    states.push(ContactState {
                        pressure_pa: p,
                        sliding_velocity_m_s: v,
                        temperature_k: tk,
                    });
                }
            }
        }
        for s in &states {
            let at = format!(
                "the model's prediction at p = {} MPa, v = {} m/min, T = {} K",
                greybox_core::rules::Compact(s.pressure_pa / units::PA_PER_MPA),
                greybox_core::rules::Compact(units::m_per_s_to_m_per_min(s.sliding_velocity_m_s)),
                greybox_core::rules::Compact(s.temperature_k)
            );
            greybox_core::physics::check(Quantity::Mu, self.mu(s), &at)
                .map_err(|e| Error::invalid("learned law", e))?;
        }
        Ok(())
    }
}

impl LearnedLaw {
    /// The model's features at a contact state: entry i is feature i of the model file (the
    /// first `model.features.len()` entries are used).
    #[inline]
    pub fn features(&self, s: &ContactState) -> [f64; MAX_FEATURES] {
        let mut x = [0.0; MAX_FEATURES];
        for (xi, inp) in x.iter_mut().zip(&self.inputs) {
            *xi = inp.value(s);
        }
        x
    }
}

impl FrictionLaw for LearnedLaw {
    fn name(&self) -> String {
        format!(
            "learned {} ({} → {})",
            self.model.family.name(),
            self.model
                .features
                .iter()
                .map(|f| f.name.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            self.model.target.name
        )
    }
    #[inline]
    fn mu(&self, s: &ContactState) -> f64 {
        let x = self.features(s);
        let x = &x[..self.inputs.len()];
        match &self.grid {
            Some(g) => g.predict_one(x),
            None => self.model.model.predict_one(x),
        }
    }
    fn domain(&self) -> Option<ValidityDomain> {
        Some(self.domain)
    }
    /// A tree ensemble is constant between its split thresholds: they are restated exactly
    /// in SI per contact variable ([`Input::boundary`]), union over trees and over the
    /// features that map to the same variable.
    fn breaks(&self) -> Option<Breaks> {
        let FittedModel::TreeEnsemble(e) = &self.model.model else {
            return None;
        };
        let collected;
        let thresholds: &[Vec<f64>] = match &self.grid {
            Some(g) => g.thresholds(),
            None => {
                let mut t = vec![Vec::new(); e.n_features];
                for n in e.nodes.iter().filter(|n| n.feature != LEAF) {
                    if let Some(v) = t.get_mut(n.feature as usize) {
                        v.push(n.value);
                    }
                }
                collected = t;
                &collected
            }
        };
        let mut breaks = Breaks {
            constant_between: true,
            ..Breaks::default()
        };
        for (inp, ts) in self.inputs.iter().zip(thresholds) {
            let lines = breaks.axis_mut(inp.variable());
            lines.extend(ts.iter().filter_map(|&t| inp.boundary(t)));
        }
        Some(breaks.normalize())
    }
}
