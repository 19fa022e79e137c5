//! The time loop. Everything that is not the physics of a step — output writers, progress,
//! checkpoints, force histories, the grey-box window update — is an [`Observer`] the executor
//! calls after every step.
//!
//! Robustness: the executor keeps an in-memory copy of the last state that passed the checks
//! (refreshed every `snapshot_every` steps); when a step goes unstable the copy is handed to
//! every observer's [`Observer::on_failure`] (the checkpoint writer stores it) and the error
//! names the step and particle.

use crate::particles::Particles;
use crate::solver::{SimError, Solver};

/// What an observer wants after a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Continue,
    Stop,
}

pub trait Observer {
    /// Called once before the first step.
    fn start(&mut self, _sim: &mut Solver) -> Result<(), SimError> {
        Ok(())
    }
    /// Called after every step.
    fn after_step(&mut self, sim: &mut Solver) -> Result<Control, SimError>;
    /// Called once after the last step.
    fn finish(&mut self, _sim: &mut Solver) -> Result<(), SimError> {
        Ok(())
    }
    /// Called when a step failed, with the last good particle state and its step/time.
    fn on_failure(&mut self, _sim: &Solver, _last_good: &Particles, _step: u64, _time: f64) {}
    /// What a resumed run needs of this observer (its history and running sums so far), under
    /// a stable key; saved in every checkpoint so that a resumed run's outputs equal an
    /// uninterrupted run's. `None`: nothing to carry over.
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        None
    }
    /// Whether this observer writes a checkpoint after the current step.
    fn checkpoint_due(&self, _sim: &Solver) -> bool {
        false
    }
    /// Write a checkpoint holding `states`, every observer's [`Observer::save_state`].
    fn write_checkpoint(
        &mut self,
        _sim: &mut Solver,
        _states: &ObserverStates,
    ) -> Result<(), SimError> {
        Ok(())
    }
}

/// Observers' saved states by key (see [`Observer::save_state`]).
pub type ObserverStates = std::collections::BTreeMap<String, serde_json::Value>;

/// An observer's state saved under `key`, for a resumed run; an error when the checkpoint
/// does not hold it.
pub fn restored_state<T: serde::de::DeserializeOwned>(
    states: &ObserverStates,
    key: &str,
) -> Result<T, SimError> {
    let v = states.get(key).ok_or_else(|| {
        SimError::Invalid(format!(
            "the checkpoint holds no '{key}' history (written by an older greybox?): a resumed run could not reproduce the uninterrupted one; start afresh"
        ))
    })?;
    serde_json::from_value(v.clone()).map_err(|e| {
        SimError::Invalid(format!(
            "the checkpoint's '{key}' history is unreadable: {e}"
        ))
    })
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSummary {
    pub steps: u64,
    pub time_s: f64,
    pub wall_s: f64,
    /// Steps before the first contact that skipped the particle passes
    /// ([`Solver::step`](crate::solver::Solver::step)); included in `steps`.
    pub idle_steps: u64,
    /// Particle-steps per second of wall time, over the steps that did the particle passes
    /// (the idle ones left out, so that this stays a measure of the solver's speed).
    pub particle_steps_per_s: f64,
    pub stopped_by_observer: bool,
}

/// Runs until `end_time_s` (simulated) or until an observer stops, reporting progress in
/// steps under `label` (see `greybox_core::progress`).
pub fn run(
    sim: &mut Solver,
    end_time_s: f64,
    label: &str,
    observers: &mut [&mut dyn Observer],
) -> Result<RunSummary, SimError> {
    const SNAPSHOT_EVERY: u64 = 200;
    let steps_ahead = ((end_time_s - sim.time) / sim.dt).ceil().max(0.0) as u64;
    let progress = greybox_core::progress::task(label, Some(sim.step + steps_ahead), "steps");
    progress.set(sim.step);
    for o in observers.iter_mut() {
        o.start(sim)?;
    }
    let t0 = std::time::Instant::now();
    let step0 = sim.step;
    let idle0 = sim.idle_steps;
    let mut last_good = sim.particles.clone();
    let mut last_good_at = (sim.step, sim.time);
    let mut stopped = false;
    while sim.time < end_time_s - 0.5 * sim.dt {
        greybox_core::interrupt::check()?;
        if let Err(e) = sim.step() {
            for o in observers.iter_mut() {
                o.on_failure(sim, &last_good, last_good_at.0, last_good_at.1);
            }
            return Err(e);
        }
        if sim.step.is_multiple_of(SNAPSHOT_EVERY) {
            last_good.clone_from(&sim.particles);
            last_good_at = (sim.step, sim.time);
        }
        let mut stop = false;
        for o in observers.iter_mut() {
            if o.after_step(sim)? == Control::Stop {
                stop = true;
            }
        }
        if observers.iter().any(|o| o.checkpoint_due(sim)) {
            let states: ObserverStates = observers
                .iter()
                .filter_map(|o| o.save_state())
                .map(|(k, v)| (k.to_string(), v))
                .collect();
            for o in observers.iter_mut() {
                if o.checkpoint_due(sim) {
                    o.write_checkpoint(sim, &states)?;
                }
            }
        }
        progress.set_with(sim.step, || {
            format!("t = {:.4e} of {:.4e} s", sim.time, end_time_s)
        });
        if stop {
            stopped = true;
            break;
        }
    }
    for o in observers.iter_mut() {
        o.finish(sim)?;
    }
    progress.finish(if stopped {
        "stopped early (an observer's criterion was met)"
    } else {
        "done"
    });
    let wall = t0.elapsed().as_secs_f64();
    let steps = sim.step - step0;
    let idle_steps = sim.idle_steps - idle0;
    Ok(RunSummary {
        steps,
        time_s: sim.time,
        wall_s: wall,
        idle_steps,
        particle_steps_per_s: (steps - idle_steps) as f64 * sim.particle_count() as f64
            / wall.max(1e-12),
        stopped_by_observer: stopped,
    })
}
