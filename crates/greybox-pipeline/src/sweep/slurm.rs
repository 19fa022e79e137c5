//! The Slurm executor: the unfinished cases as one `sbatch` array job (one task per case,
//! each running `greybox sweep run-case` on its node with the same markers as the local
//! pool), submitted, followed with `squeue` until it leaves the queue, then checked with
//! `sacct` and the cases' markers; failed tasks are reported with the end of their logs.
//!
//! Resources per task come from the sweep file's `[slurm]` section or, when unset, from
//! the cost estimate: time = 3 × (particle-steps of the largest case) / (10⁶ particle-steps
//! per second per core × cpus) + 5 min (the solver runs at 1.2–2.4·10⁶ here, see
//! docs/scaling.md); memory = 256 MB + 4 kB per particle.

use super::case::{tail, CaseDir, Status};
use super::{FailedCase, Plan, RunReport};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Particle-steps per second and core assumed for the time limit (conservative).
const RATE_PER_CORE: f64 = 1.0e6;

/// `0-3,5,7-9`: sorted indices as Slurm array ranges.
pub fn array_spec(indices: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < indices.len() {
        let mut j = i;
        while j + 1 < indices.len() && indices[j + 1] == indices[j] + 1 {
            j += 1;
        }
        parts.push(if j > i {
            format!("{}-{}", indices[i], indices[j])
        } else {
            indices[i].to_string()
        });
        i = j + 1;
    }
    parts.join(",")
}

/// `HH:MM:SS` for `s` seconds (rounded up to whole minutes).
fn hms(s: f64) -> String {
    let m = (s / 60.0).ceil().max(1.0) as u64;
    format!("{:02}:{:02}:00", m / 60, m % 60)
}

/// Where the array task `index` of job `job` writes its log.
pub fn log_path(out: &Path, job: &str, index: usize) -> PathBuf {
    out.join("slurm")
        .join("logs")
        .join(format!("{job}_{index}.log"))
}

/// The array script for `indices` of `plan` (output directory `out` and executable `exe`
/// as absolute paths).
pub fn script(plan: &Plan, out: &Path, exe: &Path, indices: &[usize]) -> String {
    let s = &plan.slurm;
    let cpus = s.cpus_per_task.unwrap_or(1).max(1);
    let largest = indices
        .iter()
        .map(|&i| plan.cases[i].cost)
        .fold((0.0f64, 0usize), |(ps, n), c| {
            (ps.max(c.particle_steps), n.max(c.particles))
        });
    let time = s
        .time
        .clone()
        .unwrap_or_else(|| hms(3.0 * largest.0 / (RATE_PER_CORE * cpus as f64) + 300.0));
    let mem = s
        .mem_mb
        .unwrap_or(256 + (largest.1 as u64 * 4096).div_ceil(1 << 20));
    let mut t = String::from("#!/bin/bash\n");
    let _ = writeln!(t, "#SBATCH --job-name=greybox-sweep");
    let mut array = format!("#SBATCH --array={}", array_spec(indices));
    if let Some(m) = s.max_concurrent {
        let _ = write!(array, "%{m}");
    }
    let _ = writeln!(t, "{array}");
    let _ = writeln!(
        t,
        "#SBATCH --output={}",
        out.join("slurm/logs/%A_%a.log").display()
    );
    let _ = writeln!(t, "#SBATCH --time={time}");
    let _ = writeln!(t, "#SBATCH --mem={mem}M");
    let _ = writeln!(t, "#SBATCH --cpus-per-task={cpus}");
    let _ = writeln!(t, "#SBATCH --ntasks=1");
    if let Some(p) = &s.partition {
        let _ = writeln!(t, "#SBATCH --partition={p}");
    }
    if let Some(a) = &s.account {
        let _ = writeln!(t, "#SBATCH --account={a}");
    }
    for e in &s.extra {
        let _ = writeln!(t, "#SBATCH {}", e.trim());
    }
    let _ = writeln!(
        t,
        "# {} case(s) of {}; largest: {} particles, {:.3e} particle-steps",
        indices.len(),
        plan.source,
        largest.1,
        largest.0
    );
    let _ = writeln!(
        t,
        "export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{cpus}}}\""
    );
    let _ = writeln!(
        t,
        "exec '{}' --quiet sweep run-case '{}' --index \"$SLURM_ARRAY_TASK_ID\"",
        exe.display(),
        out.display()
    );
    t
}

fn command_output(cmd: &mut Command, what: &str) -> Result<String> {
    let o = cmd
        .output()
        .with_context(|| format!("cannot run {what} (is Slurm installed and on PATH?)"))?;
    if !o.status.success() {
        bail!(
            "{what} failed ({}): {}",
            o.status,
            String::from_utf8_lossy(&o.stderr).trim()
        );
    }
    Ok(String::from_utf8_lossy(&o.stdout).into_owned())
}

/// Writes the script for the unfinished cases, submits it (unless `dry_run`) and follows
/// the job until it has left the queue.
pub fn run(plan: &Plan, out: &Path, exe: &Path, dry_run: bool, poll_s: f64) -> Result<RunReport> {
    let out = std::path::absolute(out)?;
    let exe = std::path::absolute(exe)?;
    let statuses = plan.statuses(&out);
    let indices: Vec<usize> = (0..plan.cases.len())
        .filter(|&i| statuses[i] != Status::Done)
        .collect();
    let skipped = plan.cases.len() - indices.len();
    let mut report = RunReport {
        cases: plan.cases.len(),
        done: skipped,
        skipped,
        failed: Vec::new(),
        slurm_job: None,
        slurm_script: None,
    };
    if indices.is_empty() {
        return Ok(report);
    }
    let text = script(plan, &out, &exe, &indices);
    report.slurm_script = Some(text.clone());
    if dry_run {
        return Ok(report);
    }
    std::fs::create_dir_all(out.join("slurm/logs"))?;
    let path = out.join("slurm/sweep.sbatch");
    write_string_atomic(&path, &text)?;
    let submitted = command_output(
        Command::new("sbatch").arg("--parsable").arg(&path),
        "sbatch",
    )?;
    let job = submitted.trim().split(';').next().unwrap_or("").to_string();
    if job.is_empty() {
        bail!("sbatch printed no job id");
    }
    report.slurm_job = Some(job.clone());
    follow(plan, &out, &job, &indices, poll_s)?;
    let states = task_states(&job);
    report.done = plan
        .statuses(&out)
        .iter()
        .filter(|s| **s == Status::Done)
        .count();
    report.failed = indices
        .iter()
        .filter(|&&i| CaseDir::of(&out, &plan.cases[i].id).status() != Status::Done)
        .map(|&i| {
            let c = &plan.cases[i];
            let dir = CaseDir::of(&out, &c.id);
            let error = dir.failure().unwrap_or_else(|| {
                format!(
                    "no result; Slurm state {}",
                    states.get(&i).map_or("unknown", String::as_str)
                )
            });
            FailedCase {
                index: i,
                id: c.id.clone(),
                error,
                log_tail: tail(&log_path(&out, &job, i), 20),
            }
        })
        .collect();
    Ok(report)
}

/// Polls `squeue` until job `job` has no task left in the queue, reporting progress by
/// the cases' markers.
fn follow(plan: &Plan, out: &Path, job: &str, indices: &[usize], poll_s: f64) -> Result<()> {
    let progress =
        greybox_core::progress::task("sweep (slurm)", Some(indices.len() as u64), "cases");
    loop {
        let queue = command_output(
            Command::new("squeue").args(["-h", "-r", "-j", job, "-o", "%i %T"]),
            "squeue",
        )
        .unwrap_or_default();
        let finished = indices
            .iter()
            .filter(|&&i| CaseDir::of(out, &plan.cases[i].id).status() != Status::Pending)
            .count();
        let queued = queue.lines().filter(|l| !l.trim().is_empty()).count();
        progress.set_with(finished as u64, || {
            format!("job {job}: {queued} task(s) in the queue")
        });
        if queued == 0 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_secs_f64(poll_s.max(0.1)));
    }
    progress.finish("job left the queue");
    Ok(())
}

/// The final state per array index from `sacct` (empty where accounting is off).
fn task_states(job: &str) -> std::collections::HashMap<usize, String> {
    let text = command_output(
        Command::new("sacct").args(["-n", "-P", "-X", "-j", job, "-o", "JobID,State"]),
        "sacct",
    )
    .unwrap_or_default();
    text.lines()
        .filter_map(|l| {
            let (id, state) = l.split_once('|')?;
            let idx = id.split_once('_')?.1.parse().ok()?;
            Some((idx, state.trim().to_string()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn indices_compress_to_array_ranges_and_times_round_up() {
        assert_eq!(array_spec(&[0, 1, 2, 3, 5, 7, 8, 9]), "0-3,5,7-9");
        assert_eq!(array_spec(&[4]), "4");
        assert_eq!(hms(61.0), "00:02:00");
        assert_eq!(hms(3.0 * 3600.0), "03:00:00");
    }
}
