//! Where the suite's cuts run. Each step of the suite (the calibration cuts at the bracket
//! ends, each refinement, the final cuts) is one batch of independent cuts, run either
//!
//! * in this process, every cut of the batch in parallel on all cores (the default), or
//! * as the cases of one sweep plan on a sweep [`Executor`]: the local process pool or one
//!   Slurm array job per batch. Each cut becomes a case whose `config.toml` is the
//!   condition's whole cutting set-up with the friction model's law inline
//!   (`[friction.law]`, its files by absolute path); the case runs `greybox sweep run-case`
//!   like any sweep case, and the suite reads the cut back from the case's summary
//!   ([`Cut::from_summary`]). The plans are written under the suite's output directory,
//!   `cuts/batch-NN/`. Cuts with the same set-up and law run once.
//!
//! Both give the same numbers: a case reads back the set-up and law the suite built, and the
//! cut keeps the cut summary's expressions (`tests: cli_validate.rs`).

use super::cut::{run_cut, Cut};
use super::variant::ModelLaw;
use crate::case::{self, Case, CaseDir, Done};
use crate::launch::CaseCommand;
use crate::spec::{CaseKind, SlurmSection};
use crate::{Executor, Plan};
use anyhow::{bail, Context, Result};
use greybox_sim::cutting::CuttingSetup;
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// How the suite's cuts run.
#[derive(Debug, Clone, Default)]
pub enum CutRunner {
    /// In this process, each batch's cuts in parallel.
    #[default]
    InProcess,
    /// As sweep cases on `executor`, each started by `command` (a `greybox` program).
    Cases {
        executor: Executor,
        command: CaseCommand,
    },
}

/// One cut of a batch: the condition's set-up, the law, and how messages and the case
/// table name it (condition, tool model, friction model).
pub struct CutJob {
    pub setup: CuttingSetup,
    pub law: ModelLaw,
    pub shown: Vec<(String, String)>,
}

/// The fields a suite case is shown by in its plan.
const SHOWN: [&str; 3] = ["condition", "tool", "friction"];

impl CutJob {
    fn what(&self) -> String {
        show(&self.shown)
    }

    /// The job as case `index` of a sweep plan: the set-up with the law inline, a flow-stress
    /// table's curves inline (the case runs from another directory).
    fn case(&self, index: usize) -> Result<Case> {
        let mut s = self.setup.clone();
        s.friction.law = None;
        s.friction.law_file = None;
        if let Some(greybox_material::FlowStress::Table(t)) = s.material.plasticity.as_mut() {
            t.file = None;
        }
        let mut v = toml::Value::try_from(&s).context("the cutting set-up as TOML")?;
        let law = toml::Value::try_from(&*self.law.spec).context("the law as TOML")?;
        case::apply(&mut v, "friction.law", &law)?;
        let frames = greybox_pipeline::simulate::Frames::of(0);
        let mut c = case::build(
            CaseKind::Cutting,
            &v,
            &[],
            Path::new("."),
            1.0,
            frames,
            index,
        )
        .with_context(|| self.what())?;
        c.values = self.shown.clone();
        Ok(c)
    }
}

/// The batches of one suite run: where their plans go and the suite's Slurm resources.
pub struct Batches<'a> {
    pub runner: &'a CutRunner,
    /// The directory the plans are written under (needed by [`CutRunner::Cases`]).
    pub dir: Option<PathBuf>,
    pub slurm: SlurmSection,
    /// The suite file, as plans name their source.
    pub source: String,
    /// Batches run so far.
    pub count: usize,
}

impl Batches<'_> {
    /// Runs every job as one batch; the cuts in the jobs' order.
    pub fn run(&mut self, jobs: &[CutJob]) -> Result<Vec<Cut>> {
        self.count += 1;
        match self.runner {
            CutRunner::InProcess => jobs
                .par_iter()
                .map(|j| run_cut(&j.setup, j.law.law.clone()).map_err(|e| e.context(j.what())))
                .collect(),
            CutRunner::Cases { executor, command } => {
                let dir = self.dir.as_ref().context(
                    "a suite run on an executor writes its cases into its output directory: none was given",
                )?;
                let out = dir.join(format!("batch-{:02}", self.count));
                self.run_as_cases(jobs, &out, executor, command)
            }
        }
    }

    fn run_as_cases(
        &self,
        jobs: &[CutJob],
        out: &Path,
        executor: &Executor,
        command: &CaseCommand,
    ) -> Result<Vec<Cut>> {
        let mut cases: Vec<Case> = Vec::new();
        let mut case_of_job = Vec::with_capacity(jobs.len());
        for j in jobs {
            let c = j.case(cases.len())?;
            match cases.iter().position(|k| k.id == c.id) {
                Some(k) => case_of_job.push(k),
                None => {
                    case_of_job.push(cases.len());
                    cases.push(c);
                }
            }
        }
        let plan = Plan {
            kind: CaseKind::Cutting,
            fraction: 1.0,
            frames: greybox_pipeline::simulate::Frames::of(0),
            fields: SHOWN.iter().map(|s| s.to_string()).collect(),
            cases,
            slurm: self.slurm.clone(),
            source: self.source.clone(),
        };
        let report = crate::run_plan(&plan, out, executor, command)?;
        if let Some(f) = report.failed.first() {
            bail!(
                "{} of {} cuts failed ({}); the first, {}: {}\n{}",
                report.failed.len(),
                plan.cases.len(),
                out.display(),
                show(&plan.cases[f.index].values),
                f.error,
                f.log_tail
            );
        }
        let cuts = plan
            .cases
            .iter()
            .map(|c| read_cut(&CaseDir::of(out, &c.id), c))
            .collect::<Result<Vec<_>>>()?;
        Ok(case_of_job.into_iter().map(|k| cuts[k].clone()).collect())
    }
}

fn show(values: &[(String, String)]) -> String {
    values
        .iter()
        .map(|(k, v)| format!("{k} {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The cut a finished case ran, from its `done.json`; its `result/` (the run's profiles and
/// plots, which the suite does not report) is removed.
fn read_cut(dir: &CaseDir, case: &Case) -> Result<Cut> {
    let path = dir.done();
    let done: Done = dir
        .read_done(case)?
        .with_context(|| format!("{}: missing: the case did not finish", path.display()))?;
    let cut = Cut::from_summary(&done.summary, &path.display().to_string())?;
    let _ = std::fs::remove_dir_all(dir.result());
    Ok(cut)
}
