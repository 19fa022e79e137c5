//! The validation suite: simulated orthogonal cuts against measured ones from published
//! experiments, with an honest split — one friction value per material and tool model is
//! calibrated on at most a third of the conditions, and the errors are reported on the
//! rest, held out.
//!
//! A suite file (TOML) names the data (a CSV of measured conditions, one row each, units in
//! the column names, every row citing its source) and, per material, a cutting set-up
//! template whose condition fields (speed, uncut chip thickness, rake, clearance, edge
//! radius) each row replaces. Two tool models run: the adiabatic tool (all friction heat into
//! the chip, as in the ETH IWF codes) and the template's thermal tool.
//!
//! Calibration: the calibration conditions run at the two ends of `mu_bracket`; per
//! condition F'f is interpolated linearly in μ, and μ* is where the mean signed relative
//! error of F'f over them is zero (the end of the bracket nearest to that, when it lies
//! outside). Every condition then runs at μ*, the calibration ones included, so that their
//! errors are simulated, not interpolated.
//!
//! Slow cuts run time-scaled (`run_speed_m_per_min`; see
//! [`greybox_sim::cutting::CuttingSetup::physical_cutting_speed_m_s`]).

use anyhow::{bail, Context, Result};
use greybox_core::csvutil::{csv_error, parse_f64, record_line, Header};
use greybox_sim::cut_run::CutRun;
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::ConstantMu;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The suite file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Suite {
    /// Measured conditions (CSV, relative to the suite file).
    pub data: String,
    pub material: Vec<MaterialRuns>,
}

impl Suite {
    /// Reads a suite file.
    pub fn read(path: &Path) -> Result<Suite> {
        greybox_pipeline::config_toml::read(path, "validation suite")
    }

    /// The files the suite at `path` reads: its data and its set-up templates (relative
    /// paths resolved against the suite's directory).
    pub fn input_files(&self, path: &Path) -> Vec<PathBuf> {
        let base = path.parent().unwrap_or(Path::new("."));
        std::iter::once(base.join(&self.data))
            .chain(self.material.iter().map(|m| base.join(&m.setup)))
            .collect()
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
    /// μ range searched, [low, high].
    pub mu_bracket: [f64; 2],
}

/// One measured condition (SI inside; the CSV has units in its column names).
#[derive(Debug, Clone, Serialize)]
pub struct Condition {
    pub id: String,
    pub material: String,
    pub source: String,
    pub cutting_speed_m_s: f64,
    pub uncut_chip_thickness_m: f64,
    pub rake_deg: f64,
    pub clearance_deg: f64,
    pub edge_radius_m: f64,
    /// Measured forces per width, N/m, and their reported dispersions.
    pub cutting_force_n_per_m: f64,
    pub cutting_force_dispersion_n_per_m: Option<f64>,
    pub feed_force_n_per_m: f64,
    pub feed_force_dispersion_n_per_m: Option<f64>,
    /// Chip compression ratio h_c/h, where reported.
    pub chip_ratio: Option<f64>,
    /// Tool–chip contact length, m, where reported.
    pub contact_length_m: Option<f64>,
}

/// Reads the measured conditions.
pub fn read_conditions(path: &Path) -> Result<Vec<Condition>> {
    let src = path.display().to_string();
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .map_err(|e| csv_error(&src, e))?;
    let header = Header::new(&src, rdr.headers().map_err(|e| csv_error(&src, e))?);
    let need = |n: &str| header.require(n);
    let cols = [
        need("id")?,
        need("material")?,
        need("source")?,
        need("cutting_speed_m_per_min")?,
        need("uncut_chip_thickness_mm")?,
        need("rake_deg")?,
        need("clearance_deg")?,
        need("edge_radius_um")?,
        need("cutting_force_N_per_mm")?,
        need("feed_force_N_per_mm")?,
    ];
    let opt = |n: &str| header.find(n);
    let (c_fcd, c_ffd, c_ratio, c_lc) = (
        opt("cutting_force_dispersion_N_per_mm"),
        opt("feed_force_dispersion_N_per_mm"),
        opt("chip_ratio"),
        opt("contact_length_mm"),
    );
    let mut out: Vec<Condition> = Vec::new();
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| csv_error(&src, e))?;
        let line = record_line(rec.position(), k as u64 + 2);
        let num = |c: usize| parse_f64(&rec[c], &src, line, &header.names()[c]);
        let maybe = |c: Option<usize>| -> Result<Option<f64>> {
            match c {
                Some(c) if !rec[c].trim().is_empty() => Ok(Some(num(c)?)),
                _ => Ok(None),
            }
        };
        let positive = |c: usize, v: f64| -> Result<f64> {
            if v > 0.0 {
                Ok(v)
            } else {
                bail!(
                    "{src}: line {line}: column {}: expected a value > 0, got {v}",
                    header.names()[c]
                )
            }
        };
        let id = rec[cols[0]].trim().to_string();
        if id.is_empty() || out.iter().any(|c| c.id == id) {
            bail!("{src}: line {line}: column id: expected a unique, non-empty id, got '{id}'");
        }
        out.push(Condition {
            id,
            material: rec[cols[1]].trim().to_string(),
            source: rec[cols[2]].trim().to_string(),
            cutting_speed_m_s: positive(cols[3], num(cols[3])?)? / 60.0,
            uncut_chip_thickness_m: positive(cols[4], num(cols[4])?)? * 1e-3,
            rake_deg: num(cols[5])?,
            clearance_deg: num(cols[6])?,
            edge_radius_m: num(cols[7])? * 1e-6,
            cutting_force_n_per_m: positive(cols[8], num(cols[8])?)? * 1e3,
            cutting_force_dispersion_n_per_m: maybe(c_fcd)?.map(|v| v * 1e3),
            feed_force_n_per_m: positive(cols[9], num(cols[9])?)? * 1e3,
            feed_force_dispersion_n_per_m: maybe(c_ffd)?.map(|v| v * 1e3),
            chip_ratio: maybe(c_ratio)?,
            contact_length_m: maybe(c_lc)?.map(|v| v * 1e-3),
        });
    }
    if out.is_empty() {
        bail!("{src}: no conditions");
    }
    Ok(out)
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

/// The set-up of condition `c` from `template` for `tool`.
pub fn condition_setup(
    template: &CuttingSetup,
    c: &Condition,
    runs: &MaterialRuns,
    tool: ToolModel,
    mu: f64,
) -> Result<CuttingSetup> {
    let mut s = template.clone();
    s.insert.rake_deg = c.rake_deg;
    s.insert.clearance_deg = c.clearance_deg;
    s.insert.edge_radius_m = c.edge_radius_m;
    s.uncut_chip_thickness_m = c.uncut_chip_thickness_m;
    let run = runs.run_speed_m_per_min / 60.0;
    if c.cutting_speed_m_s < run {
        s.cutting_speed_m_s = run;
        s.physical_cutting_speed_m_s = Some(c.cutting_speed_m_s);
    } else {
        s.cutting_speed_m_s = c.cutting_speed_m_s;
        s.physical_cutting_speed_m_s = None;
    }
    s.mu = mu;
    match tool {
        ToolModel::Adiabatic => {
            s.tool_thermal = None;
            s.numerics.friction_heat_share = 1.0;
        }
        ToolModel::Thermal => {
            if s.tool_thermal.is_none() {
                bail!(
                    "{}: the set-up template {} has no [tool_thermal] section for the thermal tool",
                    runs.name,
                    runs.setup
                );
            }
        }
    }
    s.validate()
        .with_context(|| format!("condition {}", c.id))?;
    Ok(s)
}

/// One simulated condition.
/// What a condition is for in the suite: μ* is calibrated on the calibration conditions,
/// the held-out ones only test it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Calibration,
    HeldOut,
}

greybox_core::choice!(Role, "role", [Calibration => "calibration", HeldOut => "held-out"]);

#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    pub id: String,
    pub material: String,
    pub tool: ToolModel,
    pub role: Role,
    pub mu: f64,
    pub cutting_speed_m_per_min: f64,
    pub uncut_chip_thickness_mm: f64,
    pub measured_cutting_force_n_per_mm: f64,
    pub simulated_cutting_force_n_per_mm: f64,
    pub measured_feed_force_n_per_mm: f64,
    pub simulated_feed_force_n_per_mm: f64,
    pub measured_chip_ratio: Option<f64>,
    pub simulated_chip_ratio: Option<f64>,
    pub measured_contact_length_mm: Option<f64>,
    pub simulated_contact_length_mm: Option<f64>,
    /// Relative errors (simulated − measured)/measured.
    pub cutting_force_error: f64,
    pub feed_force_error: f64,
    pub chip_ratio_error: Option<f64>,
    /// The hottest particle over the run, °C.
    pub max_temperature_c: f64,
    pub steady: bool,
    /// Cut length simulated, mm (shorter than the template's when the run stopped steady).
    pub simulated_cut_length_mm: f64,
    pub wall_s: f64,
}

/// Mean errors of one material and tool model over one role.
#[derive(Debug, Clone, Serialize)]
pub struct ErrorSummary {
    pub material: String,
    pub tool: ToolModel,
    pub role: Role,
    pub conditions: usize,
    pub mu: f64,
    /// Mean |error| and mean signed error, as fractions.
    pub cutting_force_mean_abs: f64,
    pub cutting_force_mean: f64,
    pub feed_force_mean_abs: f64,
    pub feed_force_mean: f64,
    pub chip_ratio_mean_abs: Option<f64>,
    pub chip_ratio_mean: Option<f64>,
    /// The goal on held-out conditions: F'c within ±15 %, F'f within ±30 % on average.
    pub meets_goal: bool,
}

/// What a suite run gave.
#[derive(Debug, Clone, Serialize)]
pub struct Validation {
    pub outcomes: Vec<Outcome>,
    pub summaries: Vec<ErrorSummary>,
    /// Cut length run per condition (fraction of the template's).
    pub fraction: f64,
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
}

struct Plan<'a> {
    runs: &'a MaterialRuns,
    template: CuttingSetup,
    calibration: Vec<&'a Condition>,
    held_out: Vec<&'a Condition>,
}

/// Runs the suite.
pub fn validate(suite_path: &Path, o: &ValidateOptions) -> Result<Validation> {
    run_suite(&Suite::read(suite_path)?, suite_path, o)
}

/// The tool models, each once, in the order first named.
fn distinct_in_order(tools: &[ToolModel]) -> Vec<ToolModel> {
    let mut once: Vec<ToolModel> = Vec::new();
    for &t in tools {
        if !once.contains(&t) {
            once.push(t);
        }
    }
    once
}

/// Runs `suite`, read from `suite_path` (relative paths resolve against its directory):
/// μ* calibrated per material and tool model, then every wanted condition cut at its μ*.
fn run_suite(suite: &Suite, suite_path: &Path, o: &ValidateOptions) -> Result<Validation> {
    check_options(o)?;
    let base = suite_path.parent().unwrap_or(Path::new("."));
    let conditions = read_conditions(&base.join(&suite.data))?;
    check_only(o, &conditions, &suite.data)?;
    let plans = suite
        .material
        .iter()
        .map(|runs| material_plan(runs, &conditions, suite, suite_path, o))
        .collect::<Result<Vec<_>>>()?;
    let tools = distinct_in_order(&o.tools);
    let groups: Vec<(&Plan, ToolModel)> = plans
        .iter()
        .flat_map(|p| tools.iter().map(move |&t| (p, t)))
        .collect();
    let mus = calibrate(&groups)?;
    // Every condition of every group at its μ*, as one batch.
    let done: Vec<Outcome> = jobs(&groups, &mus)
        .par_iter()
        .map(|j| simulate(j.plan, j.condition, j.tool, j.mu, j.role))
        .collect::<Result<_>>()?;
    Ok(Validation {
        summaries: summaries(&groups, &mus, &done),
        outcomes: done,
        fraction: o.fraction,
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
    let mut template =
        greybox_pipeline::simulate::read_cutting_setup(&base.join(&runs.setup))?.setup;
    template.cut_length_m *= o.fraction;
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
    })
}

/// A material's rows exist, its calibration conditions are its own and at most a third of
/// them, and its μ bracket is ordered.
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
    let [lo, hi] = runs.mu_bracket;
    if !(lo >= 0.0 && hi > lo) {
        bail!(
            "{}: material {}: mu_bracket must be [low, high] with 0 ≤ low < high",
            suite_path.display(),
            runs.name
        );
    }
    Ok(())
}

/// Every condition of every group (calibration first, then held out) at its group's μ*.
fn jobs<'a>(groups: &[(&'a Plan<'a>, ToolModel)], mus: &[f64]) -> Vec<Job<'a>> {
    groups
        .iter()
        .zip(mus)
        .flat_map(|(&(plan, tool), &mu)| {
            let calibration = plan.calibration.iter().map(|&c| (c, Role::Calibration));
            let held_out = plan.held_out.iter().map(|&c| (c, Role::HeldOut));
            calibration.chain(held_out).map(move |(c, role)| Job {
                plan,
                tool,
                condition: c,
                mu,
                role,
            })
        })
        .collect()
}

/// Per group and role, the summary of its outcomes (`done` in the order of [`jobs`]).
fn summaries(groups: &[(&Plan, ToolModel)], mus: &[f64], done: &[Outcome]) -> Vec<ErrorSummary> {
    let mut summaries = Vec::new();
    let mut rest = done;
    for (&(plan, tool), &mu) in groups.iter().zip(mus) {
        let (of_group, after) = rest.split_at(plan.calibration.len() + plan.held_out.len());
        rest = after;
        for role in [Role::Calibration, Role::HeldOut] {
            if let Some(s) = summarise(of_group, plan.runs.label(), tool, role, mu) {
                summaries.push(s);
            }
        }
    }
    summaries
}

/// One cut of the suite: a condition of a material's plan, with a tool model, at μ.
struct Job<'a> {
    plan: &'a Plan<'a>,
    tool: ToolModel,
    condition: &'a Condition,
    mu: f64,
    role: Role,
}

/// μ* of each (material, tool model) group (module docs). The calibration conditions of
/// every group run at both ends of their bracket as one parallel batch, so that the cores
/// wait for the slowest cut once, not once per group.
fn calibrate(groups: &[(&Plan, ToolModel)]) -> Result<Vec<f64>> {
    let jobs: Vec<Job> = groups
        .iter()
        .flat_map(|&(plan, tool)| {
            plan.calibration.iter().flat_map(move |&c| {
                plan.runs.mu_bracket.map(|mu| Job {
                    plan,
                    tool,
                    condition: c,
                    mu,
                    role: Role::Calibration,
                })
            })
        })
        .collect();
    let errors: Vec<f64> = jobs
        .par_iter()
        .map(|j| -> Result<f64> {
            let s = condition_setup(&j.plan.template, j.condition, j.plan.runs, j.tool, j.mu)?;
            Ok(run(&s)?.force[1] / j.condition.feed_force_n_per_m - 1.0)
        })
        .collect::<Result<_>>()?;
    let mut errors = errors.chunks_exact(2);
    Ok(groups
        .iter()
        .map(|&(plan, _)| {
            let ends: Vec<&[f64]> = errors.by_ref().take(plan.calibration.len()).collect();
            mu_star(plan.runs.mu_bracket, &ends)
        })
        .collect())
}

/// Where the mean F'f error, linear in μ between the bracket ends, is zero (clamped to the
/// bracket); `ends` holds each calibration condition's errors at the two ends.
fn mu_star([lo, hi]: [f64; 2], ends: &[&[f64]]) -> f64 {
    let n = ends.len() as f64;
    let e_lo = ends.iter().map(|e| e[0]).sum::<f64>() / n;
    let e_hi = ends.iter().map(|e| e[1]).sum::<f64>() / n;
    if e_hi == e_lo {
        return 0.5 * (lo + hi);
    }
    let mu = lo + (hi - lo) * (0.0 - e_lo) / (e_hi - e_lo);
    mu.clamp(lo, hi)
}

fn run(s: &CuttingSetup) -> Result<CutRun> {
    Ok(CutRun::execute(
        s,
        Arc::new(ConstantMu(s.mu)),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )?)
}

fn simulate(plan: &Plan, c: &Condition, tool: ToolModel, mu: f64, role: Role) -> Result<Outcome> {
    let s = condition_setup(&plan.template, c, plan.runs, tool, mu)?;
    let r = run(&s).with_context(|| format!("condition {} ({} tool)", c.id, tool.name()))?;
    let rel = |sim: f64, meas: f64| sim / meas - 1.0;
    let ratio = r.measures.compression_ratio;
    Ok(Outcome {
        id: c.id.clone(),
        material: plan.runs.label().to_string(),
        tool,
        role,
        mu,
        cutting_speed_m_per_min: c.cutting_speed_m_s * 60.0,
        uncut_chip_thickness_mm: c.uncut_chip_thickness_m * 1e3,
        measured_cutting_force_n_per_mm: c.cutting_force_n_per_m * 1e-3,
        simulated_cutting_force_n_per_mm: r.force[0] * 1e-3,
        measured_feed_force_n_per_mm: c.feed_force_n_per_m * 1e-3,
        simulated_feed_force_n_per_mm: r.force[1] * 1e-3,
        measured_chip_ratio: c.chip_ratio,
        simulated_chip_ratio: ratio,
        measured_contact_length_mm: c.contact_length_m.map(|v| v * 1e3),
        simulated_contact_length_mm: r.measures.contact_length_mm,
        cutting_force_error: rel(r.force[0], c.cutting_force_n_per_m),
        feed_force_error: rel(r.force[1], c.feed_force_n_per_m),
        chip_ratio_error: c.chip_ratio.zip(ratio).map(|(m, s)| rel(s, m)),
        max_temperature_c: r.peak_temperature.peak_k - 273.15,
        steady: r.steady.steady_since_s.is_some(),
        simulated_cut_length_mm: r.sim.time * s.cutting_speed_m_s * 1e3,
        wall_s: r.summary.wall_s,
    })
}

fn summarise(
    done: &[Outcome],
    material: &str,
    tool: ToolModel,
    role: Role,
    mu: f64,
) -> Option<ErrorSummary> {
    let rows: Vec<&Outcome> = done.iter().filter(|o| o.role == role).collect();
    if rows.is_empty() {
        return None;
    }
    let n = rows.len() as f64;
    let mean = |f: &dyn Fn(&Outcome) -> f64| rows.iter().map(|o| f(o)).sum::<f64>() / n;
    let ratios: Vec<f64> = rows.iter().filter_map(|o| o.chip_ratio_error).collect();
    let rmean = |f: &dyn Fn(f64) -> f64| {
        (!ratios.is_empty())
            .then(|| ratios.iter().map(|&e| f(e)).sum::<f64>() / ratios.len() as f64)
    };
    let fc_abs = mean(&|o| o.cutting_force_error.abs());
    let ff_abs = mean(&|o| o.feed_force_error.abs());
    Some(ErrorSummary {
        material: material.to_string(),
        tool,
        role,
        conditions: rows.len(),
        mu,
        cutting_force_mean_abs: fc_abs,
        cutting_force_mean: mean(&|o| o.cutting_force_error),
        feed_force_mean_abs: ff_abs,
        feed_force_mean: mean(&|o| o.feed_force_error),
        chip_ratio_mean_abs: rmean(&|e| e.abs()),
        chip_ratio_mean: rmean(&|e| e),
        meets_goal: fc_abs <= 0.15 && ff_abs <= 0.30,
    })
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
    let v = run_suite(&suite, suite_path, o)?;
    let files: Vec<PathBuf> = write_outputs(&v, staged.path())?
        .iter()
        .map(|p| staged.shown(p))
        .collect();
    greybox_pipeline::output::provenance(&inputs)?.write_into(staged.path())?;
    staged.commit()?;
    Ok((v, files))
}

/// Writes `results.csv`, `summary.json`, `validation.md` (tables) and the plots
/// `forces.svg` (simulated against measured forces, both tool models) into the existing
/// directory `out`.
pub fn write_outputs(v: &Validation, out: &Path) -> Result<Vec<PathBuf>> {
    use greybox_core::atomic::{write_atomic, write_string_atomic};
    let opt = |v: Option<f64>, d: usize| v.map_or(String::new(), |x| format!("{x:.d$}"));
    let results = out.join("results.csv");
    write_atomic(&results, |w| {
        writeln!(w, "id,material,tool,role,mu,cutting_speed_m_per_min,uncut_chip_thickness_mm,measured_cutting_force_N_per_mm,simulated_cutting_force_N_per_mm,cutting_force_error,measured_feed_force_N_per_mm,simulated_feed_force_N_per_mm,feed_force_error,measured_chip_ratio,simulated_chip_ratio,chip_ratio_error,simulated_contact_length_mm,peak_temperature_C,steady,simulated_cut_length_mm,wall_s")?;
        for o in &v.outcomes {
            writeln!(
                w,
                "{},{},{},{},{:.4},{},{:.3},{:.2},{:.2},{:.4},{:.2},{:.2},{:.4},{},{},{},{},{:.1},{},{:.3},{:.1}",
                o.id,
                o.material,
                o.tool.name(),
                o.role,
                o.mu,
                o.cutting_speed_m_per_min,
                o.uncut_chip_thickness_mm,
                o.measured_cutting_force_n_per_mm,
                o.simulated_cutting_force_n_per_mm,
                o.cutting_force_error,
                o.measured_feed_force_n_per_mm,
                o.simulated_feed_force_n_per_mm,
                o.feed_force_error,
                opt(o.measured_chip_ratio, 3),
                opt(o.simulated_chip_ratio, 3),
                opt(o.chip_ratio_error, 4),
                opt(o.simulated_contact_length_mm, 3),
                o.max_temperature_c,
                o.steady,
                o.simulated_cut_length_mm,
                o.wall_s
            )?;
        }
        Ok(())
    })?;
    let summary = out.join("summary.json");
    write_string_atomic(&summary, &serde_json::to_string_pretty(v)?)?;
    let md = out.join("validation.md");
    write_string_atomic(&md, &markdown(v))?;
    let plot = out.join("forces.svg");
    write_string_atomic(&plot, &force_plot(v))?;
    Ok(vec![results, summary, md, plot])
}

/// Tables of the errors (summary, then per condition).
pub fn markdown(v: &Validation) -> String {
    let pct = |e: f64| format!("{:+.1} %", 100.0 * e);
    let mut s = String::from("| material | tool | conditions | μ | F'c mean abs error (mean) | F'f mean abs error (mean) | chip ratio mean abs error (mean) | goal (F'c ±15 %, F'f ±30 %) |\n|---|---|---|---|---|---|---|---|\n");
    for e in &v.summaries {
        s += &format!(
            "| {} | {} | {} {} | {:.3} | {:.1} % ({}) | {:.1} % ({}) | {} | {} |\n",
            e.material,
            e.tool.name(),
            e.conditions,
            e.role,
            e.mu,
            100.0 * e.cutting_force_mean_abs,
            pct(e.cutting_force_mean),
            100.0 * e.feed_force_mean_abs,
            pct(e.feed_force_mean),
            e.chip_ratio_mean_abs
                .zip(e.chip_ratio_mean)
                .map_or("—".into(), |(a, m)| format!(
                    "{:.1} % ({})",
                    100.0 * a,
                    pct(m)
                )),
            if e.role == Role::HeldOut {
                if e.meets_goal {
                    "met"
                } else {
                    "not met"
                }
            } else {
                "(calibration)"
            }
        );
    }
    let steady = v.outcomes.iter().filter(|o| o.steady).count();
    let length: f64 = v.outcomes.iter().map(|o| o.simulated_cut_length_mm).sum();
    s += &format!(
        "\n{steady} of {} cuts reached steady forces; {:.3} mm of cut simulated on average.\n",
        v.outcomes.len(),
        length / v.outcomes.len().max(1) as f64
    );
    s += "\n| id | material | tool | role | v_c m/min | h mm | F'c meas / sim N/mm | F'f meas / sim N/mm | h_c/h meas / sim | T_peak °C |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for o in &v.outcomes {
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.1} / {:.1} ({}) | {:.1} / {:.1} ({}) | {} | {:.0} |\n",
            o.id,
            o.material,
            o.tool.name(),
            o.role,
            o.cutting_speed_m_per_min,
            o.uncut_chip_thickness_mm,
            o.measured_cutting_force_n_per_mm,
            o.simulated_cutting_force_n_per_mm,
            pct(o.cutting_force_error),
            o.measured_feed_force_n_per_mm,
            o.simulated_feed_force_n_per_mm,
            pct(o.feed_force_error),
            o.measured_chip_ratio
                .zip(o.simulated_chip_ratio)
                .map_or("—".into(), |(m, s)| format!("{m:.2} / {s:.2}")),
            o.max_temperature_c
        );
    }
    s
}

/// Simulated against measured F'c and F'f, held-out conditions, one colour per material
/// entry, tool model and force.
fn force_plot(v: &Validation) -> String {
    let mut labels: Vec<&str> = Vec::new();
    for o in &v.outcomes {
        if !labels.contains(&o.material.as_str()) {
            labels.push(&o.material);
        }
    }
    type Pair = fn(&Outcome) -> (f64, f64);
    let forces: [(&str, Pair); 2] = [
        ("F'c", |o| {
            (
                o.measured_cutting_force_n_per_mm,
                o.simulated_cutting_force_n_per_mm,
            )
        }),
        ("F'f", |o| {
            (
                o.measured_feed_force_n_per_mm,
                o.simulated_feed_force_n_per_mm,
            )
        }),
    ];
    let mut data = Vec::new();
    for label in &labels {
        for tool in [ToolModel::Adiabatic, ToolModel::Thermal] {
            for (force, f) in forces {
                let (m, s): (Vec<f64>, Vec<f64>) = v
                    .outcomes
                    .iter()
                    .filter(|o| o.tool == tool && o.role == Role::HeldOut && o.material == *label)
                    .map(f)
                    .unzip();
                if !m.is_empty() {
                    data.push((format!("{force}, {label}, {} tool", tool.name()), m, s));
                }
            }
        }
    }
    const COLOURS: [&str; 8] = [
        "#1f77b4", "#aec7e8", "#d62728", "#ff9896", "#2ca02c", "#98df8a", "#9467bd", "#c5b0d5",
    ];
    let series: Vec<(&str, &str, &[f64], &[f64])> = data
        .iter()
        .zip(COLOURS.iter().cycle())
        .map(|((l, m, s), c)| (l.as_str(), *c, m.as_slice(), s.as_slice()))
        .collect();
    greybox_core::plot::predicted_vs_measured(
        "held-out conditions: simulated against measured force per width",
        "(N/mm)",
        &series,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mu_star_is_where_the_mean_error_line_crosses_zero() {
        // Mean error −0.2 at μ 0.2 and +0.4 at μ 0.8: zero at 0.2 + 0.6 · 0.2/0.6 = 0.4.
        let (a, b) = ([-0.3, 0.5], [-0.1, 0.3]);
        assert!((mu_star([0.2, 0.8], &[&a, &b]) - 0.4).abs() < 1e-15);
        // Outside the bracket: its nearer end; flat: its middle.
        assert_eq!(mu_star([0.2, 0.8], &[&[0.1, 0.3]]), 0.2);
        assert_eq!(mu_star([0.2, 0.8], &[&[-0.5, -0.1]]), 0.8);
        assert_eq!(mu_star([0.2, 0.8], &[&[0.1, 0.1]]), 0.5);
    }

    #[test]
    fn repeated_tool_models_run_once_in_the_order_named() {
        use ToolModel::{Adiabatic, Thermal};
        assert_eq!(
            distinct_in_order(&[Thermal, Adiabatic, Thermal, Adiabatic]),
            vec![Thermal, Adiabatic]
        );
    }

    #[test]
    fn reads_conditions_with_units_and_names_bad_fields() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("c.csv");
        std::fs::write(&p, "# measured\nid,material,source,cutting_speed_m_per_min,uncut_chip_thickness_mm,rake_deg,clearance_deg,edge_radius_um,cutting_force_N_per_mm,feed_force_N_per_mm,chip_ratio\nA,Ti6Al4V,x,30,0.06,15,2,20,118.2,50.3,1.23\n").unwrap();
        let c = read_conditions(&p).unwrap();
        assert_eq!(c.len(), 1);
        assert!((c[0].cutting_speed_m_s - 0.5).abs() < 1e-12);
        assert!((c[0].uncut_chip_thickness_m - 6e-5).abs() < 1e-15);
        assert!((c[0].cutting_force_n_per_m - 118_200.0).abs() < 1e-9);
        assert_eq!(c[0].chip_ratio, Some(1.23));
        std::fs::write(&p, "id,material,source,cutting_speed_m_per_min,uncut_chip_thickness_mm,rake_deg,clearance_deg,edge_radius_um,cutting_force_N_per_mm,feed_force_N_per_mm\nA,Ti,x,30,-0.06,15,2,20,118,50\n").unwrap();
        let e = format!("{:#}", read_conditions(&p).unwrap_err());
        assert!(
            e.contains("line 2") && e.contains("uncut_chip_thickness_mm"),
            "{e}"
        );
    }
}
