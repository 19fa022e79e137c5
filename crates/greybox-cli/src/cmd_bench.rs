//! `greybox bench`: measured speed of the things that must be fast.

use crate::output::emit;
use anyhow::Result;
use greybox_core::choice::clap_parsers::choice;
use greybox_core::count::Count;
use greybox_friction::export::engine::{AxisPoints, TableSize, DEFAULT_MAX_TABLE_SIZE};
use greybox_friction::table_file::TableKind;
use greybox_pipeline::bench;
use greybox_report::text;
use greybox_sweep::settings::ValidateSettings;
use greybox_sweep::validate;
use std::path::PathBuf;

/// Timed repetitions of a benchmark.
type Repeats = Count<1, 1_000>;
/// Timed calls of a law, a table or a model (a few ns to µs each).
type Calls = Count<1, 10_000_000_000>;

#[derive(clap::Subcommand, Debug)]
pub enum Bench {
    /// Ingestion speed of CSV and TDMS recordings (MB/s) on a large synthetic recording.
    Ingest {
        /// Minimum CSV file size, MB.
        #[arg(long = "size-mb", default_value_t = 100.0)]
        size_mb: f64,
        /// Timed repetitions per format (the best and the median are reported).
        #[arg(long, default_value_t = Repeats::of(3))]
        repeats: Repeats,
        /// Directory for the files (default: a temporary directory, removed afterwards).
        #[arg(long)]
        dir: Option<PathBuf>,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Evaluations per second of a law (raw) and of its surrogate table, one core; the
    /// table's size and max deviation from the law on fresh states.
    Surrogate {
        /// Law, model or table file.
        #[arg(long)]
        law: PathBuf,
        /// Table kind: exact, adaptive or uniform [default: exact for tree ensembles,
        /// adaptive otherwise].
        #[arg(long, value_parser = choice::<TableKind>())]
        kind: Option<TableKind>,
        /// Uniform tables: grid points per axis (pressure, velocity).
        #[arg(long, default_value_t = AxisPoints::of(201))]
        points: AxisPoints,
        /// Adaptive tables: max deviation on the refinement's check set.
        #[arg(long, default_value_t = 1e-4)]
        tolerance: f64,
        /// Most cells (exact) or nodes (adaptive).
        #[arg(long = "max-table-size", default_value_t = DEFAULT_MAX_TABLE_SIZE)]
        max_size: TableSize,
        /// Timed evaluations of the table (the raw law gets a hundredth, at least 10 000).
        #[arg(long, default_value_t = Calls::of(20_000_000))]
        calls: Calls,
        /// Print JSON.
        #[arg(long)]
        json: bool,
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
    /// The validation suite: simulated against measured orthogonal cuts (published
    /// experiments, cited in the data file), one μ per material and tool model calibrated on
    /// at most a third of the conditions, errors reported on the rest (held out).
    Validate {
        #[command(flatten)]
        settings: ValidateSettings,
        #[arg(long)]
        json: bool,
    },
    /// Single-point prediction latency of model files (the simulator's hot path).
    Predict {
        /// Model files from `greybox fit`.
        #[arg(long, num_args = 1.., required = true)]
        models: Vec<PathBuf>,
        /// Timed calls per model.
        #[arg(long, default_value_t = Calls::of(200_000))]
        calls: Calls,
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
        Bench::Surrogate {
            law,
            kind,
            points,
            tolerance,
            max_size,
            calls,
            json,
        } => {
            let o = bench::SurrogateBench {
                kind,
                points: points.get(),
                tolerance,
                max_size: max_size.get(),
                calls: calls.get(),
            };
            emit(json, &bench::surrogate(&law, &o)?, text::surrogate_speed)
        }
        Bench::Predict {
            models,
            calls,
            json,
        } => {
            let rows = models
                .iter()
                .map(|m| bench::predict_latency(m, calls.get()))
                .collect::<Result<Vec<_>>>()?;
            emit(json, &rows, |r| text::predict_latency(r))
        }
        Bench::Validate { settings, json } => {
            let (v, files) = settings.run(&|| Ok(std::env::current_exe()?))?;
            emit(json, &v, |v| {
                let mut t = validate::markdown(v);
                t += &format!(
                    "\nwrote {}\n",
                    files
                        .iter()
                        .map(|f| f.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                t
            })
        }
        Bench::Ingest {
            size_mb,
            repeats,
            dir,
            json,
        } => emit(json, &bench::ingest(size_mb, repeats.get(), dir)?, |r| {
            text::ingest(r)
        }),
    }
}
