//! `greybox simulate`: the built-in 2D SPH solver — pin sliding and orthogonal cutting.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::settings::cut::CutSettings;
use greybox_pipeline::settings::pin::PinSettings;
use greybox_pipeline::simulate::{run_pin, RunOutput};

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
pub struct PinArgs {
    #[command(flatten)]
    pub settings: PinSettings,
    #[command(flatten)]
    pub output: RunOutput,
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args, Debug)]
pub struct CutArgs {
    #[command(flatten)]
    pub settings: CutSettings,
    #[command(flatten)]
    pub output: RunOutput,
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let (text, out) = match a.what {
        Simulate::Pin(p) => {
            let setup = p.settings.setup()?;
            let r = run_pin(&setup, &p.output)?;
            if p.json {
                return print_json(&r);
            }
            let speed = p.settings.speed_m_per_min;
            (greybox_report::text::pin(&setup, &r, speed), p.output.out)
        }
        Simulate::Cutting(c) => {
            let s = c.settings.run(&c.output)?;
            if c.json {
                return print_json(&s);
            }
            (greybox_report::text::cut(&s), c.output.out)
        }
    };
    print!("{text}");
    println!("wrote {}", out.display());
    Ok(())
}
