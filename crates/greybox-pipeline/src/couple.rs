//! The restart loop with an external FE engine (CalculiX, or a user command): per-window μ
//! from the law, re-evaluated from the engine's contact states until it settles.

use anyhow::Result;
use greybox_core::atomic::write_string_atomic;
use greybox_core::plot::{lines, Line};
use greybox_couple::calculix::{CalculixConfig, CalculixEngine};
use greybox_couple::engine::{couple as restart_loop, CommandEngine, CouplingResult, Engine};
use greybox_friction::spec::load_law;
use std::path::{Path, PathBuf};

/// The engine run per segment.
#[derive(Debug, Clone)]
pub enum EngineOptions {
    /// CalculiX (ccx) with *RESTART and *CHANGE FRICTION.
    Calculix {
        /// The ccx binary.
        ccx: PathBuf,
        /// Model, contact pairs per window, first segment (with *RESTART,WRITE).
        deck: PathBuf,
        /// Segment-step template containing {{FRICTION}}.
        segment: PathBuf,
        /// Deck stress unit, Pa per unit (MPa decks: 1e6).
        pressure_pa_per_unit: f64,
        /// Deck length unit, m per unit (mm decks: 1e-3).
        length_m_per_unit: f64,
        /// Physical duration of one segment, s (slip per segment / duration = sliding velocity).
        segment_s: f64,
    },
    /// A user command per segment (friction.csv in, states.csv out).
    Command {
        /// Command template ({cycle}, {dir}, {prev_dir}).
        command: String,
        /// Window names.
        windows: Vec<String>,
    },
}

/// Options of [`couple`].
#[derive(Debug, Clone)]
pub struct CoupleOptions {
    pub engine: EngineOptions,
    /// Friction law (law file, model file or table).
    pub law: PathBuf,
    /// Work directory (one sub-directory per cycle; history.csv and mu_history.svg).
    pub work: PathBuf,
    pub max_cycles: usize,
    /// Converged when every window's μ changes less than this.
    pub tol: f64,
}

/// Run the restart loop; writes `history.csv` and `mu_history.svg` into the work directory.
pub fn couple(o: &CoupleOptions) -> Result<CouplingResult> {
    let law = load_law(&o.law)?;
    let mut engine: Box<dyn Engine> = match &o.engine {
        EngineOptions::Calculix {
            ccx,
            deck,
            segment,
            pressure_pa_per_unit,
            length_m_per_unit,
            segment_s,
        } => Box::new(CalculixEngine::new(CalculixConfig {
            ccx: ccx.clone(),
            deck: deck.clone(),
            segment_template: segment.clone(),
            work: o.work.clone(),
            pressure_pa_per_unit: *pressure_pa_per_unit,
            length_m_per_unit: *length_m_per_unit,
            segment_s: *segment_s,
        })?),
        EngineOptions::Command { command, windows } => {
            if windows.is_empty() {
                let why = "a user command needs the friction windows";
                return Err(greybox_core::setting::refused("couple", "windows", why).into());
            }
            for w in windows {
                let pos = greybox_core::SourcePos::file("couple").field("windows");
                greybox_core::escape::check_name(pos, w)?;
            }
            Box::new(CommandEngine {
                windows: windows.clone(),
                command: command.clone(),
                work: o.work.clone(),
            })
        }
    };
    let r = restart_loop(
        engine.as_mut(),
        law.as_ref(),
        o.max_cycles,
        o.tol,
        Some(&o.work.join("history.csv")),
    )?;
    plot_history(&o.work.join("mu_history.svg"), &r)?;
    Ok(r)
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
            "cycle (-)",
            "μ (-)",
            &ls,
            false,
            &[],
        ),
    )?;
    Ok(())
}
