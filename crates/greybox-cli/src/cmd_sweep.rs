//! `greybox sweep`: parameter studies on a local process pool or a Slurm cluster.

use crate::output::emit;
use anyhow::Result;
use greybox_report::text::sweep as text;
use greybox_sweep::calibrate::calibrate;
use greybox_sweep::launch::CaseCommand;
use greybox_sweep::settings::{CalibrateSettings, ExecutorSettings};
use greybox_sweep::{self as sweep, collect::collect, Plan};
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
        #[command(flatten)]
        executor: ExecutorSettings,
        /// Slurm: print the array script, submit nothing.
        #[arg(long)]
        dry_run: bool,
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
    /// Find the Johnson–Cook C, or any set-up fields (and optionally a μ scale), that best
    /// match measured forces and chip ratios at several conditions, each iteration a sweep.
    Calibrate {
        sweep_file: PathBuf,
        #[command(flatten)]
        settings: CalibrateSettings,
        #[arg(long)]
        json: bool,
    },
}

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    pub what: Sweep,
}

/// How a case of a sweep starts: this binary, `greybox --quiet sweep run-case OUT --index N`.
fn case_command() -> Result<CaseCommand> {
    Ok(CaseCommand::greybox(std::env::current_exe()?))
}

pub fn run(a: Args) -> Result<()> {
    match a.what {
        Sweep::Plan {
            sweep_file,
            out,
            json,
        } => {
            let p = Plan::from_file(&sweep_file)?;
            p.write(&out)?;
            emit(json, &p, text::plan)
        }
        Sweep::Run {
            sweep_file,
            out,
            executor,
            dry_run,
            json,
        } => {
            let r = sweep::run(
                &sweep_file,
                &out,
                &executor.executor(dry_run)?,
                &case_command()?,
            )?;
            emit(json, &r, |r| text::run(r, dry_run))?;
            match r.failed.len() {
                0 => Ok(()),
                n => anyhow::bail!("{n} case(s) failed; rerun to retry them"),
            }
        }
        Sweep::RunCase { out, index } => sweep::run_case(&out, index).map(|_| ()),
        Sweep::Collect { out, json } => emit(json, &collect(&out)?, text::collected),
        Sweep::Calibrate {
            sweep_file,
            settings,
            json,
        } => emit(
            json,
            &calibrate(&settings.options(sweep_file, case_command()?)?)?,
            text::calibration,
        ),
    }
}
