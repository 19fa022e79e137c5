//! One simulated cut of the suite and what the suite keeps of it: the mean forces, the chip
//! measures and the local contact quantities along the rake face (where friction laws
//! differ: the μ applied, the pressures and sliding velocities it was applied at).

use anyhow::Result;
use greybox_core::units::PA_PER_MPA;
use greybox_core::FrictionLaw;
use greybox_sim::chip::ProfilePoint;
use greybox_sim::cut_run::CutRun;
use greybox_sim::cutting::{CuttingSetup, Face};
use serde::Serialize;
use std::sync::Arc;

/// Windows in contact for less than this fraction of their length on time average are left
/// out of the local quantities (as they are of the contact length, [`greybox_sim::chip`]).
const IN_CONTACT: f64 = 0.1;

/// The contact quantities along the rake face (edge included) over the windows in contact.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct LocalQuantities {
    /// The μ the law applied, averaged over the contact length.
    pub mean_mu: Option<f64>,
    /// Least and greatest window contact pressure, MPa.
    pub pressure_mpa: Option<[f64; 2]>,
    /// Least and greatest window sliding velocity (physical, time scaling undone), m/min.
    pub sliding_velocity_m_per_min: Option<[f64; 2]>,
}

/// What the suite keeps of one cut.
#[derive(Debug, Clone)]
pub struct Cut {
    /// Mean tool force per width over the averaging period (cutting, feed), N/m.
    pub force: [f64; 2],
    pub chip_ratio: Option<f64>,
    pub contact_length_mm: Option<f64>,
    /// The hottest particle over the run, °C.
    pub peak_temperature_c: f64,
    pub steady: bool,
    pub cut_length_mm: f64,
    pub wall_s: f64,
    pub local: LocalQuantities,
}

/// Runs `setup` with `law` in every friction window.
pub fn run_cut(setup: &CuttingSetup, law: Arc<dyn FrictionLaw>) -> Result<Cut> {
    let r = CutRun::execute(setup, law, 1.0, None, &mut greybox_sim::Hooks::new())?;
    Ok(Cut {
        force: r.force,
        chip_ratio: r.measures.compression_ratio,
        contact_length_mm: r.measures.contact_length_mm,
        peak_temperature_c: r.peak_temperature.peak_k - 273.15,
        steady: r.steady.steady_since_s.is_some(),
        cut_length_mm: r.sim.time * setup.cutting_speed_m_s * 1e3,
        wall_s: r.summary.wall_s,
        local: local_quantities(&r.profile),
    })
}

fn local_quantities(profile: &[ProfilePoint]) -> LocalQuantities {
    let rake: Vec<(f64, greybox_sim::tool::WindowStats)> = profile
        .iter()
        .filter(|p| matches!(p.face, Face::Rake | Face::Edge))
        .filter_map(|p| p.stats.map(|s| (p.mu, s)))
        .filter(|(_, s)| s.contact_fraction >= IN_CONTACT)
        .collect();
    if rake.is_empty() {
        return LocalQuantities::default();
    }
    let range = |f: &dyn Fn(&greybox_sim::tool::WindowStats) -> f64| {
        let lo = rake.iter().map(|(_, s)| f(s)).fold(f64::INFINITY, f64::min);
        let hi = rake
            .iter()
            .map(|(_, s)| f(s))
            .fold(f64::NEG_INFINITY, f64::max);
        Some([lo, hi])
    };
    LocalQuantities {
        mean_mu: Some(rake.iter().map(|(mu, _)| mu).sum::<f64>() / rake.len() as f64),
        pressure_mpa: range(&|s| s.pressure_pa / PA_PER_MPA),
        sliding_velocity_m_per_min: range(&|s| {
            greybox_core::units::m_per_s_to_m_per_min(s.sliding_velocity_m_s)
        }),
    }
}
