//! `greybox simulate`: the built-in 2D SPH solver — pin sliding and orthogonal cutting.

use crate::output::print_json;
use anyhow::Result;
use greybox_core::units::{m_per_min_to_m_per_s, mm_to_m, um_to_m};
use greybox_pipeline::simulate::{read_cutting_setup, run_cut, run_pin, Indentation, RunOutput};
use greybox_sim::pin::PinSetup;
use std::path::PathBuf;

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
    /// Resume an interrupted run from its checkpoint (`OUT.partial/checkpoint.json`: a run
    /// with checkpoints works in OUT.partial until it is complete, then becomes OUT). The
    /// resumed run's outputs equal those of an uninterrupted one.
    #[arg(long)]
    pub resume: Option<PathBuf>,
    /// Replace an existing, non-empty output directory (or a left-over OUT.partial) whole.
    #[arg(long)]
    pub force: bool,
    /// Cuts: also draw the chip at N evenly spaced instants (frames/chip_NNN.svg, shown as
    /// a strip and a slider by `greybox report`); the last state is always drawn.
    #[arg(long, default_value_t = 0)]
    pub frames: usize,
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
    #[arg(long = "slide-mm", default_value_t = 1.5)]
    pub slide_mm: f64,
    /// Workpiece height, mm (the article's FE model: 1 mm).
    #[arg(long = "height-mm", default_value_t = 1.0)]
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
    /// Most particles the workpiece may have (numerics.max_particles; default 5 million,
    /// about 20 GB): a finer --spacing-um is refused before anything is allocated.
    #[arg(long = "max-particles")]
    pub max_particles: Option<u64>,
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
        let r = mm_to_m(self.pin_radius_mm);
        let depth = match (self.depth_um, self.track_width_um) {
            (Some(d), None) => Indentation::Depth(um_to_m(d)),
            (None, Some(w)) => Indentation::TrackWidth(um_to_m(w)),
            _ => anyhow::bail!("give exactly one of --depth-um and --track-width-um"),
        }
        .depth_m(r)?;
        let mut s = PinSetup::article(depth, self.mu, um_to_m(self.spacing_um));
        s.pin_radius_m = r;
        s.slide_length_m = mm_to_m(self.slide_mm);
        s.workpiece_height_m = mm_to_m(self.height_mm);
        s.sliding_speed_m_s = m_per_min_to_m_per_s(self.speed_m_per_min);
        s.mach = self.mach;
        s.numerics.mass_scaling = self.mass_scaling;
        s.numerics.max_particles = self.max_particles;
        s.validate()?;
        Ok(s)
    }
}

impl Output {
    /// The library's output options for these flags.
    pub fn options(&self) -> RunOutput {
        RunOutput {
            out: self.out.clone(),
            vtk_every: self.vtk_every,
            checkpoint_every: self.checkpoint_every,
            resume: self.resume.clone(),
            force: self.force,
            frames: self.frames,
        }
    }
}

fn pin(a: &PinArgs) -> Result<()> {
    let setup = a.setup()?;
    let res = run_pin(&setup, &a.output.options())?;
    if a.output.json {
        return print_json(&res);
    }
    print!(
        "{}",
        greybox_pipeline::text::pin(&setup, &res, a.speed_m_per_min)
    );
    println!("wrote {}", a.output.out.display());
    Ok(())
}

pub fn run(a: Args) -> Result<()> {
    match a.what {
        Simulate::Pin(p) => pin(&p),
        Simulate::Cutting(c) => {
            let case = read_cutting_setup(&c.config)?;
            let s = run_cut(&case, c.fraction, &c.output.options())?;
            if c.output.json {
                return print_json(&s);
            }
            print!("{}", greybox_pipeline::text::cut(&s));
            println!("wrote {}", c.output.out.display());
            Ok(())
        }
    }
}
