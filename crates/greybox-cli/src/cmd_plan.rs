//! `greybox plan`.

use crate::output::print_json;
use anyhow::Result;
use greybox_pipeline::plan::plan;
use greybox_pipeline::study::Study;
use std::path::{Path, PathBuf};

/// Plan overrides shared by commands that build a plan.
#[derive(clap::Args, Debug, Default, Clone)]
pub struct PlanFlags {
    /// Study TOML ([plan], [contact], …); flags override it.
    #[arg(long)]
    pub study: Option<PathBuf>,
    /// Track radius on the disk, mm (required unless the study gives it).
    #[arg(long = "track-radius-mm")]
    pub track_radius_mm: Option<f64>,
    /// Smallest normal force, N.
    #[arg(long = "normal-force-min-N")]
    pub normal_force_min_n: Option<f64>,
    /// Largest normal force, N.
    #[arg(long = "normal-force-max-N")]
    pub normal_force_max_n: Option<f64>,
    /// Number of normal forces (one pin each).
    #[arg(long = "normal-force-count")]
    pub normal_force_count: Option<usize>,
    /// Lowest sliding velocity, m/min.
    #[arg(long = "velocity-min-m-per-min")]
    pub velocity_min: Option<f64>,
    /// Highest sliding velocity, m/min.
    #[arg(long = "velocity-max-m-per-min")]
    pub velocity_max: Option<f64>,
    /// Number of sliding velocities.
    #[arg(long = "velocity-count")]
    pub velocity_count: Option<usize>,
    /// Dwell per velocity once the spindle reached it, s.
    #[arg(long = "dwell-s")]
    pub dwell_s: Option<f64>,
    /// Nominal spindle acceleration, rpm/s.
    #[arg(long = "spindle-accel-rpm-per-s")]
    pub spindle_accel: Option<f64>,
    /// Spindle speed limit, rpm.
    #[arg(long = "max-spindle-rpm")]
    pub max_spindle_rpm: Option<f64>,
    /// M-code switching the recording trigger on.
    #[arg(long = "trigger-on-mcode")]
    pub trigger_on: Option<u32>,
    /// M-code switching the recording trigger off.
    #[arg(long = "trigger-off-mcode")]
    pub trigger_off: Option<u32>,
}

/// The `--study` file as a command input (when given).
pub fn study_input(flags: &PlanFlags) -> Vec<(&'static str, &Path)> {
    flags
        .study
        .as_deref()
        .map(|p| ("study", p))
        .into_iter()
        .collect()
}

impl PlanFlags {
    /// The study with the flags applied.
    pub fn study(&self) -> Result<Study> {
        let mut s = Study::load_or_default(self.study.as_deref())?;
        let p = &mut s.plan;
        macro_rules! set {
            ($field:ident, $flag:expr) => {
                if let Some(v) = $flag {
                    p.$field = v;
                }
            };
        }
        if self.track_radius_mm.is_some() {
            p.track_radius_mm = self.track_radius_mm;
        }
        set!(normal_force_min_n, self.normal_force_min_n);
        set!(normal_force_max_n, self.normal_force_max_n);
        set!(normal_force_count, self.normal_force_count);
        set!(velocity_min_m_per_min, self.velocity_min);
        set!(velocity_max_m_per_min, self.velocity_max);
        set!(velocity_count, self.velocity_count);
        set!(dwell_s, self.dwell_s);
        set!(spindle_accel_rpm_per_s, self.spindle_accel);
        set!(max_spindle_rpm, self.max_spindle_rpm);
        set!(trigger_on_mcode, self.trigger_on);
        set!(trigger_off_mcode, self.trigger_off);
        if self.normal_force_min_n.is_some()
            || self.normal_force_max_n.is_some()
            || self.normal_force_count.is_some()
        {
            p.normal_forces_n = None;
        }
        if self.velocity_min.is_some()
            || self.velocity_max.is_some()
            || self.velocity_count.is_some()
        {
            p.velocities_m_per_min = None;
        }
        Ok(s)
    }
}

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub plan: PlanFlags,
    /// Output directory: study.toml, run_sheet.csv, nc/pinNN.nc.
    #[arg(long, default_value = "plan-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: Args) -> Result<()> {
    let study = args.plan.study()?;
    let summary = plan(&study, &args.out, args.force, &study_input(&args.plan))?;
    if args.json {
        return print_json(&summary);
    }
    print!("{}", greybox_pipeline::text::plan(&summary));
    println!(
        "  wrote {} files to {}",
        summary.files.len(),
        args.out.display()
    );
    Ok(())
}
