//! One simulated cut of the suite and what the suite keeps of it: the mean forces, the chip
//! measures and the contact quantities along the rake face (where friction laws differ: the
//! μ applied, the pressures and sliding velocities it was applied at,
//! [`greybox_sim::chip::RakeContact`]).
//!
//! A cut runs either in this process ([`run_cut`]) or as a sweep case in a process of its
//! own, on the local pool or Slurm ([`Cut::from_summary`] reads it back from the case's
//! summary); both keep the same numbers, in the units of the cut summary.

use anyhow::{Context, Result};
use greybox_core::FrictionLaw;
use greybox_sim::chip::RakeContact;
use greybox_sim::cut_run::CutRun;
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::steady_report::SteadyReport;
use serde::Deserialize;
use std::sync::Arc;

/// What the suite keeps of one cut.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct Cut {
    /// Mean cutting and feed force per width over the steady stretch, N/mm.
    pub cutting_force_n_per_mm: f64,
    pub feed_force_n_per_mm: f64,
    #[serde(rename = "compression_ratio")]
    pub chip_ratio: Option<f64>,
    /// Every steady quantity with its interval and standard error (`None`: the cut found no
    /// steady stretch).
    #[serde(rename = "steady_state")]
    pub steady_report: Option<SteadyReport>,
    pub contact_length_mm: Option<f64>,
    /// The hottest particle over the run, °C.
    pub peak_temperature_c: f64,
    /// A steady stretch was found, and its force intervals met the set-up's targets.
    pub steady: bool,
    pub sure: bool,
    /// The steady stretch spans fewer contact renewals than the set-up asks (its intervals
    /// may understate the scatter).
    pub short_stretch: bool,
    #[serde(rename = "simulated_cut_length_mm")]
    pub cut_length_mm: f64,
    pub wall_s: f64,
    #[serde(rename = "rake_contact")]
    pub local: RakeContact,
}

impl Cut {
    /// The cut of run `r` of `setup` (the expressions of the pipeline's cut summary, so that
    /// a cut run here and one read back from a case agree to the bit).
    fn of_run(setup: &CuttingSetup, r: &CutRun) -> Cut {
        let steady = r
            .steady_state
            .as_ref()
            .map(|s| SteadyReport::of(s, setup.cutting_speed_m_s, setup.uncut_chip_thickness_m));
        Cut {
            cutting_force_n_per_mm: r.force[0] * 1e-3,
            feed_force_n_per_mm: r.force[1] * 1e-3,
            chip_ratio: r.measures.compression_ratio,
            steady_report: steady,
            contact_length_mm: r.measures.contact_length_mm,
            peak_temperature_c: r.peak_temperature.peak_k - 273.15,
            steady: r.steady_state.is_some(),
            sure: r.sure_at_s.is_some(),
            short_stretch: r
                .steady_state
                .as_ref()
                .is_none_or(|s| s.short(&setup.steady)),
            cut_length_mm: r.sim.time * setup.cutting_speed_m_s * 1e3,
            wall_s: r.summary.wall_s,
            local: r.measures.rake_contact,
        }
    }

    /// The standard errors of F'c, F'f (N/mm) and the chip ratio (`None`: the cut could not
    /// say how sure it is).
    pub fn standard_errors(&self) -> [Option<f64>; 3] {
        let s = self.steady_report.as_ref();
        [
            s.and_then(|s| s.cutting_force_n_per_mm.se),
            s.and_then(|s| s.feed_force_n_per_mm.se),
            s.and_then(|s| s.compression_ratio.as_ref())
                .and_then(|q| q.se),
        ]
    }

    /// The half-widths of the 95 % intervals of F'c, F'f (N/mm) and the chip ratio.
    pub fn intervals(&self) -> [Option<f64>; 3] {
        let s = self.steady_report.as_ref();
        [
            s.and_then(|s| s.cutting_force_n_per_mm.ci95),
            s.and_then(|s| s.feed_force_n_per_mm.ci95),
            s.and_then(|s| s.compression_ratio.as_ref())
                .and_then(|q| q.ci95),
        ]
    }

    /// The steady stretch averaged, mm of cut, and where it started.
    pub fn steady_length_mm(&self) -> Option<(f64, f64)> {
        self.steady_report
            .as_ref()
            .map(|s| (s.to_mm - s.from_mm, s.from_mm))
    }

    /// The cut a sweep case ran, from its summary (`greybox simulate`'s `summary.json`
    /// fields; `source` names it in errors).
    pub fn from_summary(summary: &serde_json::Value, source: &str) -> Result<Cut> {
        Cut::deserialize(summary)
            .with_context(|| format!("{source}: not the summary of a cut with its measures"))
    }
}

/// Runs `setup` with `law` in every friction window, in this process.
pub fn run_cut(setup: &CuttingSetup, law: Arc<dyn FrictionLaw>) -> Result<Cut> {
    let r = CutRun::execute(setup, law, 1.0, None, &mut greybox_sim::Hooks::new())?;
    Ok(Cut::of_run(setup, &r))
}
