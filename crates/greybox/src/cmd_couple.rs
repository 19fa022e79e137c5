//! `greybox couple`: the restart loop with an external FE engine.

use crate::output::print_json;
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::plot::{lines, Line};
use greybox_couple::calculix::{CalculixConfig, CalculixEngine};
use greybox_couple::engine::{couple, CommandEngine, CouplingResult, Engine};
use greybox_friction::spec::load_law;
use std::path::{Path, PathBuf};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum EngineArg {
    /// CalculiX (ccx) with *RESTART and *CHANGE FRICTION.
    Calculix,
    /// A user command per segment (friction.csv in, states.csv out).
    Command,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Write the bundled example (model.inp, segment.inp, law.json) into this directory and stop.
    #[arg(long)]
    pub example: Option<PathBuf>,
    /// Friction windows in the example.
    #[arg(long, default_value_t = 5)]
    pub example_windows: usize,
    #[arg(long, value_enum, default_value_t = EngineArg::Calculix)]
    pub engine: EngineArg,
    /// CalculiX deck: model, contact pairs per window, first segment (with *RESTART,WRITE).
    #[arg(long)]
    pub deck: Option<PathBuf>,
    /// CalculiX segment-step template containing {{FRICTION}}.
    #[arg(long)]
    pub segment: Option<PathBuf>,
    /// The ccx binary.
    #[arg(long, default_value = "ccx")]
    pub ccx: PathBuf,
    /// Command template for --engine command ({cycle}, {dir}, {prev_dir}).
    #[arg(long)]
    pub command: Option<String>,
    /// Window names for --engine command, comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub windows: Vec<String>,
    /// Friction law (law file, model file or table).
    #[arg(long)]
    pub law: Option<PathBuf>,
    /// Work directory (one sub-directory per cycle).
    #[arg(long, default_value = "couple-out")]
    pub work: PathBuf,
    #[arg(long, default_value_t = 20)]
    pub max_cycles: usize,
    /// Converged when every window's μ changes less than this.
    #[arg(long, default_value_t = 1e-3)]
    pub tol: f64,
    /// Deck stress unit: MPa or Pa.
    #[arg(long, default_value = "MPa")]
    pub pressure_unit: String,
    /// Deck length unit: mm or m.
    #[arg(long, default_value = "mm")]
    pub length_unit: String,
    /// Physical duration of one segment, s (slip per segment / duration = sliding velocity).
    #[arg(long = "segment-s", default_value_t = 1e-3)]
    pub segment_s: f64,
    #[arg(long)]
    pub json: bool,
}

/// Plot μ per window over the cycles.
fn plot_history(path: &Path, r: &CouplingResult) -> Result<()> {
    let names: Vec<String> = r.final_mu.iter().map(|m| m.0.clone()).collect();
    let colours = [
        "#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#7f7f7f",
    ];
    let series: Vec<(Vec<f64>, Vec<f64>)> = names
        .iter()
        .map(|n| {
            let rows: Vec<_> = r.history.iter().filter(|h| &h.window == n).collect();
            (
                rows.iter().map(|h| h.cycle as f64).collect(),
                rows.iter().map(|h| h.mu_new).collect(),
            )
        })
        .collect();
    let ls: Vec<Line> = names
        .iter()
        .zip(&series)
        .enumerate()
        .map(|(i, (n, (x, y)))| Line {
            label: n,
            colour: colours[i % 8],
            x,
            y,
        })
        .collect();
    write_string_atomic(
        path,
        &lines(
            "friction windows: μ from the law per cycle",
            "cycle",
            "μ",
            &ls,
            false,
            &[],
        ),
    )?;
    Ok(())
}

pub fn run(a: Args) -> Result<()> {
    if let Some(dir) = &a.example {
        greybox_couple::example::write_example(dir, a.example_windows)?;
        println!(
            "wrote {0}/model.inp, {0}/segment.inp and {0}/law.json; run:\n  greybox couple --deck {0}/model.inp --segment {0}/segment.inp --law {0}/law.json --work {0}/run",
            dir.display()
        );
        return Ok(());
    }
    let law_path = a.law.as_ref().context("--law is required")?;
    let law = load_law(law_path)?;
    let pressure = match a.pressure_unit.as_str() {
        "MPa" => 1e6,
        "Pa" => 1.0,
        o => bail!("unknown pressure unit '{o}'; expected MPa or Pa"),
    };
    let length = match a.length_unit.as_str() {
        "mm" => 1e-3,
        "m" => 1.0,
        o => bail!("unknown length unit '{o}'; expected mm or m"),
    };
    let mut engine: Box<dyn Engine> = match a.engine {
        EngineArg::Calculix => Box::new(CalculixEngine::new(CalculixConfig {
            ccx: a.ccx.clone(),
            deck: a
                .deck
                .clone()
                .context("--deck is required for --engine calculix")?,
            segment_template: a
                .segment
                .clone()
                .context("--segment is required for --engine calculix")?,
            work: a.work.clone(),
            pressure_pa_per_unit: pressure,
            length_m_per_unit: length,
            segment_s: a.segment_s,
        })?),
        EngineArg::Command => {
            if a.windows.is_empty() {
                bail!("--engine command needs --windows");
            }
            Box::new(CommandEngine {
                windows: a.windows.clone(),
                command: a
                    .command
                    .clone()
                    .context("--command is required for --engine command")?,
                work: a.work.clone(),
            })
        }
    };
    let r = couple(
        engine.as_mut(),
        law.as_ref(),
        a.max_cycles,
        a.tol,
        Some(&a.work.join("history.csv")),
    )?;
    plot_history(&a.work.join("mu_history.svg"), &r)?;
    if a.json {
        return print_json(&r);
    }
    println!(
        "{} after {} cycles (tolerance {})",
        if r.converged {
            "converged"
        } else {
            "NOT converged"
        },
        r.cycles,
        a.tol
    );
    for ((name, mu), h) in r
        .final_mu
        .iter()
        .zip(r.history.iter().filter(|h| h.cycle == r.cycles))
    {
        println!(
            "  {name}: p = {:.2} MPa, v = {:.3} m/min, mu = {:.4} (engine applied {:.4})",
            h.pressure_mpa, h.velocity_m_per_min, mu, h.shear_ratio
        );
    }
    println!(
        "history: {}, plot: {}",
        a.work.join("history.csv").display(),
        a.work.join("mu_history.svg").display()
    );
    Ok(())
}
