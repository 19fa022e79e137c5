//! Runs an orthogonal cut with the grey-box loop until its steady state is sure (or to its
//! length limit), and derives its results: the steady state with every quantity's interval
//! ([`crate::steady`]), the time-averaged contact profile and the chip measures.

use crate::checkpoint::Checkpoint;
use crate::chip::{contact_profile, measure, CutMeasures, ProfilePoint};
use crate::cut_series::{cut_series, ChipSampler};
use crate::cutting::{CuttingSetup, EdgeLayout};
use crate::executor::{restored_state, run, Hooks, RunSummary};
use crate::friction_loop::FrictionUpdater;
use crate::output::{ForceHistory, PeakTemperature};
use crate::solver::{SimError, Solver};
use crate::steady::{RunUntilSure, SteadyState};
use greybox_core::physics::Quantity;
use greybox_core::FrictionLaw;
use std::sync::Arc;

/// A finished cut.
pub struct CutRun {
    pub sim: Solver,
    pub summary: RunSummary,
    pub forces: ForceHistory,
    pub updater: FrictionUpdater,
    /// The steady stretch and every steady quantity with its interval (`None`: the cut was
    /// too short to find one; its forces are then the mean over its last half).
    pub steady_state: Option<SteadyState>,
    /// When the force intervals met the set-up's targets, s (`None`: never; with
    /// `stop_when_sure` the cut then ran to its length limit).
    pub sure_at_s: Option<f64>,
    /// The chip sampled as the cut went.
    pub chip: ChipSampler,
    /// The hottest particle over the run (sampled as often as the force history).
    pub peak_temperature: PeakTemperature,
    pub layout: EdgeLayout,
    /// Start of the averaging period (the steady stretch's, or half the run), s.
    pub averaged_from_s: f64,
    /// Mean tool force over the averaging period (cutting, feed), N/m.
    pub force: [f64; 2],
    pub profile: Vec<ProfilePoint>,
    pub measures: CutMeasures,
}

impl CutRun {
    /// Runs `fraction` of the set-up's cut length (or until its force intervals meet their
    /// targets when the set-up asks for it) with `law` in every friction window; the `extra`
    /// seams (outputs, checkpoints) run after the built-in ones of their kind.
    pub fn execute(
        setup: &CuttingSetup,
        law: Arc<dyn FrictionLaw>,
        fraction: f64,
        resume: Option<Checkpoint>,
        extra: &mut Hooks<'_>,
    ) -> Result<CutRun, SimError> {
        if !(fraction > 0.0 && fraction <= 1.0) {
            return Err(SimError::Invalid(format!(
                "fraction of the cut length (`fraction`): expected a number in (0, 1], got {fraction}"
            )));
        }
        let (model, duration) = setup.model_with_law(law)?;
        let layout = setup.insert.layout()?;
        let mut sim = Solver::new(model)?;
        let end = duration * fraction;
        let fresh_dt = sim.dt;
        let states = Checkpoint::resume_into(resume, &mut sim, &fingerprint(setup))?;
        check_steps_ahead(&sim, end, states.is_some(), fraction, fresh_dt)?;
        let v = setup.cutting_speed_m_s;
        let bin_steps = ((end / sim.dt) / FORCE_BINS).ceil().max(1.0) as u64;
        let mut peak_temperature =
            PeakTemperature::new(((end / sim.dt) / 500.0).ceil().max(1.0) as u64);
        let mut updater = FrictionUpdater::new(0, setup.friction.update_every_steps);
        updater.smoothing = setup.friction.smoothing;
        let mut steady = RunUntilSure::new(0, bin_steps, setup, FORCE_BINS as usize / 100);
        if let Some(states) = &states {
            // the histories so far: the outputs and averages cover the whole run
            updater = restored_state::<FrictionUpdater>(states)?;
            updater.resumed = true;
            steady = restored_state::<RunUntilSure>(states)?.resumed(setup);
            peak_temperature = restored_state::<PeakTemperature>(states)?;
        }
        let hooks = Hooks::new()
            .control(&mut updater)
            .observe(&mut steady)
            .observe(&mut peak_temperature)
            .then(extra);
        let summary = run(&mut sim, end, "cut", hooks)?;
        let t_end = sim.time;
        let window = steady.window();
        let renewal = window.and_then(|w| steady.renewal_m(&w));
        let (forces, chip) = (steady.forces, steady.chip);
        let averaged_from_s = window.map_or(0.5 * t_end, |w| w.from_s);
        let tool = &sim.tools[0];
        let series = cut_series(
            &chip,
            &updater,
            tool,
            &layout,
            sim.particles.spacing,
            setup.friction.window_length_m,
        );
        let steady_state = window.map(|w| SteadyState::of(w, &forces, &series, renewal, v));
        let force = steady_state
            .as_ref()
            .map(|s| [s.cutting_force.mean, s.feed_force.mean])
            .or_else(|| forces.mean_force(averaged_from_s, t_end))
            .unwrap_or([0.0, 0.0]);
        if !summary.stopped_by_observer {
            // a run that reached its end (one an observer stopped, killed or sure, has its
            // own account)
            check_cutting_force(force[0], t_end * v)?;
        }
        let profile = contact_profile(
            &sim.tools[0],
            &layout,
            &updater.sums_since(averaged_from_s),
            sim.particles.spacing,
        );
        let means = steady_state.as_ref().map_or([None; 2], |s| {
            [s.chip_thickness, s.contact_length].map(|m| m.map(|m| m.mean))
        });
        let measures = measure(&sim, setup, 0, &profile, means);
        Ok(CutRun {
            sim,
            summary,
            forces,
            updater,
            steady_state,
            sure_at_s: steady.sure_at_s,
            chip,
            peak_temperature,
            layout,
            averaged_from_s,
            force,
            profile,
            measures,
        })
    }
}

/// Force bins over a cut's full length (the force history's rows and the chip's samples;
/// the steady state's intervals are re-formed every hundredth of them).
pub const FORCE_BINS: f64 = 2000.0;

/// A cut's mean cutting force (N/m) over `cut_m` of cut: exactly 0 means the tool never
/// engaged the workpiece (a speed or mass scaling that leaves the chip behind, a cut shorter
/// than the approach) and is an error, not a result of 0.0 N/mm; outside the possible range
/// of [`Quantity::ForcePerWidth`] it is refused with the number.
pub fn check_cutting_force(force_n_per_m: f64, cut_m: f64) -> Result<(), SimError> {
    if force_n_per_m == 0.0 {
        return Err(SimError::Invalid(format!(
            "the cut gave a cutting force of exactly 0 N/mm over {:.3} mm: the tool never engaged the workpiece (check the cutting speed, mass scaling and cut length)",
            cut_m * 1e3
        )));
    }
    greybox_core::physics::check(
        Quantity::ForcePerWidth,
        force_n_per_m.abs(),
        "cutting force",
    )
    .map_err(SimError::Invalid)?;
    Ok(())
}

/// A run must have steps ahead of it: a checkpoint at or past the requested end, or a cut
/// fraction shorter than one step, is an error (it used to report a force of zero).
pub fn check_steps_ahead(
    sim: &Solver,
    end_s: f64,
    resumed: bool,
    fraction: f64,
    dt_s: f64,
) -> Result<(), SimError> {
    if sim.time < end_s - 0.5 * sim.dt {
        let steps = ((end_s - sim.time) / sim.dt).ceil();
        let max = sim
            .numerics
            .max_steps
            .map_or(crate::model::DEFAULT_MAX_STEPS, |c| c.as_u64());
        if steps > max as f64 {
            return Err(SimError::Invalid(format!(
                "the run would take {steps:.3e} time steps of {:.3e} s to reach t = {end_s:.3e} s, over numerics.max_steps = {max}: check cutting_speed_m_s (m/s) and cut_length_m (m), or raise numerics.max_steps",
                sim.dt
            )));
        }
        return Ok(());
    }
    Err(SimError::Invalid(if resumed {
        format!(
            "the checkpoint is at step {} (t = {:.6e} s), at or past the requested end t = {:.6e} s: nothing left to run (resume with a larger `fraction`, or use the finished run)",
            sim.step, sim.time, end_s
        )
    } else {
        format!(
            "`fraction` {fraction} gives an end time of {end_s:.3e} s, less than one time step ({dt_s:.3e} s): no step would run"
        )
    }))
}

/// Identifies a set-up for checkpoints (a checkpoint only resumes the set-up that wrote it).
pub fn fingerprint(setup: &CuttingSetup) -> String {
    serde_json::to_string(setup).unwrap_or_default()
}

/// Result of the inverse search for the Johnson–Cook rate sensitivity C.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RateSensitivityFit {
    /// The C found.
    pub c: f64,
    /// Measured cutting force to match, N/m.
    pub measured_force_n_per_m: f64,
    /// |simulated − measured| at the best evaluated C, N/m.
    pub residual_n_per_m: f64,
    /// Every run: (C, simulated steady cutting force N/m).
    pub runs: Vec<(f64, f64)>,
}

/// The article's inverse step (digest §6): finds the J-C C for which the simulated steady
/// cutting force equals `measured_force_n_per_m`, by an Illinois search over `c_range`
/// (the force grows with C; the two end runs go in parallel). Stops when the force is matched
/// within `tol_n_per_m` or after `max_runs` simulations.
pub fn find_rate_sensitivity(
    base: &CuttingSetup,
    law: Arc<dyn FrictionLaw>,
    measured_force_n_per_m: f64,
    c_range: (f64, f64),
    tol_n_per_m: f64,
    max_runs: usize,
) -> Result<RateSensitivityFit, SimError> {
    if base.material.plasticity.is_none() {
        return Err(SimError::Invalid(
            "the material has no plasticity whose rate sensitivity C could be calibrated".into(),
        ));
    }
    let (c_lo, c_hi) = c_range;
    if !(c_lo >= 0.0 && c_hi > c_lo && measured_force_n_per_m > 0.0 && max_runs >= 2) {
        return Err(SimError::Invalid(format!(
            "expected 0 ≤ C_min < C_max, a positive measured force and at least 2 runs; got C in [{c_lo}, {c_hi}], {measured_force_n_per_m} N/m, {max_runs} runs"
        )));
    }
    let eval = |c: f64| -> Result<f64, SimError> {
        let mut s = base.clone();
        if let Some(f) = s.material.plasticity.as_mut() {
            f.set_rate_sensitivity(c);
        }
        let r = CutRun::execute(&s, law.clone(), 1.0, None, &mut Hooks::new())?;
        Ok(r.force[0] - measured_force_n_per_m)
    };
    let (flo, fhi) = rayon::join(|| eval(c_lo), || eval(c_hi));
    let (flo, fhi) = (flo?, fhi?);
    let mut log = vec![(c_lo, flo), (c_hi, fhi)];
    if !(flo <= 0.0 && fhi >= 0.0) {
        return Err(SimError::Invalid(format!(
            "the measured cutting force {:.1} N/mm lies outside the simulated range {:.1}–{:.1} N/mm for C in [{c_lo}, {c_hi}]; widen the C range",
            measured_force_n_per_m * 1e-3,
            (flo + measured_force_n_per_m) * 1e-3,
            (fhi + measured_force_n_per_m) * 1e-3
        )));
    }
    let c = greybox_core::roots::illinois_increasing(
        eval,
        (c_lo, flo),
        (c_hi, fhi),
        tol_n_per_m,
        max_runs - 2,
        &mut log,
    )?;
    let residual = log.iter().map(|r| r.1.abs()).fold(f64::INFINITY, f64::min);
    Ok(RateSensitivityFit {
        c,
        measured_force_n_per_m,
        residual_n_per_m: residual,
        runs: log
            .iter()
            .map(|&(c, f)| (c, f + measured_force_n_per_m))
            .collect(),
    })
}
