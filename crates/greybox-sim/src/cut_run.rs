//! Runs an orthogonal cut with the grey-box loop and steady-force detection, and derives its
//! results: steady forces, the time-averaged contact profile and the chip measures.

use crate::checkpoint::Checkpoint;
use crate::chip::{contact_profile, measure, CutMeasures, ProfilePoint};
use crate::cutting::{CuttingSetup, EdgeLayout};
use crate::executor::{run, Observer, RunSummary};
use crate::friction_loop::FrictionUpdater;
use crate::output::ForceHistory;
use crate::solver::{SimError, Solver};
use crate::steady::SteadyForce;
use greybox_core::FrictionLaw;
use std::sync::Arc;

/// A finished cut.
pub struct CutRun {
    pub sim: Solver,
    pub summary: RunSummary,
    pub forces: ForceHistory,
    pub updater: FrictionUpdater,
    pub steady: SteadyForce,
    pub layout: EdgeLayout,
    /// Start of the averaging period (steady start, or half the run), s.
    pub averaged_from_s: f64,
    /// Mean tool force over the averaging period (cutting, feed), N/m.
    pub force: [f64; 2],
    pub profile: Vec<ProfilePoint>,
    pub measures: CutMeasures,
}

impl CutRun {
    /// Runs `fraction` of the set-up's cut length (or until the force is steady when the
    /// set-up asks for it) with `law` in every friction window; `extra` observers (outputs,
    /// checkpoints) run after the built-in ones.
    pub fn execute(
        setup: &CuttingSetup,
        law: Arc<dyn FrictionLaw>,
        fraction: f64,
        resume: Option<Checkpoint>,
        extra: &mut [&mut dyn Observer],
    ) -> Result<CutRun, SimError> {
        let invalid = |e: greybox_core::Error| SimError::Invalid(e.to_string());
        if !(fraction > 0.0 && fraction <= 1.0) {
            return Err(SimError::Invalid(format!(
                "fraction of the cut length (--fraction): expected a number in (0, 1], got {fraction}"
            )));
        }
        let (model, duration) = setup.model_with_law(law).map_err(invalid)?;
        let layout = setup.insert.layout().map_err(invalid)?;
        let mut sim = Solver::new(model)?;
        if let Some(c) = resume {
            c.restore(&mut sim, &fingerprint(setup))?;
        }
        let end = duration * fraction;
        let v = setup.cutting_speed_m_s;
        let mut forces = ForceHistory::new(0, ((end / sim.dt) / 500.0).ceil().max(1.0) as u64);
        let mut updater = FrictionUpdater::new(0, setup.friction.update_every_steps);
        let st = &setup.steady;
        let mut steady = SteadyForce::new(
            0,
            st.block_length_m / v,
            st.blocks,
            st.tolerance,
            st.stop_when_steady,
        );
        let summary = {
            let mut obs: Vec<&mut dyn Observer> = vec![&mut forces, &mut updater, &mut steady];
            for o in extra.iter_mut() {
                obs.push(&mut **o);
            }
            run(&mut sim, end, &mut obs)?
        };
        let t_end = sim.time;
        let averaged_from_s = steady.steady_since_s.unwrap_or(0.5 * t_end);
        let force = steady
            .steady_mean()
            .or_else(|| forces.mean_force(averaged_from_s, t_end))
            .unwrap_or([0.0, 0.0]);
        let profile = contact_profile(
            &sim.tools[0],
            &layout,
            &updater.sums_since(averaged_from_s),
            sim.particles.spacing,
        );
        let measures = measure(&sim, setup, 0, &profile);
        Ok(CutRun {
            sim,
            summary,
            forces,
            updater,
            steady,
            layout,
            averaged_from_s,
            force,
            profile,
            measures,
        })
    }
}

/// Identifies a set-up for checkpoints (a checkpoint only resumes the set-up that wrote it).
pub fn fingerprint(setup: &CuttingSetup) -> String {
    serde_json::to_string(setup).unwrap_or_default()
}
