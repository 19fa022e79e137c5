#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! `greybox`: the command-line shell over the greybox library crates.

mod cmd_adhesive;
mod cmd_bench;
mod cmd_characterize;
mod cmd_couple;
mod cmd_demo;
mod cmd_export;
mod cmd_fit;
mod cmd_hertz;
mod cmd_identify;
mod cmd_import;
mod cmd_law;
mod cmd_material;
mod cmd_plan;
mod cmd_predict;
mod cmd_report;
mod cmd_simulate;
mod cmd_sweep;
mod cmd_synth;
mod cmd_wear;
mod cmd_windows;
mod count_help;
mod export_help;
mod flags;
mod output;
mod stage_flags;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

/// greybox — tribometer measurements to data-driven friction models for cutting simulation.
#[derive(Parser)]
#[command(name = "greybox", version, about, long_about = None, propagate_version = true)]
struct Cli {
    /// No progress display (bars on a terminal, status lines otherwise, all on stderr).
    #[arg(long, short = 'q', global = true, help_heading = "Global options")]
    quiet: bool,
    #[command(flatten)]
    budget: BudgetArgs,
    #[command(subcommand)]
    command: Command,
}

/// The caps of the readers (greybox_core::budget): inputs beyond them are refused with the
/// cap named, before the memory or time they would take is spent. Every command takes them;
/// they are listed once, in `greybox --help` ([`budget_help`]), not in each command's help.
#[derive(clap::Args)]
struct BudgetArgs {
    /// Largest configuration file (set-up TOML, sweep file, base configuration) read, MiB.
    #[arg(long = "max-input-mib", global = true, hide = true, default_value_t = greybox_core::budget::DEFAULT.max_input_bytes >> 20)]
    max_input_mib: u64,
    /// Most elements of a UBJSON typed array of null/true/false (which take no bytes each).
    #[arg(long = "max-array-len", global = true, hide = true, default_value_t = greybox_core::budget::DEFAULT.max_array_len)]
    max_array_len: u64,
    /// Most cells of one spreadsheet sheet (declared, held in memory, shared strings).
    #[arg(long = "max-sheet-cells", global = true, hide = true, default_value_t = greybox_core::budget::DEFAULT.max_sheet_cells)]
    max_sheet_cells: u64,
    /// Most bytes a spreadsheet archive expands to, MiB.
    #[arg(long = "max-uncompressed-mib", global = true, hide = true, default_value_t = greybox_core::budget::DEFAULT.max_uncompressed_bytes >> 20)]
    max_uncompressed_mib: u64,
    /// Longest line in the head of a text recording, KiB.
    #[arg(long = "max-line-kib", global = true, hide = true, default_value_t = greybox_core::budget::DEFAULT.max_line_bytes >> 10)]
    max_line_kib: u64,
    /// Largest recording file (text, spreadsheet, TDMS) read, MiB.
    #[arg(long = "max-recording-mib", global = true, hide = true, default_value_t = greybox_core::budget::DEFAULT.max_recording_bytes >> 20)]
    max_recording_mib: u64,
    /// Largest data, model or state file read (training data, track widths, points, models, laws, decks, sweep plans, checkpoints), MiB.
    #[arg(long = "max-data-mib", global = true, hide = true, default_value_t = greybox_core::budget::DEFAULT.max_data_bytes >> 20)]
    max_data_mib: u64,
}

/// The caps as one section of `greybox --help`: each flag, its default and what it bounds.
fn budget_help() -> String {
    use clap::Args;
    let caps = BudgetArgs::augment_args(clap::Command::new("budget"));
    let mut out = String::from(
        "Input budgets (every command; an input beyond a cap is refused, naming it):\n",
    );
    for a in caps.get_arguments() {
        let default = a
            .get_default_values()
            .first()
            .map(|v| v.to_string_lossy().into_owned());
        out.push_str(&format!(
            "  --{} <{}>\n          {}\n",
            a.get_long().unwrap_or_default(),
            default.unwrap_or_default(),
            a.get_help().map(|h| h.to_string()).unwrap_or_default()
        ));
    }
    out
}

impl BudgetArgs {
    fn install(&self) {
        greybox_core::budget::set(greybox_core::budget::Budget {
            max_input_bytes: self.max_input_mib.saturating_mul(1 << 20),
            max_array_len: self.max_array_len,
            max_sheet_cells: self.max_sheet_cells,
            max_uncompressed_bytes: self.max_uncompressed_mib.saturating_mul(1 << 20),
            max_line_bytes: self.max_line_kib.saturating_mul(1 << 10),
            max_recording_bytes: self.max_recording_mib.saturating_mul(1 << 20),
            max_data_bytes: self.max_data_mib.saturating_mul(1 << 20),
        });
    }
}

#[derive(Subcommand)]
enum Command {
    /// Plan a pin-on-disk campaign: run sheet CSV and one ISO lathe program per pin.
    Plan(cmd_plan::Args),
    /// Virtual tribometer: raw recordings (CSV and/or TDMS) and the ground truth of a plan.
    Synth(cmd_synth::Args),
    /// Identify apparent friction coefficients per plateau from raw recordings.
    Identify(cmd_identify::Args),
    /// Hertzian contact: contact size, maximum and mean pressure, approach.
    Hertz(cmd_hertz::Args),
    /// Ploughing correction: adhesive COF from the apparent COF and measured track widths.
    Adhesive(cmd_adhesive::Args),
    /// Export a friction law as Abaqus/DEFORM/LS-DYNA tables, CSV, or a surrogate table.
    Export(cmd_export::Args),
    /// Train and compare regressors (RF, SVR, boosting, MLP) with nested CV, CIs, importance.
    Fit(cmd_fit::Args),
    /// Grey-box friction law around a fitted model (power law outside its domain, clamp, shear cap).
    Law(cmd_law::Args),
    /// Import a model trained elsewhere (XGBoost JSON/UBJSON, ONNX, scikit-learn via greybox.export_sklearn).
    Import(cmd_import::Args),
    /// Evaluate a model file at points, with prediction intervals and a domain check.
    Predict(cmd_predict::Args),
    /// Rig dynamics from impact-hammer tests (FRF, resonances) and the check against the plan.
    Characterize(cmd_characterize::Args),
    /// Archard wear rates from volumes, height maps or scar geometry.
    Wear(cmd_wear::Args),
    /// Friction windows from a coated tool mesh (Gmsh/Abaqus) → JSON, CSV, DEFORM FRCWIN, VTK.
    Windows(cmd_windows::Args),
    /// Restart loop with an external FE engine (CalculiX, or a user command): per-window μ from the law.
    Couple(cmd_couple::Args),
    /// Built-in 2D SPH solver: pin sliding (ploughing share) and orthogonal cutting.
    Simulate(cmd_simulate::Args),
    /// Parameter sweeps on a local process pool or a Slurm cluster; collect; calibrate J-C C across conditions.
    Sweep(cmd_sweep::Args),
    /// Johnson-Cook parameters: fit to flow curves; C from a measured cutting force.
    Material(cmd_material::Args),
    /// Run the whole pipeline on the bundled example study.
    Demo(cmd_demo::Args),
    /// One self-contained HTML page for a study directory: campaign, friction data, models, cuts with chip pictures, rig, provenance.
    Report(cmd_report::Args),
    /// Benchmarks: ingestion, prediction latency, surrogate tables, SPH solver speed.
    Bench(cmd_bench::Args),
}

fn main() {
    // The main thread joins rayon's global pool as worker 0, so that every parallel pass of
    // the solver starts on a worker instead of being handed across threads (the hand-off
    // was ≈ 7 % of a solver step on one thread). Besides the signal watcher (which only
    // waits), greybox starts no other threads; code that
    // did (or a `rayon::spawn` waited on outside the pool) could hang with
    // RAYON_NUM_THREADS=1, where the main thread is the whole pool.
    if let Err(e) = rayon::ThreadPoolBuilder::new()
        .use_current_thread()
        .build_global()
    {
        eprintln!("warning: rayon thread pool: {e}");
    }
    greybox_pipeline::output::remove_temporaries_on_interrupt();
    let command =
        count_help::state_count_ranges(export_help::state_export_defaults(Cli::command()))
            .after_help(budget_help());
    let matches = command.clone().get_matches();
    flags::Flags::of(&command, &matches).install();
    // values outside their usual range, said once each, with the settings shown as flags
    greybox_core::notes::install(|text| eprintln!("warning: {}", flags::shown(text)));
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    greybox_report::progress_display::Mode::choose(cli.quiet).install();
    cli.budget.install();
    simd_cap_from_env();
    let result = match cli.command {
        Command::Plan(a) => cmd_plan::run(a),
        Command::Synth(a) => cmd_synth::run(a),
        Command::Identify(a) => cmd_identify::run(a),
        Command::Hertz(a) => cmd_hertz::run(a),
        Command::Fit(a) => cmd_fit::run(a),
        Command::Adhesive(a) => cmd_adhesive::run(a),
        Command::Export(a) => cmd_export::run(a),
        Command::Predict(a) => cmd_predict::run(a),
        Command::Import(a) => cmd_import::run(a),
        Command::Law(a) => cmd_law::run(a),
        Command::Simulate(a) => cmd_simulate::run(a),
        Command::Sweep(a) => cmd_sweep::run(a),
        Command::Material(a) => cmd_material::run(a),
        Command::Demo(a) => cmd_demo::run(a),
        Command::Report(a) => cmd_report::run(a),
        Command::Characterize(a) => cmd_characterize::run(a),
        Command::Wear(a) => cmd_wear::run(a),
        Command::Windows(a) => cmd_windows::run(a),
        Command::Couple(a) => cmd_couple::run(a),
        Command::Bench(a) => cmd_bench::run(a),
    };
    if let Err(e) = result {
        eprintln!("error: {}", flags::shown_error(&e));
        std::process::exit(1);
    }
}

/// The solver's SIMD path capped by `GREYBOX_SIMD` (the library reads no environment).
fn simd_cap_from_env() {
    let value = std::env::var(greybox_sim::cpu::SIMD_ENV).ok();
    if let Err(warning) = greybox_sim::cpu::apply_cap(value.as_deref()) {
        eprintln!("{warning}");
    }
}
