//! The local executor: a pool of case processes (the handed-in [`CaseCommand`]), `jobs` at a time,
//! each with its share of the cores (`RAYON_NUM_THREADS`) and its own log file.
//!
//! Finished cases are skipped, failed ones run again. A case counts as finished only when
//! its `done.json` exists, which `run-case` writes after the run's outputs are complete;
//! an interrupt (Ctrl-C reaches the whole process group) leaves the cases that were running
//! without it, so the next run repeats them.

use super::case::{CaseDir, Status};
use super::launch::CaseCommand;
use super::{failures, Plan, RunReport};
use anyhow::{Context, Result};
use greybox_core::atomic::create_output_file;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// Runs the unfinished cases of `plan` (already written to `out`) with `jobs` processes,
/// each started by `command`.
pub fn run(plan: &Plan, out: &Path, jobs: usize, command: &CaseCommand) -> Result<RunReport> {
    let jobs = jobs.max(1);
    let statuses = plan.statuses(out);
    let skipped = statuses.iter().filter(|s| **s == Status::Done).count();
    let mut queue = plan
        .cases
        .iter()
        .zip(&statuses)
        .filter(|(_, s)| **s != Status::Done)
        .map(|(c, _)| c)
        .peekable();
    let pending = plan.cases.len() - skipped;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let threads = (cores / jobs).max(1);
    let progress = greybox_core::progress::task("sweep", Some(pending as u64), "cases");
    let mut running: Vec<(usize, Child)> = Vec::new();
    let (mut done, mut failed) = (0usize, 0usize);
    while queue.peek().is_some() || !running.is_empty() {
        while running.len() < jobs {
            let Some(c) = queue.next() else { break };
            let dir = CaseDir::of(out, &c.id);
            let log = create_output_file(&dir.log())
                .with_context(|| format!("cannot write {}", dir.log().display()))?;
            let child = Command::new(&command.program)
                .args(command.args_for(out, &c.index.to_string()))
                .env("RAYON_NUM_THREADS", threads.to_string())
                .stdin(Stdio::null())
                .stdout(log.try_clone()?)
                .stderr(log)
                .spawn()
                .with_context(|| format!("cannot start {}", command.program.display()))?;
            running.push((c.index, child));
        }
        let mut still = Vec::with_capacity(running.len());
        for (i, mut child) in running {
            match child.try_wait()? {
                Some(_) => {
                    let c = &plan.cases[i];
                    if CaseDir::of(out, &c.id).status(c) == Status::Done {
                        done += 1;
                    } else {
                        failed += 1;
                    }
                }
                None => still.push((i, child)),
            }
        }
        running = still;
        progress.set_with((done + failed) as u64, || {
            format!("{} running, {failed} failed", running.len())
        });
        std::thread::sleep(Duration::from_millis(50));
    }
    progress.finish(&format!("{done} done, {failed} failed"));
    Ok(RunReport {
        cases: plan.cases.len(),
        done: skipped + done,
        skipped,
        failed: failures(plan, out, &|c| CaseDir::of(out, &c.id).log()),
        slurm_job: None,
        slurm_script: None,
    })
}
