//! `greybox couple`: the restart loop with an external FE engine.

use crate::output::print_json;
use anyhow::{Context, Result};
use greybox_pipeline::couple::{couple, m_per_unit, pa_per_unit, CoupleOptions, EngineOptions};
use std::path::PathBuf;

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

impl Args {
    /// The library's options for these flags.
    pub fn options(&self) -> Result<CoupleOptions> {
        let engine = match self.engine {
            EngineArg::Calculix => EngineOptions::Calculix {
                ccx: self.ccx.clone(),
                deck: self
                    .deck
                    .clone()
                    .context("--deck is required for --engine calculix")?,
                segment: self
                    .segment
                    .clone()
                    .context("--segment is required for --engine calculix")?,
                pressure_pa_per_unit: pa_per_unit(&self.pressure_unit)?,
                length_m_per_unit: m_per_unit(&self.length_unit)?,
                segment_s: self.segment_s,
            },
            EngineArg::Command => EngineOptions::Command {
                command: self
                    .command
                    .clone()
                    .context("--command is required for --engine command")?,
                windows: self.windows.clone(),
            },
        };
        Ok(CoupleOptions {
            engine,
            law: self.law.clone().context("--law is required")?,
            work: self.work.clone(),
            max_cycles: self.max_cycles,
            tol: self.tol,
        })
    }
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
    let r = couple(&a.options()?)?;
    if a.json {
        return print_json(&r);
    }
    print!("{}", greybox_pipeline::text::coupling(&r, a.tol, &a.work));
    Ok(())
}
