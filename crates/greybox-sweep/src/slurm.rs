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
use super::launch::CaseCommand;
use super::spec::SlurmSection;
use super::{FailedCase, Plan, RunReport};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::outputs::path_component;
use greybox_core::shell;
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

/// `#SBATCH` lines of the `[slurm]` section's free values (partition, account, time, extra),
/// each checked by [`shell::directive_value`]; `extra` entries must be `--flag` or
/// `--flag=value`.
fn user_directives(s: &SlurmSection, time: &str, source: &str) -> Result<Vec<String>> {
    let field = |f: &str| format!("sweep file {}, [slurm] {f}", shell::comment(source));
    let mut lines = vec![format!(
        "--time={}",
        shell::directive_value(&field("time"), time)?
    )];
    if !time
        .chars()
        .all(|c| c.is_ascii_digit() || c == ':' || c == '-')
    {
        bail!(
            "{}: '{time}' is not a Slurm time (minutes, MM:SS, HH:MM:SS or D-HH:MM:SS)",
            field("time")
        );
    }
    for (name, v) in [("partition", &s.partition), ("account", &s.account)] {
        if let Some(v) = v {
            lines.push(format!(
                "--{name}={}",
                shell::directive_value(&field(name), v)?
            ));
        }
    }
    for (k, e) in s.extra.iter().enumerate() {
        let what = field(&format!("extra[{k}]"));
        let e = e.trim();
        let (flag, value) = e.split_once('=').unwrap_or((e, ""));
        let name_ok = flag.strip_prefix("--").is_some_and(|n| {
            n.starts_with(|c: char| c.is_ascii_lowercase())
                && n.chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
        });
        if !name_ok {
            bail!("{what}: {e:?} is not a long option `--flag` or `--flag=value` (write -q short as --qos=short)");
        }
        if e.contains('=') {
            shell::directive_value(&what, value)?;
        }
        lines.push(e.to_string());
    }
    Ok(lines)
}

/// The array script for `indices` of `plan` (output directory `out` and the case command
/// `command` with an absolute program). Every value from the user goes through [`greybox_core::shell`]:
/// quoted for the shell, checked against an allow-list in `#SBATCH` lines (which sbatch
/// parses itself), escaped in comments; what cannot go in safely is refused.
pub fn script(plan: &Plan, out: &Path, command: &CaseCommand, indices: &[usize]) -> Result<String> {
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
    let mem = s.mem_mb.unwrap_or(
        256 + (largest.1 as u64 * greybox_sim::particles::BYTES_PER_PARTICLE).div_ceil(1 << 20),
    );
    let text = |p: &Path, what: &str| {
        p.to_str()
            .map(str::to_string)
            .with_context(|| format!("{what} {}: not UTF-8", p.display()))
    };
    let out_text = text(out, "--out")?;
    let log = format!("{out_text}/slurm/logs/%A_%a.log");
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
        shell::directive_value(&format!("--out {}", shell::comment(&out_text)), &log)?
    );
    let _ = writeln!(t, "#SBATCH --mem={mem}M");
    let _ = writeln!(t, "#SBATCH --cpus-per-task={cpus}");
    let _ = writeln!(t, "#SBATCH --ntasks=1");
    for d in user_directives(s, &time, &plan.source)? {
        let _ = writeln!(t, "#SBATCH {d}");
    }
    let _ = writeln!(
        t,
        "# {} case(s) of {}; largest: {} particles, {:.3e} particle-steps",
        indices.len(),
        shell::comment(&plan.source),
        largest.1,
        largest.0
    );
    let _ = writeln!(
        t,
        "export RAYON_NUM_THREADS=\"${{SLURM_CPUS_PER_TASK:-{cpus}}}\""
    );
    let _ = writeln!(
        t,
        "exec {}",
        command.shell_line(&out_text, "\"$SLURM_ARRAY_TASK_ID\"")?
    );
    Ok(t)
}

/// Refuses, before anything is written, a plan whose Slurm script could not be written
/// safely (the same checks as [`script`]).
pub fn check(plan: &Plan, out: &Path, command: &CaseCommand) -> Result<()> {
    let all: Vec<usize> = (0..plan.cases.len()).collect();
    script(plan, &std::path::absolute(out)?, &command.absolute()?, &all).map(drop)
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
pub fn run(
    plan: &Plan,
    out: &Path,
    command: &CaseCommand,
    dry_run: bool,
    poll_s: f64,
) -> Result<RunReport> {
    let out = std::path::absolute(out)?;
    let command = command.absolute()?;
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
    let text = script(plan, &out, &command, &indices)?;
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
    // the job id names the tasks' log files
    path_component(&job, Path::new("sbatch --parsable's output"), "job id")?;
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
        .filter(|&&i| CaseDir::of(&out, &plan.cases[i].id).status(&plan.cases[i]) != Status::Done)
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
            .filter(|&&i| {
                CaseDir::of(out, &plan.cases[i].id).status(&plan.cases[i]) != Status::Pending
            })
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

    /// The case command the `greybox` binary hands in, with `program` as its executable.
    fn cmd(program: &str) -> CaseCommand {
        CaseCommand::greybox(program)
    }

    fn plan(slurm: SlurmSection, source: &str) -> Plan {
        use super::super::case::{Case, Cost};
        Plan {
            kind: super::super::spec::CaseKind::Pin,
            fraction: 1.0,
            frames: greybox_pipeline::simulate::Frames::of(0),
            fields: vec![],
            cases: vec![Case {
                index: 0,
                id: "abc".into(),
                values: vec![],
                config: String::new(),
                cost: Cost {
                    particles: 1000,
                    steps: 10,
                    particle_steps: 1e4,
                },
            }],
            slurm,
            source: source.into(),
        }
    }

    /// The script run by bash with `/bin/echo` as the executable: the task's arguments come
    /// out verbatim and no injected command runs.
    #[test]
    fn hostile_names_stay_text_when_the_script_runs() {
        let d = tempfile::tempdir().unwrap();
        let marker = d.path().join("pwned");
        let m = marker.display();
        // the source may hold anything: it only goes into a comment
        let source = format!("s.toml\ntouch {m}\n");
        let p = plan(SlurmSection::default(), &source);
        let out = d.path().join("o");
        let t = script(&p, &out, &cmd("/bin/echo"), &[0]).unwrap();
        assert!(t.lines().filter(|l| l.starts_with('#')).count() >= 8, "{t}");
        let run = std::process::Command::new("/bin/bash")
            .arg("-c")
            .arg(&t)
            .env("SLURM_ARRAY_TASK_ID", "0")
            .output()
            .unwrap();
        assert_eq!(
            String::from_utf8_lossy(&run.stdout).trim_end(),
            format!("--quiet sweep run-case {} --index 0", out.display())
        );
        assert!(!marker.exists(), "{t}");
        // a quote, a substitution and a newline in --out: refused for the #SBATCH line
        for bad in ["o'x", "o$(touch M)", "o\ntouch M", "o x"] {
            let e = script(&p, &d.path().join(bad), &cmd("/bin/echo"), &[0])
                .unwrap_err()
                .to_string();
            assert!(e.contains("--out") && e.contains("#SBATCH"), "{e}");
        }
    }

    #[test]
    fn slurm_section_values_are_checked_field_by_field() {
        let refused = |s: SlurmSection, field: &str| {
            let e = script(&plan(s, "s.toml"), Path::new("/o"), &cmd("/g"), &[0])
                .unwrap_err()
                .to_string();
            assert!(e.contains(field) && e.contains("s.toml"), "{field}: {e}");
        };
        let with = |f: &dyn Fn(&mut SlurmSection)| {
            let mut s = SlurmSection::default();
            f(&mut s);
            s
        };
        refused(
            with(&|s| s.partition = Some("a'; touch M; '".into())),
            "[slurm] partition",
        );
        refused(
            with(&|s| s.partition = Some("a\n#SBATCH --x".into())),
            "[slurm] partition",
        );
        refused(
            with(&|s| s.account = Some("$(id)".into())),
            "[slurm] account",
        );
        refused(
            with(&|s| s.time = Some("1:00\ntouch M".into())),
            "[slurm] time",
        );
        refused(with(&|s| s.time = Some("soon".into())), "[slurm] time");
        refused(
            with(&|s| s.extra = vec!["--qos=short; touch M".into()]),
            "[slurm] extra[0]",
        );
        refused(
            with(&|s| s.extra = vec!["-q short".into()]),
            "[slurm] extra[0]",
        );
        refused(
            with(&|s| s.extra = vec!["--comment=a\nb".into()]),
            "[slurm] extra[0]",
        );
        let ok = with(&|s| {
            s.partition = Some("compute".into());
            s.account = Some("proj-42".into());
            s.time = Some("1-02:00:00".into());
            s.extra = vec!["--qos=short".into(), " --exclusive ".into()];
        });
        let t = script(&plan(ok, "s.toml"), Path::new("/o"), &cmd("/g"), &[0]).unwrap();
        for l in [
            "#SBATCH --partition=compute",
            "#SBATCH --account=proj-42",
            "#SBATCH --time=1-02:00:00",
            "#SBATCH --qos=short",
            "#SBATCH --exclusive",
        ] {
            assert!(t.lines().any(|x| x == l), "{l} in {t}");
        }
    }
}
