//! `greybox bench`: measured speed of the things that must be fast.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::bench;
use std::path::{Path, PathBuf};

#[derive(clap::Subcommand, Debug)]
pub enum Bench {
    /// Ingestion speed of CSV and TDMS recordings (MB/s) on a large synthetic recording.
    Ingest {
        /// Minimum CSV file size, MB.
        #[arg(long = "size-mb", default_value_t = 100.0)]
        size_mb: f64,
        /// Timed repetitions per format (the best and the median are reported).
        #[arg(long, default_value_t = 3)]
        repeats: usize,
        /// Directory for the files (default: a temporary directory, removed afterwards).
        #[arg(long)]
        dir: Option<PathBuf>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Evaluations per second of a law (raw) and of its surrogate table, one core.
    Surrogate {
        /// Law, model or table file.
        #[arg(long)]
        law: PathBuf,
        /// Surrogate grid points per axis (pressure, velocity).
        #[arg(long, default_value_t = 201)]
        points: usize,
        /// Timed evaluations per law.
        #[arg(long, default_value_t = 20_000_000)]
        calls: usize,
    },
    /// SPH solver speed on a cutting set-up (default: the bundled ETH IWF Ti6Al4V case):
    /// particle-steps per second per core and the wall time of the cut.
    Sph {
        #[arg(long, default_value = "examples/iwf-ti64-cut.toml")]
        config: PathBuf,
        /// Fraction of the configured cut to run (the full-cut time is extrapolated if < 1).
        #[arg(long, default_value_t = 1.0)]
        fraction: f64,
        #[arg(long)]
        json: bool,
    },
    /// Single-point prediction latency of model files (the simulator's hot path).
    Predict {
        /// Model files from `greybox fit`.
        #[arg(long, num_args = 1.., required = true)]
        models: Vec<PathBuf>,
        /// Timed calls per model.
        #[arg(long, default_value_t = 200_000)]
        calls: usize,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    pub bench: Bench,
}

fn bench_surrogate(path: &Path, points: usize, calls: usize) -> Result<()> {
    let s = bench::surrogate(path, points, calls)?;
    println!(
        "law:       {:8.1} ns per call, {:.3e} evaluations/s/core ({})",
        s.law_ns_per_call,
        1e9 / s.law_ns_per_call,
        s.law
    );
    println!(
        "surrogate: {:8.1} ns per call, {:.3e} evaluations/s/core ({points} x {points} grid, max deviation {:.2e})",
        s.table_ns_per_call,
        1e9 / s.table_ns_per_call,
        s.max_deviation
    );
    Ok(())
}

fn bench_sph(config: &Path, fraction: f64, json: bool) -> Result<()> {
    let (case, s) = bench::sph(config, fraction)?;
    if json {
        return print_json(&s);
    }
    // A run that stopped at a steady force is complete; otherwise extrapolate the fraction.
    let (full, how) = match s.steady_from_mm {
        Some(mm) if case.setup.steady.stop_when_steady => (
            s.wall_s,
            format!(", stopped at a steady force that set in at {mm:.3} mm"),
        ),
        _ if fraction < 1.0 => (s.wall_s / fraction, ", extrapolated".to_string()),
        _ => (s.wall_s, String::new()),
    };
    println!(
        "SPH cutting benchmark ({}): {} particles, {} steps, dt {:.3e} s, mass scaling {}",
        config.display(),
        s.particles,
        s.steps,
        s.dt_s,
        s.mass_scaling
    );
    println!(
        "  {:.3e} particle-steps/s on {} threads = {:.3e} per core; {:.3} mm of cut in {:.1} s (full run: {:.1} s{how})",
        s.particle_steps_per_s,
        s.threads,
        s.particle_steps_per_s_per_core,
        s.simulated_cut_length_mm,
        s.wall_s,
        full
    );
    if config.ends_with("iwf-ti64-cut.toml") {
        println!(
            "  reference: ETH IWF mfree_iwf-ul-cut-refine ~1.7e5 particle-steps/s/core, 59 min for the cut on one core"
        );
    }
    println!(
        "  cutting force {:.1} N/mm, feed force {:.1} N/mm",
        s.cutting_force_n_per_mm, s.feed_force_n_per_mm
    );
    Ok(())
}

pub fn run(a: Args) -> Result<()> {
    match a.bench {
        Bench::Sph {
            config,
            fraction,
            json,
        } => bench_sph(&config, fraction, json),
        Bench::Surrogate { law, points, calls } => {
            bench_surrogate(&law, points.max(2), calls.max(1))
        }
        Bench::Predict {
            models,
            calls,
            json,
        } => {
            let rows = models
                .iter()
                .map(|m| bench::predict_latency(m, calls.max(1)))
                .collect::<Result<Vec<_>>>()?;
            if json {
                return print_json(&rows);
            }
            for r in &rows {
                println!(
                    "predict {:>18}: {:8.1} ns per point ({} calls, {})",
                    r.family, r.ns_per_call, r.calls, r.model
                );
            }
            Ok(())
        }
        Bench::Ingest {
            size_mb,
            repeats,
            dir,
            json,
        } => {
            let results = bench::ingest(size_mb, repeats, dir)?;
            if json {
                return print_json(&results);
            }
            for r in &results {
                println!(
                    "ingest {:>4}: {:8.1} MB, {} samples x 5 channels: best {:.3} s (median {:.3} s) -> {:7.1} MB/s, {:.2} Msamples/s",
                    r.format, r.file_mb, r.samples, r.best_s, r.median_s, r.best_mb_per_s, r.best_msamples_per_s
                );
            }
            Ok(())
        }
    }
}
