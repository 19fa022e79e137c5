//! `greybox simulate`: the built-in 2D SPH solver — pin sliding and orthogonal cutting.

use crate::output::print_json;
use anyhow::{Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_sim::checkpoint::{Checkpoint, Checkpointer};
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::output::{write_windows_csv, ForceHistory, VtkSeries};
use greybox_sim::pin::{fingerprint, simulate_from, PinSetup};
use greybox_sim::{Observer, Solver};
use std::path::{Path, PathBuf};

#[derive(clap::Subcommand, Debug)]
pub enum Simulate {
    /// Press a rigid pin (circle) into a Johnson–Cook workpiece and slide it (plane strain).
    Pin(PinArgs),
    /// Orthogonal cut from a TOML set-up (see examples/iwf-ti64-cut.toml).
    Cutting(CutArgs),
}

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(subcommand)]
    pub what: Simulate,
}

#[derive(clap::Args, Debug)]
pub struct Output {
    /// Output directory.
    #[arg(long, default_value = "sim-out")]
    pub out: PathBuf,
    /// Write VTK particle files every N steps (0: first and last only).
    #[arg(long = "vtk-every", default_value_t = 0)]
    pub vtk_every: u64,
    /// Write a checkpoint every N steps (0: none).
    #[arg(long = "checkpoint-every", default_value_t = 0)]
    pub checkpoint_every: u64,
    /// Resume from a checkpoint written by the same set-up.
    #[arg(long)]
    pub resume: Option<PathBuf>,
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args, Debug)]
pub struct PinArgs {
    /// Indentation depth, µm (or give --track-width-um).
    #[arg(long = "depth-um")]
    pub depth_um: Option<f64>,
    /// Measured track width, µm: depth d = r − √(r² − (w/2)²).
    #[arg(long = "track-width-um")]
    pub track_width_um: Option<f64>,
    #[arg(long = "pin-radius-mm", default_value_t = 17.0)]
    pub pin_radius_mm: f64,
    /// Coulomb μ on the pin.
    #[arg(long, default_value_t = 0.3)]
    pub mu: f64,
    /// Particle spacing, µm.
    #[arg(long = "spacing-um", default_value_t = 10.0)]
    pub spacing_um: f64,
    /// Slide length after pressing, mm.
    #[arg(long = "slide-mm", default_value_t = 1.0)]
    pub slide_mm: f64,
    /// Workpiece height, mm.
    #[arg(long = "height-mm", default_value_t = 0.5)]
    pub height_mm: f64,
    /// Physical sliding speed (sets the J-C strain rate), m/min.
    #[arg(long = "speed-m-per-min", default_value_t = 150.0)]
    pub speed_m_per_min: f64,
    /// Simulated sliding speed / elastic wave speed (time scaling of the quasi-static slide).
    #[arg(long, default_value_t = 0.01)]
    pub mach: f64,
    /// Mass scaling factor (≥ 1).
    #[arg(long = "mass-scaling", default_value_t = 1.0)]
    pub mass_scaling: f64,
    #[command(flatten)]
    pub output: Output,
}

#[derive(clap::Args, Debug)]
pub struct CutArgs {
    /// Set-up TOML (a serialised CuttingSetup).
    #[arg(long)]
    pub config: PathBuf,
    /// Simulate this fraction of the configured cut length.
    #[arg(long, default_value_t = 1.0)]
    pub fraction: f64,
    #[command(flatten)]
    pub output: Output,
}

impl PinArgs {
    pub fn setup(&self) -> Result<PinSetup> {
        let r = self.pin_radius_mm * 1e-3;
        let depth = match (self.depth_um, self.track_width_um) {
            (Some(d), None) => d * 1e-6,
            (None, Some(w)) => greybox_tribo::ploughing::track_depth(r, w * 1e-6)?,
            _ => anyhow::bail!("give exactly one of --depth-um and --track-width-um"),
        };
        let mut s = PinSetup::article(depth, self.mu, self.spacing_um * 1e-6);
        s.pin_radius_m = r;
        s.slide_length_m = self.slide_mm * 1e-3;
        s.workpiece_height_m = self.height_mm * 1e-3;
        s.sliding_speed_m_s = self.speed_m_per_min / 60.0;
        s.mach = self.mach;
        s.numerics.mass_scaling = self.mass_scaling;
        s.validate()?;
        Ok(s)
    }
}

/// Output observers shared by pin and cutting runs.
struct Observers {
    vtk: VtkSeries,
    ckpt: Option<Checkpointer>,
}

impl Observers {
    fn new(o: &Output, setup_id: &str) -> Self {
        Observers {
            vtk: VtkSeries::new(
                &o.out.join("vtk"),
                if o.vtk_every == 0 {
                    u64::MAX
                } else {
                    o.vtk_every
                },
            ),
            ckpt: (o.checkpoint_every > 0).then(|| {
                Checkpointer::new(&o.out.join("checkpoint.json"), o.checkpoint_every, setup_id)
            }),
        }
    }
    fn list(&mut self) -> Vec<&mut dyn Observer> {
        let mut v: Vec<&mut dyn Observer> = vec![&mut self.vtk];
        if let Some(c) = self.ckpt.as_mut() {
            v.push(c);
        }
        v
    }
}

fn read_checkpoint(p: &Option<PathBuf>) -> Result<Option<Checkpoint>> {
    p.as_ref().map(|p| Ok(Checkpoint::read(p)?)).transpose()
}

/// Adds the files a failed run left behind to the error.
fn failure_context(e: greybox_sim::SimError, obs: &Observers) -> anyhow::Error {
    let mut files: Vec<String> = obs
        .vtk
        .written
        .iter()
        .filter(|p| p.to_string_lossy().contains("last_good"))
        .map(|p| p.display().to_string())
        .collect();
    if let Some(p) = obs.ckpt.as_ref().and_then(|c| c.failure_path.as_ref()) {
        files.push(p.display().to_string());
    }
    if files.is_empty() {
        anyhow::anyhow!(e)
    } else {
        anyhow::anyhow!("{e}\nlast good state written to: {}", files.join(", "))
    }
}

fn write_common(
    out: &Path,
    sim: &Solver,
    hist: &ForceHistory,
    summary: &impl serde::Serialize,
) -> Result<()> {
    hist.write_csv(&out.join("forces.csv"))?;
    for (k, t) in sim.tools.iter().enumerate() {
        write_windows_csv(
            &out.join(format!("windows_tool{k}.csv")),
            t,
            sim.particles.spacing,
        )?;
    }
    write_string_atomic(
        &out.join("summary.json"),
        &serde_json::to_string_pretty(summary)?,
    )?;
    Ok(())
}

fn run_pin(a: &PinArgs) -> Result<()> {
    let setup = a.setup()?;
    let mut obs = Observers::new(&a.output, &fingerprint(&setup));
    let resume = read_checkpoint(&a.output.resume)?;
    let (res, hist, sim) =
        simulate_from(&setup, resume, &mut obs.list()).map_err(|e| failure_context(e, &obs))?;
    write_common(&a.output.out, &sim, &hist, &res)?;
    if a.output.json {
        return print_json(&res);
    }
    println!(
        "pin r = {} mm, depth {:.2} µm, μ = {}: F_t/F_N = {:.4} (deformation share {:.4}; analytic cylinder tan(θ/2) = {:.4})",
        setup.pin_radius_m * 1e3,
        setup.depth_m * 1e6,
        setup.mu,
        res.force_ratio,
        res.deformation_share,
        res.analytic_share
    );
    println!(
        "  F_N = {:.1} N/mm, F_t = {:.1} N/mm; {} particles, {} steps, {:.1} s wall ({:.2e} particle-steps/s), energy residual {:.2} %",
        res.normal_force_n_per_mm, res.tangential_force_n_per_mm, res.particles, res.steps, res.wall_s, res.particle_steps_per_s, 100.0 * res.energy_error
    );
    println!(
        "  simulated slide speed {:.1} m/s (strain rate scaled to {} m/min), mass scaling {}",
        res.simulated_speed_m_s, a.speed_m_per_min, res.mass_scaling
    );
    println!("wrote {}", a.output.out.display());
    Ok(())
}

/// Reads a cutting set-up TOML.
pub fn read_cutting_setup(path: &Path) -> Result<CuttingSetup> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let s: CuttingSetup = toml::from_str(&text)
        .with_context(|| format!("{}: not a cutting set-up", path.display()))?;
    s.validate().with_context(|| path.display().to_string())?;
    Ok(s)
}

#[derive(serde::Serialize)]
pub struct CutSummary {
    pub particles: usize,
    pub steps: u64,
    pub dt_s: f64,
    pub simulated_cut_length_mm: f64,
    pub wall_s: f64,
    pub particle_steps_per_s: f64,
    pub particle_steps_per_s_per_core: f64,
    pub threads: usize,
    /// Mean cutting and feed force over the last half of the run, N/mm.
    pub cutting_force_n_per_mm: f64,
    pub feed_force_n_per_mm: f64,
    pub mass_scaling: f64,
    pub energy_error: f64,
}

/// Runs a cut; returns the summary.
pub fn run_cut(setup: &CuttingSetup, fraction: f64, o: &Output) -> Result<CutSummary> {
    if !(fraction > 0.0 && fraction <= 1.0) {
        anyhow::bail!("--fraction: expected a number in (0, 1], got {fraction}");
    }
    let (model, duration) = setup.model()?;
    let mut sim = Solver::new(model)?;
    let id = serde_json::to_string(setup)?;
    if let Some(c) = read_checkpoint(&o.resume)? {
        c.restore(&mut sim, &id)?;
    }
    let end = duration * fraction.clamp(0.0, 1.0);
    let mut hist = ForceHistory::new(0, ((end / sim.dt) / 500.0).ceil().max(1.0) as u64);
    let mut obs = Observers::new(o, &id);
    let summary = {
        let mut list = obs.list();
        list.push(&mut hist);
        greybox_sim::run(&mut sim, end, &mut list)
    }
    .map_err(|e| failure_context(e, &obs))?;
    let f = hist.mean_force(0.5 * end, end).unwrap_or([0.0, 0.0]);
    let threads = greybox_sim::threads();
    let s = CutSummary {
        particles: sim.particle_count(),
        steps: summary.steps,
        dt_s: sim.dt,
        simulated_cut_length_mm: (end * setup.cutting_speed_m_s) * 1e3,
        wall_s: summary.wall_s,
        particle_steps_per_s: summary.particle_steps_per_s,
        particle_steps_per_s_per_core: summary.particle_steps_per_s / threads as f64,
        threads,
        cutting_force_n_per_mm: f[0] * 1e-3,
        feed_force_n_per_mm: f[1] * 1e-3,
        mass_scaling: sim.numerics.mass_scaling,
        energy_error: sim.energy_balance().relative_error,
    };
    write_common(&o.out, &sim, &hist, &s)?;
    Ok(s)
}

pub fn run(a: Args) -> Result<()> {
    match a.what {
        Simulate::Pin(p) => run_pin(&p),
        Simulate::Cutting(c) => {
            let setup = read_cutting_setup(&c.config)?;
            let s = run_cut(&setup, c.fraction, &c.output)?;
            if c.output.json {
                return print_json(&s);
            }
            println!(
                "{} particles, {} steps (dt {:.3e} s), {:.3} mm of cut in {:.1} s: {:.3e} particle-steps/s ({:.3e} per core, {} threads)",
                s.particles, s.steps, s.dt_s, s.simulated_cut_length_mm, s.wall_s, s.particle_steps_per_s, s.particle_steps_per_s_per_core, s.threads
            );
            println!(
                "  cutting force {:.1} N/mm, feed force {:.1} N/mm (mean over the second half)",
                s.cutting_force_n_per_mm, s.feed_force_n_per_mm
            );
            println!("wrote {}", c.output.out.display());
            Ok(())
        }
    }
}
