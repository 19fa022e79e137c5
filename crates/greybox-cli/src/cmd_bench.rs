//! `greybox bench`: measured speed of the things that must be fast.

use crate::output::emit;
use anyhow::Result;
use greybox_pipeline::{bench, text};
use std::path::PathBuf;

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

pub fn run(a: Args) -> Result<()> {
    match a.bench {
        Bench::Sph {
            config,
            fraction,
            json,
        } => {
            let (case, s) = bench::sph(&config, fraction)?;
            emit(json, &s, |s| text::sph_bench(&config, fraction, &case, s))
        }
        Bench::Surrogate { law, points, calls } => {
            let s = bench::surrogate(&law, points.max(2), calls.max(1))?;
            emit(false, &s, text::surrogate_speed)
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
            emit(json, &rows, |r| text::predict_latency(r))
        }
        Bench::Ingest {
            size_mb,
            repeats,
            dir,
            json,
        } => emit(json, &bench::ingest(size_mb, repeats, dir)?, |r| {
            text::ingest(r)
        }),
    }
}
