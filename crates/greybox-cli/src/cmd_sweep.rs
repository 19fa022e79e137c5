//! `greybox sweep`: parameter studies on a local process pool or a Slurm cluster.

use crate::output::emit;
use anyhow::Result;
use greybox_pipeline::sweep::calibrate::{calibrate, CalibrateOptions, HoldOut};
use greybox_pipeline::sweep::{self, collect::collect, Executor, Plan};
use std::fmt::Write as _;
use std::path::PathBuf;

#[derive(clap::Subcommand, Debug)]
pub enum Sweep {
    /// Expand a sweep file into cases (each with its directory and resolved config); print
    /// the case table with the cost of each.
    Plan {
        sweep_file: PathBuf,
        /// The sweep's output directory.
        #[arg(long, default_value = "sweep-out")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Run the unfinished cases (finished ones are skipped, failed ones rerun).
    Run {
        sweep_file: PathBuf,
        #[arg(long, default_value = "sweep-out")]
        out: PathBuf,
        /// `local` (a process pool here) or `slurm` (one sbatch array job).
        #[arg(long, default_value = "local")]
        executor: String,
        /// Local: cases at once.
        #[arg(long, default_value_t = 1)]
        jobs: usize,
        /// Slurm: print the array script, submit nothing.
        #[arg(long)]
        dry_run: bool,
        /// Slurm: seconds between squeue polls.
        #[arg(long, default_value_t = 10.0)]
        poll_s: f64,
        #[arg(long)]
        json: bool,
    },
    /// Run one case of a planned sweep (what pool workers and Slurm array tasks run).
    #[command(hide = true)]
    RunCase {
        out: PathBuf,
        #[arg(long)]
        index: usize,
    },
    /// Gather every case's summary into results.csv and plot the results over the axes.
    Collect {
        #[arg(default_value = "sweep-out")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Find the Johnson–Cook C (and optionally a μ scale) that best matches measured forces
    /// at several conditions, each iteration a sweep.
    Calibrate {
        sweep_file: PathBuf,
        /// CSV: configuration fields per condition, cutting_force_N_per_mm[, feed_force_N_per_mm].
        #[arg(long)]
        measured: PathBuf,
        #[arg(long, default_value = "calibrate-out")]
        out: PathBuf,
        #[arg(long, default_value = "local")]
        executor: String,
        #[arg(long, default_value_t = 1)]
        jobs: usize,
        #[arg(long, default_value_t = 10.0)]
        poll_s: f64,
        /// Bracket of C.
        #[arg(long = "c-min", default_value_t = 0.001)]
        c_min: f64,
        #[arg(long = "c-max", default_value_t = 0.1)]
        c_max: f64,
        /// Evaluations per golden-section search.
        #[arg(long, default_value_t = 10)]
        iterations: usize,
        /// Hold out every k-th condition (default 3) …
        #[arg(long = "hold-out-every", default_value_t = 3)]
        hold_out_every: usize,
        /// … or these conditions (1-based, comma-separated).
        #[arg(long = "hold-out", value_delimiter = ',')]
        hold_out: Vec<usize>,
        /// Also scale the base's Coulomb mu.
        #[arg(long)]
        friction_scale: bool,
        #[arg(long)]
        json: bool,
    },
}

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    pub what: Sweep,
}

fn executor(name: &str, jobs: usize, dry_run: bool, poll_s: f64) -> Result<Executor> {
    match name {
        "local" => Ok(Executor::Local { jobs }),
        "slurm" => Ok(Executor::Slurm { dry_run, poll_s }),
        other => anyhow::bail!("--executor: expected local or slurm, got '{other}'"),
    }
}

fn plan_text(p: &Plan) -> String {
    let mut t = format!("{} cases of {}\n", p.cases.len(), p.source);
    let _ = write!(t, "{:>4}  {:<12}", "case", "id");
    for f in &p.fields {
        let _ = write!(t, "  {f}");
    }
    let _ = writeln!(t, "  particles  steps  particle-steps");
    let mut total = 0.0;
    for c in &p.cases {
        let _ = write!(t, "{:>4}  {:<12}", c.index, c.id);
        for (_, v) in &c.values {
            let _ = write!(t, "  {v}");
        }
        let _ = writeln!(
            t,
            "  {}  {}  {:.3e}",
            c.cost.particles, c.cost.steps, c.cost.particle_steps
        );
        total += c.cost.particle_steps;
    }
    let _ = writeln!(
        t,
        "total {total:.3e} particle-steps (≈ {:.0} core-s at 1.5e6 particle-steps/s per core)",
        total / 1.5e6
    );
    t
}

pub fn run(a: Args) -> Result<()> {
    let exe = std::env::current_exe()?;
    match a.what {
        Sweep::Plan {
            sweep_file,
            out,
            json,
        } => {
            let p = Plan::from_file(&sweep_file)?;
            p.write(&out)?;
            emit(json, &p, plan_text)
        }
        Sweep::Run {
            sweep_file,
            out,
            executor: e,
            jobs,
            dry_run,
            poll_s,
            json,
        } => {
            let ex = executor(&e, jobs, dry_run, poll_s)?;
            let r = sweep::run(&sweep_file, &out, &ex, &exe)?;
            emit(json, &r, |r| {
                let mut t = String::new();
                if let (true, Some(s)) = (dry_run, &r.slurm_script) {
                    return s.clone();
                }
                if let Some(j) = &r.slurm_job {
                    let _ = writeln!(t, "Slurm job {j}");
                }
                let _ = writeln!(
                    t,
                    "{} of {} cases done ({} already before this run), {} failed",
                    r.done,
                    r.cases,
                    r.skipped,
                    r.failed.len()
                );
                for f in &r.failed {
                    let _ = writeln!(
                        t,
                        "case {} ({}) failed: {}\n{}",
                        f.index, f.id, f.error, f.log_tail
                    );
                }
                t
            })?;
            if r.failed.is_empty() {
                Ok(())
            } else {
                anyhow::bail!("{} case(s) failed; rerun to retry them", r.failed.len())
            }
        }
        Sweep::RunCase { out, index } => {
            sweep::run_case(&out, index)?;
            Ok(())
        }
        Sweep::Collect { out, json } => {
            let c = collect(&out)?;
            emit(json, &c, |c| {
                let mut t = format!("{} of {} cases -> {}\n", c.done, c.cases, c.csv);
                for (i, id, s) in &c.missing {
                    let _ = writeln!(t, "  no result: case {i} ({id}), {s:?}");
                }
                for p in &c.plots {
                    let _ = writeln!(t, "  plot: {p}");
                }
                t
            })
        }
        Sweep::Calibrate {
            sweep_file,
            measured,
            out,
            executor: e,
            jobs,
            poll_s,
            c_min,
            c_max,
            iterations,
            hold_out_every,
            hold_out,
            friction_scale,
            json,
        } => {
            let o = CalibrateOptions {
                sweep_file,
                measured,
                out,
                executor: executor(&e, jobs, false, poll_s)?,
                exe,
                c_range: (c_min, c_max),
                iterations,
                hold_out: if hold_out.is_empty() {
                    HoldOut::Every(hold_out_every)
                } else {
                    HoldOut::List(hold_out)
                },
                friction_scale,
            };
            let r = calibrate(&o)?;
            emit(json, &r, |r| {
                let mut t = format!("C = {:.5}", r.c);
                if let Some(s) = r.friction_scale {
                    let _ = write!(t, ", mu scale = {s:.4}");
                }
                let _ = writeln!(
                    t,
                    "; mean relative force error: training {:.2} %{}",
                    100.0 * r.training_error,
                    r.held_out_error
                        .map(|e| format!(", held out {:.2} %", 100.0 * e))
                        .unwrap_or_default()
                );
                for x in &r.residuals {
                    let _ = writeln!(
                        t,
                        "  {:>3} {:<9} F'c measured {:.1} simulated {:.1} N/mm ({:+.1} %)",
                        x.condition,
                        if x.held_out { "held out" } else { "training" },
                        x.measured_cutting_force_n_per_mm,
                        x.simulated_cutting_force_n_per_mm,
                        100.0 * x.cutting_force_error
                    );
                }
                t
            })
        }
    }
}
