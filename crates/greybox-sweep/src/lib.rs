//! Studies of many cuts. Parameter sweeps: a base case (a cut or a pin) and axes of any
//! configuration field, expanded into cases that run on a local process pool or as one Slurm
//! array job, resume where they stopped, and are collected into one table with plots; a
//! calibration of the Johnson–Cook C against measured forces uses sweeps as its inner loop.
//! The validation suite runs the cutting model against measured cuts.
//!
//! This crate sits above the pipeline (a case is a pipeline cut or pin) and knows no command
//! line: the program running a sweep hands in how a case's process starts ([`launch`]).
//!
//! | step | module |
//! |---|---|
//! | sweep file, axes | [`spec`] |
//! | cases: resolved configs, ids, cost, case directories | [`case`] |
//! | the plan and running one case | this crate's root |
//! | how a case's process starts (handed in) | [`launch`] |
//! | a local process pool | [`local`] |
//! | Slurm: array script, submission, following | [`slurm`] |
//! | one table and plots | [`collect`] |
//! | J-C C across conditions | [`calibrate`] |
//! | the executor and calibration settings | [`settings`] |
//! | measured cuts: μ* calibration, held-out errors | [`validate`] |

pub mod calibrate;
pub mod case;
pub mod collect;
pub mod fit_certainty;
pub mod launch;
pub mod local;
pub mod search;
pub mod settings;
pub mod slurm;
pub mod spec;
pub mod validate;

use anyhow::{bail, Context, Result};
use case::{Case, CaseDir, Done, Status};
use greybox_core::atomic::write_string_atomic;
use greybox_core::outputs::path_component;
use launch::CaseCommand;
use serde::{Deserialize, Serialize};
use spec::{CaseKind, SlurmSection, SweepFile};
use std::path::{Path, PathBuf};

/// A sweep expanded: what `greybox sweep plan` writes as `plan.json` in the sweep's
/// output directory, and what every executor and `run-case` read.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Plan {
    pub kind: CaseKind,
    pub fraction: f64,
    pub frames: greybox_pipeline::simulate::Frames,
    /// The fields the axes vary, in order.
    pub fields: Vec<String>,
    pub cases: Vec<Case>,
    pub slurm: SlurmSection,
    /// The sweep file it came from.
    pub source: String,
}

/// The file name of the plan in a sweep's output directory.
pub const PLAN_FILE: &str = "plan.json";

impl Plan {
    /// Expands the sweep file at `path` into cases.
    pub fn from_file(path: &Path) -> Result<Plan> {
        let (f, dir) = SweepFile::load(path)?;
        Self::expand(&f, &dir, &path.display().to_string(), &[])
    }

    /// Expands `f` (relative paths against `dir`), every case with `extra` (field, value)
    /// pairs applied after its axes (used by calibration).
    pub fn expand(
        f: &SweepFile,
        dir: &Path,
        source: &str,
        extra: &[(String, toml::Value)],
    ) -> Result<Plan> {
        let base = case::read_base(
            &dir.join(&f.sweep.base),
            f.sweep.kind,
            f.sweep.stop_when_sure,
        )
        .with_context(|| format!("{source}: [sweep] base"))?;
        let axes = f.expand_axes().with_context(|| source.to_string())?;
        let mut fields: Vec<String> = axes.iter().flat_map(|a| a.fields.clone()).collect();
        fields.extend(extra.iter().map(|(k, _)| k.clone()));
        let cases = spec::combinations(&axes)
            .into_iter()
            .enumerate()
            .map(|(i, mut values)| {
                values.extend(extra.iter().cloned());
                case::build(
                    f.sweep.kind,
                    &base,
                    &values,
                    dir,
                    f.sweep.fraction,
                    f.sweep.frames,
                    i,
                )
                .with_context(|| source.to_string())
            })
            .collect::<Result<Vec<_>>>()?;
        let mut ids: Vec<&str> = cases.iter().map(|c| c.id.as_str()).collect();
        ids.sort_unstable();
        if ids.windows(2).any(|w| w[0] == w[1]) {
            bail!(
                "{source}: two cases resolve to the same configuration (an axis repeats a value?)"
            );
        }
        Ok(Plan {
            kind: f.sweep.kind,
            fraction: f.sweep.fraction,
            frames: f.sweep.frames,
            fields,
            cases,
            slurm: f.slurm.clone(),
            source: source.to_string(),
        })
    }

    /// Writes `plan.json` and every case's directory with its `config.toml` into `out`.
    pub fn write(&self, out: &Path) -> Result<()> {
        std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
        for c in &self.cases {
            CaseDir::of(out, &c.id).prepare(c)?;
        }
        write_string_atomic(&out.join(PLAN_FILE), &serde_json::to_string_pretty(self)?)?;
        Ok(())
    }

    /// Reads the `plan.json` of a sweep's output directory.
    pub fn read(out: &Path) -> Result<Plan> {
        let p = out.join(PLAN_FILE);
        let text = case::read_state(&p, "sweep plan")
            .context("plan the sweep first (greybox sweep plan, or sweep run)")?;
        let plan: Plan = serde_json::from_str(&text)
            .with_context(|| format!("{}: not a sweep plan", p.display()))?;
        // every id becomes a directory under cases/, every field part of a plot's file name;
        // one id, one case, one place in the plan
        let mut seen = std::collections::HashMap::new();
        for (i, c) in plan.cases.iter().enumerate() {
            path_component(&c.id, &p, &format!("cases[{i}].id"))?;
            if let Some(j) = seen.insert(c.id.as_str(), i) {
                bail!(
                    "{}: cases[{i}].id {} repeats cases[{j}].id: two cases would share one directory and one result (plan the sweep again)",
                    p.display(),
                    c.id
                );
            }
            if c.index != i {
                bail!(
                    "{}: cases[{i}].index is {}, not its place {i} in the plan (plan the sweep again)",
                    p.display(),
                    c.index
                );
            }
        }
        for (i, f) in plan.fields.iter().enumerate() {
            path_component(f, &p, &format!("fields[{i}]"))?;
        }
        Ok(plan)
    }

    /// The status of every case in `out`.
    pub fn statuses(&self, out: &Path) -> Vec<Status> {
        self.cases
            .iter()
            .map(|c| CaseDir::of(out, &c.id).status(c))
            .collect()
    }
}

/// Runs case `index` of the plan in `out` (what a pool worker or a Slurm array task does):
/// a finished case is left alone; otherwise the run writes `result/` (replacing leftovers
/// of an interrupted attempt) and then `done.json`, or `failed.json` with the error.
pub fn run_case(out: &Path, index: usize) -> Result<Status> {
    let plan = Plan::read(out)?;
    let case = plan.cases.get(index).with_context(|| {
        format!(
            "case index {index}: the plan has {} cases (0 … {})",
            plan.cases.len(),
            plan.cases.len().saturating_sub(1)
        )
    })?;
    let dir = CaseDir::of(out, &case.id);
    if dir.status(case) == Status::Done {
        return Ok(Status::Done);
    }
    dir.ensure()?;
    dir.checked_config(case)?;
    let _ = std::fs::remove_file(dir.failed());
    let t0 = std::time::Instant::now();
    match run_config(&plan, &dir) {
        Ok(summary) => {
            let done = Done {
                id: case.id.clone(),
                config_sha256: Some(case::config_sha256(&case.config)),
                wall_s: t0.elapsed().as_secs_f64(),
                peak_memory_mb: greybox_core::provenance::peak_memory_mb(),
                summary,
            };
            write_string_atomic(&dir.done(), &serde_json::to_string_pretty(&done)?)?;
            Ok(Status::Done)
        }
        Err(e) => {
            let msg = serde_json::json!({ "id": case.id, "error": format!("{e:#}") });
            write_string_atomic(&dir.failed(), &serde_json::to_string_pretty(&msg)?)?;
            Err(e.context(format!("case {index} ({})", case.id)))
        }
    }
}

fn run_config(plan: &Plan, dir: &CaseDir) -> Result<serde_json::Value> {
    use greybox_pipeline::simulate::{read_cutting_setup, run_cut, run_pin, RunOutput};
    let o = RunOutput {
        force: true,
        frames: plan.frames,
        ..RunOutput::to(dir.result())
    };
    Ok(match plan.kind {
        CaseKind::Cutting => {
            let case = read_cutting_setup(&dir.config())?;
            serde_json::to_value(run_cut(&case, plan.fraction, &o)?)?
        }
        CaseKind::Pin => {
            let setup: greybox_sim::pin::PinSetup =
                greybox_pipeline::config_toml::read(&dir.config(), "pin set-up")?;
            serde_json::to_value(run_pin(&setup, &o)?)?
        }
    })
}

/// The executor of `greybox sweep run`.
#[derive(Debug, Clone)]
pub enum Executor {
    /// A pool of `jobs` processes on this machine.
    Local { jobs: usize },
    /// One Slurm array job; `dry_run` prints the script only.
    Slurm { dry_run: bool, poll_s: f64 },
}

/// What a run of the sweep ended with.
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    pub cases: usize,
    pub done: usize,
    /// Cases finished before this run (skipped).
    pub skipped: usize,
    pub failed: Vec<FailedCase>,
    /// Slurm: the job id and the script.
    pub slurm_job: Option<String>,
    pub slurm_script: Option<String>,
}

/// A case that failed, with the end of its log.
#[derive(Debug, Clone, Serialize)]
pub struct FailedCase {
    pub index: usize,
    pub id: String,
    pub error: String,
    pub log_tail: String,
}

/// The failed cases of the plan in `out` with their errors and log tails (`log` gives a
/// case's log file).
pub fn failures(plan: &Plan, out: &Path, log: &dyn Fn(&Case) -> PathBuf) -> Vec<FailedCase> {
    plan.cases
        .iter()
        .filter(|c| CaseDir::of(out, &c.id).status(c) == Status::Failed)
        .map(|c| {
            let error = CaseDir::of(out, &c.id).failure().unwrap_or_default();
            FailedCase {
                index: c.index,
                id: c.id.clone(),
                error,
                log_tail: case::tail(&log(c), 20),
            }
        })
        .collect()
}

impl Executor {
    /// Runs the unfinished cases of `plan` (written to `out`), each case's process started by
    /// `command`.
    pub fn run(&self, plan: &Plan, out: &Path, command: &CaseCommand) -> Result<RunReport> {
        match self {
            Executor::Local { jobs } => local::run(plan, out, *jobs, command),
            Executor::Slurm { dry_run, poll_s } => {
                slurm::run(plan, out, command, *dry_run, *poll_s)
            }
        }
    }
}

/// Plans the sweep file into `out` and runs its unfinished cases on `executor`, each case's
/// process started by `command`.
pub fn run(
    sweep_file: &Path,
    out: &Path,
    executor: &Executor,
    command: &CaseCommand,
) -> Result<RunReport> {
    run_plan(&Plan::from_file(sweep_file)?, out, executor, command)
}

/// Writes `plan` into `out` and runs its unfinished cases on `executor`, each case's process
/// started by `command`; for Slurm, the array script is checked before anything is written.
pub fn run_plan(
    plan: &Plan,
    out: &Path,
    executor: &Executor,
    command: &CaseCommand,
) -> Result<RunReport> {
    if let Executor::Slurm { .. } = executor {
        slurm::check(plan, out, command)?;
    }
    plan.write(out)?;
    executor.run(plan, out, command)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A planned sweep of the bundled cut over two rake angles, written to `d/o`; its
    /// `plan.json` as JSON.
    fn planned(d: &Path) -> serde_json::Value {
        std::fs::write(
            d.join("cut.toml"),
            include_str!("../../../examples/aisi1045-cut.toml"),
        )
        .unwrap();
        std::fs::write(
            d.join("s.toml"),
            "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\n[[axis]]\nfield = \"insert.rake_deg\"\nvalues = [0.0, 6.0]\n",
        )
        .unwrap();
        let plan = Plan::from_file(&d.join("s.toml")).unwrap();
        plan.write(&d.join("o")).unwrap();
        serde_json::to_value(&plan).unwrap()
    }

    /// Issue 62: `plan.json` is read like any input: one id per case, each case at its place.
    #[test]
    fn a_plan_with_a_repeated_id_or_a_moved_case_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let v = planned(d.path());
        let out = d.path().join("o");
        assert_eq!(Plan::read(&out).unwrap().cases.len(), 2);
        let mut dup = v.clone();
        dup["cases"][1]["id"] = dup["cases"][0]["id"].clone();
        std::fs::write(out.join(PLAN_FILE), dup.to_string()).unwrap();
        let e = format!("{:#}", Plan::read(&out).unwrap_err());
        assert!(
            e.contains("cases[1].id") && e.contains("repeats cases[0].id"),
            "{e}"
        );
        let mut moved = v.clone();
        moved["cases"][1]["index"] = serde_json::json!(4294967297u64);
        std::fs::write(out.join(PLAN_FILE), moved.to_string()).unwrap();
        let e = format!("{:#}", Plan::read(&out).unwrap_err());
        assert!(e.contains("cases[1].index is 4294967297"), "{e}");
    }
}
