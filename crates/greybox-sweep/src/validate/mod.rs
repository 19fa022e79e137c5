//! The validation suite: simulated orthogonal cuts against measured ones from published
//! experiments, with an honest split — the friction models are calibrated on at most a third
//! of the conditions, and the errors are reported on the rest, held out.
//!
//! A suite file (TOML) names the data (a CSV of measured conditions, one row each, units in
//! the column names, every row citing its source, [`conditions`]) and, per material, a
//! cutting set-up template whose condition fields (speed, uncut chip thickness, rake,
//! clearance, edge radius) each row replaces. Two tool models run: the adiabatic tool (all
//! friction heat into the chip, as in the ETH IWF codes) and the template's thermal tool.
//!
//! Each material lists the friction models it is cut with ([`variant`]: a calibrated
//! Coulomb μ\*, a law file as it is or with a calibrated factor, a law with fitted
//! parameters); every model runs on the same conditions, and the results name it. The
//! calibration ([`fit`]) uses the calibration conditions only; then every condition is cut
//! with the calibrated model, the calibration ones included, so that their errors are
//! simulated, not interpolated. Each cut also records the local contact quantities along the
//! rake face ([`cut`]).
//!
//! Slow cuts run time-scaled (`run_speed_m_per_min`; see
//! [`greybox_sim::cutting::CuttingSetup::physical_cutting_speed_m_s`]).

pub mod batch;
pub mod compare;
pub mod conditions;
pub mod cut;
pub mod fit;
pub mod goals;
pub mod report;
#[cfg(test)]
mod test_support;
pub mod trend;
pub mod variant;

pub use conditions::{condition_setup, read_conditions, Condition};
pub use report::{markdown, write_outputs};

use anyhow::{bail, Context, Result};
use batch::{Batches, CutJob, CutRunner};
use cut::Cut;
use fit::{best_shape, feed_error, fit_shapes, ErrorsAt, FactorErrors, ShapeFit};
use greybox_sim::chip::RakeContact;
use greybox_sim::cutting::CuttingSetup;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use variant::{FrictionVariant, Model, ModelLaw, VariantKind};

/// The suite file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    /// Measured conditions (CSV, relative to the suite file).
    pub data: String,
    pub material: Vec<MaterialRuns>,
    /// Resources of each Slurm array task when the cuts run on Slurm (as a sweep file's
    /// `[slurm]`; unset ones from each batch's cost estimate).
    #[serde(default)]
    pub slurm: crate::spec::SlurmSection,
    /// The held-out mean |error| each measure should stay within ([`goals`]; default F'c
    /// 15 %, F'f 30 %).
    #[serde(default)]
    pub goals: goals::Goals,
}

impl Suite {
    /// Reads a suite file.
    pub fn read(path: &Path) -> Result<Suite> {
        greybox_pipeline::config_toml::read(path, "validation suite")
    }

    /// The files the suite at `path` reads: its data, its set-up templates and its law
    /// files with the files they name (relative paths resolved against the suite's
    /// directory).
    pub fn input_files(&self, path: &Path) -> Vec<PathBuf> {
        let base = path.parent().unwrap_or(Path::new("."));
        let mut files: Vec<PathBuf> = std::iter::once(base.join(&self.data))
            .chain(self.material.iter().map(|m| base.join(&m.setup)))
            .collect();
        for v in self.material.iter().flat_map(|m| &m.friction) {
            if let Some(f) = v.file_path(base) {
                // an unreadable law file is named when the variant is built
                files.extend(
                    greybox_friction::spec::law_inputs(&f).unwrap_or_else(|_| vec![f.clone()]),
                );
            }
        }
        files
    }
}

/// How one material's conditions are simulated and calibrated.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialRuns {
    /// The `material` of the data rows this applies to.
    pub name: String,
    /// How the results name this entry (default: `name`); several entries may model the
    /// same material differently (e.g. two flow-stress models).
    #[serde(default)]
    pub label: Option<String>,
    /// Cutting set-up template (TOML, relative to the suite file).
    pub setup: String,
    /// Cuts slower than this run time-scaled at this speed, m/min.
    pub run_speed_m_per_min: f64,
    /// Ids of the calibration conditions (at most a third of the material's rows).
    pub calibration: Vec<String>,
    /// μ range searched, [low, high] (the Coulomb μ\*, and the two cuts per calibration
    /// condition every fitted law starts from).
    pub mu_bracket: [f64; 2],
    /// Steps refining each factor's s\* by cutting the calibration conditions again there
    /// (default 0: the linear interpolation between the bracket ends alone; [`fit`]).
    #[serde(default)]
    pub refine: usize,
    /// The friction models cut, side by side (default: `coulomb-calibrated` alone).
    #[serde(default = "default_friction")]
    pub friction: Vec<FrictionVariant>,
    /// The template's cut length replaced, m (with `stop_when_sure` in the template: the
    /// length limit); the run's `fraction` applies to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cut_length_m: Option<f64>,
    /// The template's level-0 particle spacing replaced, m (with `refinement`: coarse away
    /// from the tool).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing_m: Option<f64>,
    /// The template's `[refinement]` replaced: dynamic refinement around the cutting edge
    /// (the regions of a cutting set-up, `greybox_sim::cutting::CutRefinement`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement: Option<greybox_sim::cutting::CutRefinement>,
    /// Local time stepping on (`numerics.local_time_stepping` of every cut; it acts only with
    /// a refinement). Unset (off), it is not written out.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub local_time_stepping: bool,
    /// Fields of the template set before it is read, by dotted path as a sweep's axes
    /// (`set = { "material.plasticity.n" = 0.34 }`; the string `"none"` removes a field):
    /// one template, several variants of it, without a copy of the file per variant.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub set: BTreeMap<String, toml::Value>,
}

impl MaterialRuns {
    /// The entry's set-up template: its file with the entry's `set` fields applied.
    pub fn template(&self, base: &Path) -> Result<CuttingSetup> {
        let path = base.join(&self.setup);
        if self.set.is_empty() {
            return Ok(greybox_pipeline::simulate::read_cutting_setup(&path)?.setup);
        }
        let text = greybox_pipeline::config_toml::read_text(&path, "cutting set-up")?;
        let mut v: toml::Value = greybox_pipeline::config_toml::parse(
            &text,
            &path.display().to_string(),
            "cutting set-up",
        )?;
        for (field, value) in &self.set {
            super::case::apply(&mut v, field, value)
                .with_context(|| format!("material {}: set", self.label()))?;
        }
        let source = format!("{} with material {}'s set", path.display(), self.label());
        Ok(greybox_pipeline::simulate::cutting_setup_of_text(
            &toml::to_string(&v)?,
            &path,
            &source,
        )?
        .setup)
    }
}

/// The most refinement steps a material may ask for (each cuts every calibration condition
/// once per friction model and shape).
pub const MAX_REFINE: usize = 4;

fn default_friction() -> Vec<FrictionVariant> {
    vec![FrictionVariant::coulomb_calibrated()]
}

/// The tool models compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ToolModel {
    /// Rigid and adiabatic: all friction heat into the chip, no conduction into the tool.
    Adiabatic,
    /// The template's thermal tool (conduction, coating, interface conductance).
    Thermal,
}

greybox_core::choice!(ToolModel, "validate.tools", [Adiabatic => "adiabatic", Thermal => "thermal"], text);

impl MaterialRuns {
    /// The entry's name in the results.
    pub fn label(&self) -> &str {
        self.label.as_deref().unwrap_or(&self.name)
    }
}

impl ToolModel {
    pub fn name(self) -> &'static str {
        match self {
            ToolModel::Adiabatic => "adiabatic",
            ToolModel::Thermal => "thermal",
        }
    }
}

/// What a condition is for in the suite: the friction models are calibrated on the
/// calibration conditions, the held-out ones only test them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Calibration,
    HeldOut,
}

greybox_core::choice!(Role, "role", [Calibration => "calibration", HeldOut => "held-out"]);

/// One simulated condition.
#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    pub id: String,
    pub material: String,
    pub tool: ToolModel,
    /// The friction model's name.
    pub friction: String,
    pub role: Role,
    /// The constant μ of a Coulomb model (`None`: a law of the contact state).
    pub mu: Option<f64>,
    pub cutting_speed_m_per_min: f64,
    pub uncut_chip_thickness_mm: f64,
    pub measured_cutting_force_n_per_mm: f64,
    pub simulated_cutting_force_n_per_mm: f64,
    pub measured_feed_force_n_per_mm: f64,
    pub simulated_feed_force_n_per_mm: f64,
    pub measured_chip_ratio: Option<f64>,
    pub simulated_chip_ratio: Option<f64>,
    /// The chip's extent along the rake-face normal over h, the steady mean: the chip ratio
    /// as measured until 2026-12-01 ([`greybox_sim::chip::chip_extent`]).
    pub simulated_extent_ratio: Option<f64>,
    pub measured_contact_length_mm: Option<f64>,
    pub simulated_contact_length_mm: Option<f64>,
    /// Relative errors (simulated − measured)/measured.
    pub cutting_force_error: f64,
    pub feed_force_error: f64,
    pub chip_ratio_error: Option<f64>,
    /// Half-widths of the 95 % intervals of the simulated F'c, F'f (N/mm) and chip ratio.
    pub simulated_ci95: [Option<f64>; 3],
    /// Standard errors of the three errors from the cut's own scatter (its steady state's
    /// batch means over the measured value; `None`: the cut could not say).
    pub error_se: [Option<f64>; 3],
    /// Standard errors of the three errors from the measured values' own scatter,
    /// (1 + e) σ_m/m with σ_m the measured mean's standard error (`None`: the data do not
    /// say; [`Condition::measured_standard_errors`]).
    pub measured_error_se: [Option<f64>; 3],
    /// The steady stretch the cut averaged, mm (`None`: none was found), and where it began.
    pub steady_length_mm: Option<f64>,
    pub steady_from_mm: Option<f64>,
    /// The cut's force intervals met the template's targets.
    pub sure: bool,
    /// Its steady stretch spans fewer contact renewals than the template asks.
    pub short_stretch: bool,
    /// μ, pressure and sliding velocity along the rake face.
    pub local: RakeContact,
    /// The hottest particle over the run, °C.
    pub max_temperature_c: f64,
    pub steady: bool,
    /// Cut length simulated, mm (shorter than the template's when the run stopped steady).
    pub simulated_cut_length_mm: f64,
    pub wall_s: f64,
}

impl Outcome {
    /// The relative error of measure `k` in the order of `error_se` (0 F'c, 1 F'f, 2 chip
    /// ratio; `None`: no chip ratio measured or simulated).
    pub fn error(&self, k: usize) -> Option<f64> {
        match k {
            0 => Some(self.cutting_force_error),
            1 => Some(self.feed_force_error),
            _ => self.chip_ratio_error,
        }
    }
}

/// Mean errors of one material, tool model and friction model over one role.
#[derive(Debug, Clone, Serialize)]
pub struct ErrorSummary {
    pub material: String,
    pub tool: ToolModel,
    pub friction: String,
    pub kind: VariantKind,
    pub role: Role,
    pub conditions: usize,
    /// The calibrated constant μ\* (Coulomb models).
    pub mu: Option<f64>,
    /// The fitted parameters (field, value; the factor on μ as `factor`).
    pub parameters: Vec<(String, f64)>,
    /// Mean |error| and mean signed error, as fractions.
    pub cutting_force_mean_abs: f64,
    pub cutting_force_mean: f64,
    pub feed_force_mean_abs: f64,
    pub feed_force_mean: f64,
    pub chip_ratio_mean_abs: Option<f64>,
    pub chip_ratio_mean: Option<f64>,
    /// Half-widths of the 95 % intervals of the three mean |error|s from the cuts' own
    /// scatter (`None`: a cut could not say); μ\*'s uncertainty is in `factor_ci95`.
    pub cutting_force_mean_abs_ci95: Option<f64>,
    pub feed_force_mean_abs_ci95: Option<f64>,
    pub chip_ratio_mean_abs_ci95: Option<f64>,
    /// The calibrated factor's 95 % interval (μ\* for Coulomb) from the calibration cuts'
    /// scatter ([`fit`]).
    pub factor_ci95: Option<[f64; 2]>,
    /// Cuts (F'c, F'f, chip ratio) that could not say how sure they are: their standard error
    /// is the median of the others' in the intervals above ([`imputed_errors`]).
    pub imputed_errors: [usize; 3],
    /// The mean over the conditions of the contact-length-averaged μ the law applied.
    pub mean_mu_applied: Option<f64>,
    /// The suite's goals checked on the held-out conditions, each with the interval of both
    /// the cuts' and the measurements' scatter (empty for the calibration conditions), and
    /// all of them together (`None`: none checked).
    pub goals: Vec<goals::GoalCheck>,
    pub goal: Option<goals::Verdict>,
    /// How each measure's signed error moves with the cutting speed over these conditions,
    /// with its interval ([`trend`]; a measure left out where fewer than three conditions
    /// or a single speed have it).
    pub speed_trends: Vec<trend::SpeedTrend>,
    /// What the friction model cost in all (calibration and every condition): cuts run and
    /// their summed wall time, s.
    pub cuts: usize,
    pub cut_seconds: f64,
}

/// The calibration record of one friction model with a factor: every shape tried, its
/// factor s\* and its interpolated objective J ([`fit`]).
#[derive(Debug, Clone, Serialize)]
pub struct FitRecord {
    pub material: String,
    pub tool: ToolModel,
    pub friction: String,
    pub fields: Vec<String>,
    pub shapes: Vec<ShapeFit>,
}

/// What a suite run gave.
#[derive(Debug, Clone, Serialize)]
pub struct Validation {
    pub outcomes: Vec<Outcome>,
    pub summaries: Vec<ErrorSummary>,
    /// Every friction model against the material's first one, paired on the held-out
    /// conditions ([`compare`]).
    pub comparisons: Vec<compare::Comparison>,
    pub fits: Vec<FitRecord>,
    /// Cut length run per condition (fraction of the template's).
    pub fraction: f64,
    /// The goals the held-out summaries were checked against.
    pub goals: goals::Goals,
}

/// Options of a suite run.
#[derive(Debug, Clone)]
pub struct ValidateOptions {
    /// Only these condition ids (calibration ones among them are still used to calibrate);
    /// empty: all.
    pub only: Vec<String>,
    pub tools: Vec<ToolModel>,
    /// Fraction of each template's cut length.
    pub fraction: f64,
    /// Where the cuts run ([`batch`]).
    pub runner: CutRunner,
}

struct Plan<'a> {
    runs: &'a MaterialRuns,
    template: CuttingSetup,
    calibration: Vec<&'a Condition>,
    held_out: Vec<&'a Condition>,
    models: Vec<Model>,
}

/// Runs the suite (its cuts in this process or, with an executor, as cases under `cuts`).
pub fn validate(suite_path: &Path, o: &ValidateOptions, cuts: Option<&Path>) -> Result<Validation> {
    run_suite(&Suite::read(suite_path)?, suite_path, o, cuts)
}

/// The held-out outcomes grouped by material entry and tool model (in the order first met),
/// each group with its friction models in order: the rows friction models are compared on.
pub(crate) fn held_out_groups(
    outcomes: &[Outcome],
) -> Vec<(&str, ToolModel, Vec<&Outcome>, Vec<&str>)> {
    let held: Vec<&Outcome> = outcomes
        .iter()
        .filter(|o| o.role == Role::HeldOut)
        .collect();
    distinct(held.iter().map(|o| (o.material.as_str(), o.tool)))
        .into_iter()
        .map(|(material, tool)| {
            let rows: Vec<&Outcome> = held
                .iter()
                .copied()
                .filter(|o| o.material == material && o.tool == tool)
                .collect();
            let models = distinct(rows.iter().map(|o| o.friction.as_str()));
            (material, tool, rows, models)
        })
        .collect()
}

/// The standard errors of a group of cuts, a cut that could not say how sure it is given the
/// median of the others' (the one rule wherever the suite combines cuts' scatter): the
/// errors and how many were imputed; `None` when no cut of the group could say.
pub(crate) fn imputed_errors(se: &[Option<f64>]) -> Option<(Vec<f64>, usize)> {
    let mut known: Vec<f64> = se.iter().flatten().copied().collect();
    if known.is_empty() {
        return None;
    }
    known.sort_by(f64::total_cmp);
    let n = known.len();
    let median = if n % 2 == 1 {
        known[n / 2]
    } else {
        0.5 * (known[n / 2 - 1] + known[n / 2])
    };
    let missing = se.iter().filter(|e| e.is_none()).count();
    Some((se.iter().map(|e| e.unwrap_or(median)).collect(), missing))
}

/// Half-width of the 95 % interval of a mean over `n` terms whose standard errors are `se`
/// (independent): 1.96 √(Σ se²)/n. The one rule wherever the suite combines scatter.
pub(crate) fn mean_ci95<'a>(se: impl IntoIterator<Item = &'a f64>, n: usize) -> f64 {
    1.96 * se.into_iter().map(|e| e * e).sum::<f64>().sqrt() / n as f64
}

/// The items, each once, in the order first met.
fn distinct<T: PartialEq>(items: impl IntoIterator<Item = T>) -> Vec<T> {
    let mut once: Vec<T> = Vec::new();
    for t in items {
        if !once.contains(&t) {
            once.push(t);
        }
    }
    once
}

/// One (material plan, tool model, friction model): a column of the comparison.
struct Arm<'a> {
    plan: &'a Plan<'a>,
    tool: ToolModel,
    model: &'a Model,
}

/// An arm's calibration: the kept shape and factor, every shape's fit, and the cost.
#[derive(Default)]
struct Calibrated {
    shape: Vec<f64>,
    factor: f64,
    /// The factor's 95 % interval from the calibration cuts' scatter ([`fit`]).
    factor_ci95: Option<[f64; 2]>,
    shapes: Vec<ShapeFit>,
    cuts: usize,
    cut_seconds: f64,
}

impl Calibrated {
    fn count(&mut self, cuts: &[Cut]) {
        self.cuts += cuts.len();
        self.cut_seconds += cuts.iter().map(|c| c.wall_s).sum::<f64>();
    }
}

/// A cut of a condition with a friction model's law.
struct Job<'a> {
    arm: &'a Arm<'a>,
    condition: &'a Condition,
    law: ModelLaw,
}

/// Runs every job as one batch (in parallel: the cores wait for the slowest cut once).
fn run_batch(batches: &mut Batches, jobs: &[Job]) -> Result<Vec<Cut>> {
    let cuts = jobs
        .iter()
        .map(|j| {
            let plan = j.arm.plan;
            Ok(CutJob {
                setup: condition_setup(&plan.template, j.condition, plan.runs, j.arm.tool)?,
                law: j.law.clone(),
                shown: vec![
                    ("condition".into(), j.condition.id.clone()),
                    ("tool".into(), j.arm.tool.name().into()),
                    ("friction".into(), j.arm.model.label.clone()),
                ],
            })
        })
        .collect::<Result<Vec<_>>>()?;
    batches.run(&cuts)
}

/// Runs `suite`, read from `suite_path` (relative paths resolve against its directory):
/// every friction model calibrated per material and tool model, then every wanted condition
/// cut with it.
fn run_suite(
    suite: &Suite,
    suite_path: &Path,
    o: &ValidateOptions,
    cuts: Option<&Path>,
) -> Result<Validation> {
    check_options(o)?;
    let base = suite_path.parent().unwrap_or(Path::new("."));
    let conditions = read_conditions(&base.join(&suite.data))?;
    let plans = plan_suite(suite, suite_path, o, &conditions)?;
    let tools = distinct(o.tools.iter().copied());
    let groups: Vec<(&Plan, ToolModel)> = plans
        .iter()
        .flat_map(|p| tools.iter().map(move |&t| (p, t)))
        .collect();
    let arms: Vec<Arm> = groups
        .iter()
        .flat_map(|&(plan, tool)| {
            plan.models
                .iter()
                .map(move |model| Arm { plan, tool, model })
        })
        .collect();
    let mut batches = Batches {
        runner: &o.runner,
        dir: cuts.map(Path::to_path_buf),
        slurm: suite.slurm.clone(),
        source: suite_path.display().to_string(),
        count: 0,
    };
    let mut calibrated = calibrate(&mut batches, &arms)?;
    let (outcomes, summaries) = final_cuts(&mut batches, &arms, &mut calibrated, &suite.goals)?;
    let fits = arms
        .iter()
        .zip(&calibrated)
        .filter(|(a, _)| a.model.factor.is_some())
        .map(|(a, c)| FitRecord {
            material: a.plan.runs.label().to_string(),
            tool: a.tool,
            friction: a.model.label.clone(),
            fields: a.model.fields.clone(),
            shapes: c.shapes.clone(),
        })
        .collect();
    Ok(Validation {
        comparisons: compare::compare(&outcomes),
        outcomes,
        summaries,
        fits,
        fraction: o.fraction,
        goals: suite.goals.clone(),
    })
}

/// Everything a suite's run reads and checks before its first cut: its goals, the `--only`
/// ids and each material's plan (template with its `set`, friction models, conditions).
fn plan_suite<'a>(
    suite: &'a Suite,
    suite_path: &Path,
    o: &ValidateOptions,
    conditions: &'a [Condition],
) -> Result<Vec<Plan<'a>>> {
    suite.goals.check(&suite_path.display().to_string())?;
    check_only(o, conditions, &suite.data)?;
    suite
        .material
        .iter()
        .map(|runs| material_plan(runs, conditions, suite, suite_path, o))
        .collect()
}

/// Per arm, shape and factor of `at(arm, shape)`, the calibration conditions' F'f errors:
/// every arm's cuts as one parallel batch, each counted in its `calibrated`.
type FactorPoints = Vec<Vec<Vec<(f64, ErrorsAt)>>>;

fn cut_at_factors(
    batches: &mut Batches,
    arms: &[Arm],
    calibrated: &mut [Calibrated],
    at: &dyn Fn(usize, usize) -> Vec<f64>,
) -> Result<FactorPoints> {
    let shapes = |a: &Arm| {
        if a.model.factor.is_some() {
            a.model.shapes.len()
        } else {
            0
        }
    };
    let mut jobs: Vec<Job> = Vec::new();
    for (i, a) in arms.iter().enumerate() {
        for k in 0..shapes(a) {
            for s in at(i, k) {
                let law = a.model.law(&a.model.shapes[k], s)?;
                jobs.extend(a.plan.calibration.iter().map(|&condition| Job {
                    arm: a,
                    condition,
                    law: law.clone(),
                }));
            }
        }
    }
    let mut cuts = run_batch(batches, &jobs)?.into_iter();
    let mut out = Vec::new();
    for (i, a) in arms.iter().enumerate() {
        let mut of_arm = Vec::new();
        for k in 0..shapes(a) {
            let mut of_shape = Vec::new();
            for s in at(i, k) {
                let these: Vec<Cut> = cuts.by_ref().take(a.plan.calibration.len()).collect();
                let measured = a
                    .plan
                    .calibration
                    .iter()
                    .map(|c| c.feed_force_n_per_m * 1e-3);
                let errors = ErrorsAt {
                    errors: measured
                        .clone()
                        .zip(&these)
                        .map(|(m, cut)| feed_error(cut, m))
                        .collect(),
                    se: measured
                        .zip(&these)
                        .map(|(m, cut)| cut.standard_errors()[1].map(|e| e / m))
                        .collect(),
                };
                calibrated[i].count(&these);
                of_shape.push((s, errors));
            }
            of_arm.push(of_shape);
        }
        out.push(of_arm);
    }
    Ok(out)
}

/// Every arm with a factor calibrated ([`fit`]): each of its shapes cut on the calibration
/// conditions at both ends of the factor's bracket, then at each refinement's s\*, every
/// step of all arms as one parallel batch; the shape of least interpolated J kept with its
/// s\*. An arm without a factor keeps its law.
fn calibrate(batches: &mut Batches, arms: &[Arm]) -> Result<Vec<Calibrated>> {
    let mut calibrated: Vec<Calibrated> = arms
        .iter()
        .map(|_| Calibrated {
            factor: 1.0,
            ..Calibrated::default()
        })
        .collect();
    let ends = cut_at_factors(batches, arms, &mut calibrated, &|i, _| {
        arms[i].model.factor.map_or(Vec::new(), |b| b.to_vec())
    })?;
    let mut searches: Vec<Vec<FactorErrors>> = arms
        .iter()
        .zip(ends)
        .map(|(a, of_arm)| {
            of_arm
                .into_iter()
                .map(|mut two| {
                    let hi = two.pop().expect("two ends").1;
                    let lo = two.pop().expect("two ends").1;
                    FactorErrors::new(a.model.factor.expect("a factor"), lo, hi)
                })
                .collect()
        })
        .collect();
    let steps = arms.iter().map(|a| a.plan.runs.refine).max().unwrap_or(0);
    for step in 0..steps {
        let next: Vec<Vec<Vec<f64>>> = arms
            .iter()
            .zip(&searches)
            .map(|(a, of_arm)| {
                of_arm
                    .iter()
                    .map(|f| {
                        let s = f.zero();
                        if step < a.plan.runs.refine && !f.has(s) {
                            vec![s]
                        } else {
                            Vec::new()
                        }
                    })
                    .collect()
            })
            .collect();
        let done = cut_at_factors(batches, arms, &mut calibrated, &|i, k| next[i][k].clone())?;
        for (of_arm, done) in searches.iter_mut().zip(done) {
            for (f, points) in of_arm.iter_mut().zip(done) {
                for (s, errors) in points {
                    f.add(s, errors);
                }
            }
        }
    }
    for ((a, c), of_arm) in arms.iter().zip(calibrated.iter_mut()).zip(&searches) {
        if of_arm.is_empty() {
            continue;
        }
        c.shapes = fit_shapes(&a.model.shapes, of_arm);
        if let Some(best) = best_shape(&c.shapes) {
            c.shape = best.values.clone();
            c.factor = best.factor;
            c.factor_ci95 = best.factor_ci95;
        }
    }
    Ok(calibrated)
}

/// Every wanted condition of every arm cut with its calibrated model, as one batch; the
/// outcomes in arm order (calibration conditions, then held out) and their summaries.
fn final_cuts(
    batches: &mut Batches,
    arms: &[Arm],
    calibrated: &mut [Calibrated],
    goals: &goals::Goals,
) -> Result<(Vec<Outcome>, Vec<ErrorSummary>)> {
    let laws: Vec<ModelLaw> = arms
        .iter()
        .zip(calibrated.iter())
        .map(|(a, c)| a.model.law(&c.shape, c.factor))
        .collect::<Result<_>>()?;
    let jobs: Vec<Job> = arms
        .iter()
        .zip(&laws)
        .flat_map(|(a, law)| {
            a.plan
                .calibration
                .iter()
                .chain(&a.plan.held_out)
                .map(move |&condition| Job {
                    arm: a,
                    condition,
                    law: law.clone(),
                })
        })
        .collect();
    let mut cuts = run_batch(batches, &jobs)?.into_iter();
    let mut outcomes = Vec::new();
    let mut summaries = Vec::new();
    for (a, c) in arms.iter().zip(calibrated.iter_mut()) {
        let cal: Vec<Cut> = cuts.by_ref().take(a.plan.calibration.len()).collect();
        let held: Vec<Cut> = cuts.by_ref().take(a.plan.held_out.len()).collect();
        c.count(&cal);
        c.count(&held);
        let mu = (a.model.kind == VariantKind::CoulombCalibrated).then_some(c.factor);
        let rows: Vec<Outcome> = a
            .plan
            .calibration
            .iter()
            .zip(&cal)
            .map(|(cond, cut)| outcome(a, cond, Role::Calibration, mu, cut))
            .chain(
                a.plan
                    .held_out
                    .iter()
                    .zip(&held)
                    .map(|(cond, cut)| outcome(a, cond, Role::HeldOut, mu, cut)),
            )
            .collect();
        for role in [Role::Calibration, Role::HeldOut] {
            if let Some(s) = summarise(&rows, a, c, role, mu, goals) {
                summaries.push(s);
            }
        }
        outcomes.extend(rows);
    }
    Ok((outcomes, summaries))
}

fn outcome(arm: &Arm, c: &Condition, role: Role, mu: Option<f64>, cut: &Cut) -> Outcome {
    let rel = |sim: f64, meas: f64| sim / meas - 1.0;
    let (fc, ff) = (c.cutting_force_n_per_m * 1e-3, c.feed_force_n_per_m * 1e-3);
    Outcome {
        id: c.id.clone(),
        material: arm.plan.runs.label().to_string(),
        tool: arm.tool,
        friction: arm.model.label.clone(),
        role,
        mu,
        cutting_speed_m_per_min: c.cutting_speed_m_s * 60.0,
        uncut_chip_thickness_mm: c.uncut_chip_thickness_m * 1e3,
        measured_cutting_force_n_per_mm: fc,
        simulated_cutting_force_n_per_mm: cut.cutting_force_n_per_mm,
        measured_feed_force_n_per_mm: ff,
        simulated_feed_force_n_per_mm: cut.feed_force_n_per_mm,
        measured_chip_ratio: c.chip_ratio,
        simulated_chip_ratio: cut.chip_ratio,
        simulated_extent_ratio: cut
            .steady_report
            .as_ref()
            .and_then(|s| s.extent_ratio.as_ref())
            .map(|q| q.mean),
        measured_contact_length_mm: c.contact_length_m.map(|v| v * 1e3),
        simulated_contact_length_mm: cut.contact_length_mm,
        cutting_force_error: rel(cut.cutting_force_n_per_mm, fc),
        feed_force_error: rel(cut.feed_force_n_per_mm, ff),
        chip_ratio_error: c.chip_ratio.zip(cut.chip_ratio).map(|(m, s)| rel(s, m)),
        simulated_ci95: cut.intervals(),
        error_se: {
            let [sc, sf, sr] = cut.standard_errors();
            [
                sc.map(|e| e / fc),
                sf.map(|e| e / ff),
                sr.zip(c.chip_ratio).map(|(e, m)| e / m),
            ]
        },
        measured_error_se: {
            let [mc, mf, mr] = c.measured_standard_errors();
            let sim_over_meas = |s: f64, m: f64, se: f64| s / m * se / m;
            [
                mc.map(|se| sim_over_meas(cut.cutting_force_n_per_mm, fc, se * 1e-3)),
                mf.map(|se| sim_over_meas(cut.feed_force_n_per_mm, ff, se * 1e-3)),
                mr.zip(c.chip_ratio)
                    .zip(cut.chip_ratio)
                    .map(|((se, m), s)| sim_over_meas(s, m, se)),
            ]
        },
        steady_length_mm: cut.steady_length_mm().map(|l| l.0),
        steady_from_mm: cut.steady_length_mm().map(|l| l.1),
        sure: cut.sure,
        short_stretch: cut.short_stretch,
        local: cut.local,
        max_temperature_c: cut.peak_temperature_c,
        steady: cut.steady,
        simulated_cut_length_mm: cut.cut_length_mm,
        wall_s: cut.wall_s,
    }
}

/// The fitted parameters of an arm: its grid fields' values and, but for Coulomb (whose
/// factor is μ\*), its factor.
fn parameters(arm: &Arm, cal: &Calibrated) -> Vec<(String, f64)> {
    let mut p: Vec<(String, f64)> = arm
        .model
        .fields
        .iter()
        .cloned()
        .zip(cal.shape.iter().copied())
        .collect();
    if arm.model.factor.is_some() && arm.model.kind != VariantKind::CoulombCalibrated {
        p.push(("factor".to_string(), cal.factor));
    }
    p
}

fn summarise(
    done: &[Outcome],
    arm: &Arm,
    cal: &Calibrated,
    role: Role,
    mu: Option<f64>,
    goals: &goals::Goals,
) -> Option<ErrorSummary> {
    let rows: Vec<&Outcome> = done.iter().filter(|o| o.role == role).collect();
    if rows.is_empty() {
        return None;
    }
    let n = rows.len() as f64;
    let mean = |f: &dyn Fn(&Outcome) -> f64| rows.iter().map(|o| f(o)).sum::<f64>() / n;
    let of_some = |v: Vec<f64>, f: &dyn Fn(f64) -> f64| {
        (!v.is_empty()).then(|| v.iter().map(|&e| f(e)).sum::<f64>() / v.len() as f64)
    };
    let ratios: Vec<f64> = rows.iter().filter_map(|o| o.chip_ratio_error).collect();
    let mus: Vec<f64> = rows.iter().filter_map(|o| o.local.mean_mu).collect();
    let fc_abs = mean(&|o| o.cutting_force_error.abs());
    let ff_abs = mean(&|o| o.feed_force_error.abs());
    // the mean of n errors, each with its cut's standard error: 1.96 √(Σ se²)/n
    let ci = |k: usize, of: &dyn Fn(&Outcome) -> bool| {
        let se: Vec<Option<f64>> = rows
            .iter()
            .filter(|o| of(o))
            .map(|o| o.error_se[k])
            .collect();
        imputed_errors(&se).map(|(v, _)| mean_ci95(&v, v.len()))
    };
    let imputed = |k: usize| {
        rows.iter()
            .filter(|o| k < 2 || o.chip_ratio_error.is_some())
            .filter(|o| o.error_se[k].is_none())
            .count()
    };
    let checks = match role {
        Role::HeldOut => goals::check(&rows, goals),
        Role::Calibration => Vec::new(),
    };
    Some(ErrorSummary {
        material: arm.plan.runs.label().to_string(),
        tool: arm.tool,
        friction: arm.model.label.clone(),
        kind: arm.model.kind,
        role,
        conditions: rows.len(),
        mu,
        parameters: parameters(arm, cal),
        cutting_force_mean_abs: fc_abs,
        cutting_force_mean: mean(&|o| o.cutting_force_error),
        feed_force_mean_abs: ff_abs,
        feed_force_mean: mean(&|o| o.feed_force_error),
        chip_ratio_mean_abs: of_some(ratios.clone(), &|e| e.abs()),
        chip_ratio_mean: of_some(ratios, &|e| e),
        cutting_force_mean_abs_ci95: ci(0, &|_| true),
        feed_force_mean_abs_ci95: ci(1, &|_| true),
        chip_ratio_mean_abs_ci95: ci(2, &|o| o.chip_ratio_error.is_some()),
        factor_ci95: cal.factor_ci95,
        imputed_errors: [imputed(0), imputed(1), imputed(2)],
        mean_mu_applied: of_some(mus, &|m| m),
        goals: checks.clone(),
        goal: goals::Verdict::all(checks.iter().map(|c| c.verdict)),
        speed_trends: trend::trends(&rows),
        cuts: cal.cuts,
        cut_seconds: cal.cut_seconds,
    })
}

/// The run's own options: a fraction of the cut length in (0, 1] and at least one tool model.
fn check_options(o: &ValidateOptions) -> Result<()> {
    if !(o.fraction > 0.0 && o.fraction <= 1.0) {
        bail!(
            "fraction of the cut length (fraction): expected a number in (0, 1], got {}",
            o.fraction
        );
    }
    if o.tools.is_empty() {
        bail!("tool models (tools): expected at least one of adiabatic, thermal");
    }
    Ok(())
}

/// Every id of `o.only` is a condition of the data file `data`.
fn check_only(o: &ValidateOptions, conditions: &[Condition], data: &str) -> Result<()> {
    if let Some(id) = o
        .only
        .iter()
        .find(|id| !conditions.iter().any(|c| &c.id == *id))
    {
        bail!(
            "only: condition '{id}' is not in {data} (ids: {})",
            conditions
                .iter()
                .map(|c| c.id.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(())
}

/// The plan of one material: its checked calibration conditions, its held-out conditions
/// (those `o.only` wants) and its cutting set-up shortened to `o.fraction`.
fn material_plan<'a>(
    runs: &'a MaterialRuns,
    conditions: &'a [Condition],
    suite: &Suite,
    suite_path: &Path,
    o: &ValidateOptions,
) -> Result<Plan<'a>> {
    let rows: Vec<&Condition> = conditions
        .iter()
        .filter(|c| c.material == runs.name)
        .collect();
    check_material(runs, &rows, suite, suite_path)?;
    let base = suite_path.parent().unwrap_or(Path::new("."));
    let mut template = runs.template(base)?;
    if let Some(l) = runs.cut_length_m {
        if !(l > 0.0 && l.is_finite()) {
            bail!(
                "{}: material {}: cut_length_m = {l}: expected a positive length, m",
                suite_path.display(),
                runs.label()
            );
        }
        template.cut_length_m = l;
    }
    template.cut_length_m *= o.fraction;
    let models = runs
        .friction
        .iter()
        .map(|v| Model::build(v, runs.label(), runs.mu_bracket, base))
        .collect::<Result<Vec<_>>>()?;
    if models.is_empty() {
        bail!(
            "{}: material {}: friction = []: expected at least one friction model",
            suite_path.display(),
            runs.label()
        );
    }
    let wanted = |c: &&Condition| o.only.is_empty() || o.only.contains(&c.id);
    let is_cal = |c: &&Condition| runs.calibration.contains(&c.id);
    Ok(Plan {
        runs,
        template,
        calibration: rows.iter().copied().filter(is_cal).collect(),
        held_out: rows
            .iter()
            .copied()
            .filter(|c| !is_cal(c) && wanted(c))
            .collect(),
        models,
    })
}

/// A material's rows exist, its calibration conditions are its own and at most a third of
/// them, its μ bracket is ordered and its run speed is a cutting speed (the physics table:
/// impossible refused, unusual said).
fn check_material(
    runs: &MaterialRuns,
    rows: &[&Condition],
    suite: &Suite,
    suite_path: &Path,
) -> Result<()> {
    if rows.is_empty() {
        bail!(
            "{}: no conditions of material '{}' in {}",
            suite_path.display(),
            runs.name,
            suite.data
        );
    }
    for id in &runs.calibration {
        if !rows.iter().any(|c| &c.id == id) {
            bail!(
                "{}: calibration condition '{id}' is not a {} row of {}",
                suite_path.display(),
                runs.name,
                suite.data
            );
        }
    }
    if 3 * runs.calibration.len() > rows.len() || runs.calibration.is_empty() {
        bail!(
            "{}: material {}: {} calibration conditions of {}: expected at least one and at most a third",
            suite_path.display(),
            runs.name,
            runs.calibration.len(),
            rows.len()
        );
    }
    if runs.refine > MAX_REFINE {
        bail!(
            "{}: material {}: refine = {}: expected at most {MAX_REFINE} steps",
            suite_path.display(),
            runs.name,
            runs.refine
        );
    }
    let [lo, hi] = runs.mu_bracket;
    if !(lo >= 0.0 && hi > lo) {
        bail!(
            "{}: material {}: mu_bracket must be [low, high] with 0 ≤ low < high",
            suite_path.display(),
            runs.name
        );
    }
    // the run speed is a cutting speed: the physics table, as for a set-up's
    let what = format!("material {}: run_speed_m_per_min", runs.name);
    match greybox_core::physics::check(
        greybox_core::physics::Quantity::CuttingSpeed,
        runs.run_speed_m_per_min / 60.0,
        &what,
    ) {
        Ok(None) => {}
        Ok(Some(flag)) => {
            greybox_core::notes::note(format!("{}: {}", suite_path.display(), flag.text))
        }
        Err(e) => bail!("{}: {e}", suite_path.display()),
    }
    Ok(())
}

/// Runs the suite and writes its outputs into the directory `out`: staged and swapped in
/// whole once every cut has run, with a provenance record of the suite, its data and
/// templates. An `out` that already holds files is refused before any cut runs, unless
/// `force`. Returns the results and the files written (as they are named after the swap).
pub fn validate_into(
    suite_path: &Path,
    o: &ValidateOptions,
    out: &Path,
    force: bool,
) -> Result<(Validation, Vec<PathBuf>)> {
    let suite = Suite::read(suite_path)?;
    let files = suite.input_files(suite_path);
    let mut inputs = vec![("suite", suite_path)];
    inputs.extend(files.iter().map(|f| ("suite input", f.as_path())));
    let staged = greybox_pipeline::output::stage_out_dir(out, force, &inputs)?;
    let v = run_suite(&suite, suite_path, o, Some(&staged.path().join("cuts")))?;
    let files: Vec<PathBuf> = write_outputs(&v, staged.path())?
        .iter()
        .map(|p| staged.shown(p))
        .collect();
    greybox_pipeline::output::provenance(&inputs)?.write_into(staged.path())?;
    staged.commit()?;
    Ok((v, files))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A suite entry's `set` changes its template's fields by dotted path before the
    /// template is read (the rest as in the file), removes one with "none", and a field the
    /// set-up refuses is refused naming the file and the entry.
    #[test]
    fn a_suite_entry_sets_fields_of_its_template() {
        let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation");
        let entry = |set: &str| -> MaterialRuns {
            toml::from_str(&format!(
                "name = \"Ti6Al4V\"\nlabel = \"fitted\"\nsetup = \"ti64-seo-setup.toml\"\n\
                 run_speed_m_per_min = 600.0\ncalibration = []\nmu_bracket = [0.1, 0.7]\nset = {set}\n"
            ))
            .unwrap()
        };
        let plain = entry("{}").template(&repo).unwrap();
        let set = entry(r#"{ "material.plasticity.n" = 0.3, "chip_break_height_m" = "none" }"#)
            .template(&repo)
            .unwrap();
        let n = |s: &CuttingSetup| match s.material.plasticity.as_ref().unwrap() {
            greybox_material::FlowStress::JohnsonCook(jc) => jc.n,
            other => panic!("{other:?}"),
        };
        assert_eq!((n(&plain), n(&set)), (0.45, 0.3));
        assert!(plain.chip_break_height_m.is_some() && set.chip_break_height_m.is_none());
        let mut same = set.clone();
        same.material = plain.material.clone();
        same.chip_break_height_m = plain.chip_break_height_m;
        assert_eq!(same, plain, "nothing else changes");
        let e = format!(
            "{:#}",
            entry(r#"{ "material.plasticity.n" = -1.0 }"#)
                .template(&repo)
                .unwrap_err()
        );
        assert!(
            e.contains("ti64-seo-setup.toml with material fitted's set") && e.contains("n"),
            "{e}"
        );
        let e = format!(
            "{:#}",
            entry(r#"{ "material.plasticity.n.x" = 1.0 }"#)
                .template(&repo)
                .unwrap_err()
        );
        assert!(
            e.contains("material fitted: set") && e.contains("'n' is not a table"),
            "{e}"
        );
    }

    /// The shipped friction-sure suite, its conditions and options for planning it (thermal
    /// tool, half the cut length, in process).
    fn friction_sure_suite() -> (PathBuf, Suite, Vec<Condition>, ValidateOptions) {
        let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation");
        let suite_path = repo.join("suite-friction-sure.toml");
        let suite = Suite::read(&suite_path).unwrap();
        let conditions = read_conditions(&repo.join(&suite.data)).unwrap();
        let o = ValidateOptions {
            only: Vec::new(),
            tools: vec![ToolModel::Thermal],
            fraction: 0.5,
            runner: CutRunner::InProcess,
        };
        (suite_path, suite, conditions, o)
    }

    /// Every suite shipped in validation/ plans without a cut: its goals, data, set-up
    /// templates (with each entry's `set`) and friction models all read, as `bench validate`
    /// reads them before its first cut, and every entry has held-out conditions.
    #[test]
    fn every_bundled_suite_plans() {
        let (_, _, _, o) = friction_sure_suite();
        let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation");
        let mut suites: Vec<PathBuf> = std::fs::read_dir(&repo)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                let name = p.file_name().unwrap().to_string_lossy();
                name.starts_with("suite") && name.ends_with(".toml")
            })
            .collect();
        suites.sort();
        assert!(suites.len() >= 10, "{suites:?}");
        for path in &suites {
            let suite = Suite::read(path).unwrap();
            let conditions = read_conditions(&repo.join(&suite.data)).unwrap();
            let plans = plan_suite(&suite, path, &o, &conditions)
                .unwrap_or_else(|e| panic!("{}: {e:#}", path.display()));
            for plan in &plans {
                assert!(!plan.held_out.is_empty() && !plan.models.is_empty());
            }
        }
    }

    /// A suite entry's `cut_length_m` replaces the template's before the run's fraction;
    /// a length that is not positive is refused, naming the entry.
    #[test]
    fn a_suite_entry_replaces_the_cut_length() {
        let (suite_path, mut suite, conditions, o) = friction_sure_suite();
        let plan = material_plan(&suite.material[0], &conditions, &suite, &suite_path, &o).unwrap();
        assert!((plan.template.cut_length_m - 0.6e-3).abs() < 1e-15);
        suite.material[0].cut_length_m = Some(-1.0);
        let e = material_plan(&suite.material[0], &conditions, &suite, &suite_path, &o)
            .err()
            .unwrap();
        assert!(format!("{e:#}").contains("cut_length_m = -1"), "{e:#}");
    }

    /// A run speed no cut can have is refused naming the entry; an unusual one (0.01 m/min,
    /// a speed in m/s typed as m/min?) is said as a note; the shipped 600 m/min says nothing.
    #[test]
    fn a_suite_entrys_run_speed_is_checked_against_the_physics_table() {
        let (suite_path, mut suite, conditions, o) = friction_sure_suite();
        let plan = |suite: &Suite| {
            greybox_core::notes::collected(|| {
                material_plan(&suite.material[0], &conditions, suite, &suite_path, &o).map(|_| ())
            })
        };
        let (r, notes) = plan(&suite);
        assert!(r.is_ok() && notes.is_empty(), "{notes:?}");
        suite.material[0].run_speed_m_per_min = 0.01;
        let (r, notes) = plan(&suite);
        assert!(r.is_ok());
        assert!(
            notes
                .iter()
                .any(|n| n.contains("run_speed_m_per_min") && n.contains("usual range")),
            "{notes:?}"
        );
        suite.material[0].run_speed_m_per_min = 1e7;
        let (r, _) = plan(&suite);
        let e = format!("{:#}", r.unwrap_err());
        assert!(
            e.contains("run_speed_m_per_min") && e.contains("possible range"),
            "{e}"
        );
    }

    #[test]
    fn repeated_tool_models_run_once_in_the_order_named() {
        use ToolModel::{Adiabatic, Thermal};
        assert_eq!(
            distinct([Thermal, Adiabatic, Thermal, Adiabatic]),
            vec![Thermal, Adiabatic]
        );
    }
}
