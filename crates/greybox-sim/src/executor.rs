//! The time loop. Everything that is not the physics of a step is one of three seams the
//! executor calls after every step ([`Hooks`]):
//! * a [`Controller`] may change the state between steps — the grey-box loop re-evaluates the
//!   friction windows' μ; controllers run first, so everything else sees the state the next
//!   step starts from;
//! * an [`Observer`] only reads it — output writers, force histories, stopping criteria;
//! * a [`CheckpointWriter`] stores the state with every controller's and observer's history
//!   ([`Controller::save_state`], [`Observer::save_state`]) so that a resumed run's outputs
//!   equal an uninterrupted run's.
//!
//! Robustness: the executor keeps an in-memory copy of the last state that passed the checks
//! (refreshed every `snapshot_every` steps); when a step goes unstable the copy is handed to
//! every observer's [`Observer::on_failure`] and checkpoint writer's
//! [`CheckpointWriter::on_failure`] (the checkpoint writer stores it) and the error names the
//! step and particle.

use crate::particles::Particles;
use crate::solver::{SimError, Solver};

/// What an observer or controller wants after a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    Continue,
    Stop,
}

/// A read-only watcher of a run: an output writer, a history, a stopping criterion.
///
/// It gets the solver by shared reference, so it cannot change the run: adding one never
/// changes another output. What it has gathered so far travels in checkpoints through
/// [`Observer::save_state`].
///
/// ```rust
/// use greybox_material::Material;
/// use greybox_sim::{run, Control, Hooks, Model, Numerics, Observer, Particles, SimError, Solver};
///
/// /// Stops the run after `0` steps.
/// struct StopAfter(u64);
/// impl Observer for StopAfter {
///     fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
///         Ok(if sim.step >= self.0 { Control::Stop } else { Control::Continue })
///     }
/// }
///
/// let material = Material::elastic_steel();
/// let particles = Particles::block(0.0, 0.0, 4, 4, 10e-6, material.density_kg_m3, 293.15);
/// let model = Model { particles, material, tools: vec![], groups: vec![], numerics: Numerics::default(), refinement: None, sink: None };
/// let mut sim = Solver::new(model)?;
/// let mut stop = StopAfter(3);
/// let summary = run(&mut sim, 1.0, "example", Hooks::new().observe(&mut stop))?;
/// assert_eq!((summary.steps, summary.stopped_by_observer), (3, true));
/// # Ok::<(), SimError>(())
/// ```
pub trait Observer {
    /// Called once before the first step (after the controllers' start).
    fn start(&mut self, _sim: &Solver) -> Result<(), SimError> {
        Ok(())
    }
    /// Called after every step (after the controllers').
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError>;
    /// Called once after the last step (after the controllers' finish).
    fn finish(&mut self, _sim: &Solver) -> Result<(), SimError> {
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
}

/// A seam that changes the run between steps: the grey-box loop
/// ([`crate::friction_loop::FrictionUpdater`]) sets the friction windows' μ from the contact
/// state. It gets the solver mutably and runs before the observers after every step.
///
/// ```rust
/// use greybox_material::Material;
/// use greybox_sim::{run, Control, Controller, Hooks, Model, Numerics, Particles, SimError, Solver};
///
/// /// Warms every particle by `0` K per step.
/// struct Heater(f64);
/// impl Controller for Heater {
///     fn after_step(&mut self, sim: &mut Solver) -> Result<Control, SimError> {
///         sim.particles.temp.iter_mut().for_each(|t| *t += self.0);
///         Ok(Control::Continue)
///     }
/// }
///
/// let material = Material::elastic_steel();
/// let particles = Particles::block(0.0, 0.0, 4, 4, 10e-6, material.density_kg_m3, 293.15);
/// let model = Model { particles, material, tools: vec![], groups: vec![], numerics: Numerics::default(), refinement: None, sink: None };
/// let mut sim = Solver::new(model)?;
/// let end = 3.0 * sim.dt; // three steps
/// run(&mut sim, end, "example", Hooks::new().control(&mut Heater(1.0)))?;
/// assert!((sim.particles.temp[0] - 296.15).abs() < 1e-9);
/// # Ok::<(), SimError>(())
/// ```
pub trait Controller {
    /// Called once before the first step.
    fn start(&mut self, _sim: &mut Solver) -> Result<(), SimError> {
        Ok(())
    }
    /// Called after every step, before the observers.
    fn after_step(&mut self, sim: &mut Solver) -> Result<Control, SimError>;
    /// Called once after the last step, before the observers' finish.
    fn finish(&mut self, _sim: &mut Solver) -> Result<(), SimError> {
        Ok(())
    }
    /// As [`Observer::save_state`]: this controller's history for a resumed run.
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        None
    }
}

/// A seam that stores the run's state ([`crate::checkpoint::Checkpointer`] writes it to a
/// file) with every controller's and observer's saved state, after the step's controllers
/// and observers; and stores the last good state when a step fails.
///
/// ```rust
/// use greybox_material::Material;
/// use greybox_sim::{run, CheckpointWriter, Hooks, Model, Numerics, ObserverStates, Particles, SimError, Solver};
///
/// /// Keeps the step of every 2nd step in memory.
/// #[derive(Default)]
/// struct Steps(Vec<u64>);
/// impl CheckpointWriter for Steps {
///     fn checkpoint_due(&self, sim: &Solver) -> bool {
///         sim.step % 2 == 0
///     }
///     fn write_checkpoint(&mut self, sim: &mut Solver, _states: &ObserverStates) -> Result<(), SimError> {
///         self.0.push(sim.step);
///         Ok(())
///     }
/// }
///
/// let material = Material::elastic_steel();
/// let particles = Particles::block(0.0, 0.0, 4, 4, 10e-6, material.density_kg_m3, 293.15);
/// let model = Model { particles, material, tools: vec![], groups: vec![], numerics: Numerics::default(), refinement: None, sink: None };
/// let mut sim = Solver::new(model)?;
/// let end = 4.5 * sim.dt;
/// let mut steps = Steps::default();
/// run(&mut sim, end, "example", Hooks::new().checkpoint(&mut steps))?;
/// assert_eq!(steps.0, [2, 4]);
/// # Ok::<(), SimError>(())
/// ```
pub trait CheckpointWriter {
    /// Whether to write a checkpoint after the current step.
    fn checkpoint_due(&self, sim: &Solver) -> bool;
    /// Write a checkpoint holding `states`, every controller's and observer's saved state.
    /// Gets the solver mutably to put it into the state a resumed run starts from (the
    /// checkpoint writer rebuilds the neighbour lists, as a restore does).
    fn write_checkpoint(
        &mut self,
        sim: &mut Solver,
        states: &ObserverStates,
    ) -> Result<(), SimError>;
    /// Called when a step failed, with the last good particle state and its step/time.
    fn on_failure(&mut self, _sim: &Solver, _last_good: &Particles, _step: u64, _time: f64) {}
}

/// The seams a [`run`] calls besides the step, each list in its own order: controllers, then
/// observers, then checkpoint writers.
#[derive(Default)]
pub struct Hooks<'a> {
    pub controllers: Vec<&'a mut dyn Controller>,
    pub observers: Vec<&'a mut dyn Observer>,
    pub checkpoints: Vec<&'a mut dyn CheckpointWriter>,
}

impl<'a> Hooks<'a> {
    /// No seams.
    pub fn new() -> Self {
        Self::default()
    }
    /// With one more observer (after those already there).
    pub fn observe(mut self, o: &'a mut dyn Observer) -> Self {
        self.observers.push(o);
        self
    }
    /// With one more controller (after those already there).
    pub fn control(mut self, c: &'a mut dyn Controller) -> Self {
        self.controllers.push(c);
        self
    }
    /// With one more checkpoint writer (after those already there).
    pub fn checkpoint(mut self, c: &'a mut dyn CheckpointWriter) -> Self {
        self.checkpoints.push(c);
        self
    }
    /// With `more`'s seams (borrowed for this run) after these, list by list.
    pub fn then(mut self, more: &'a mut Hooks<'_>) -> Self {
        for c in more.controllers.iter_mut() {
            self.controllers.push(&mut **c);
        }
        for o in more.observers.iter_mut() {
            self.observers.push(&mut **o);
        }
        for c in more.checkpoints.iter_mut() {
            self.checkpoints.push(&mut **c);
        }
        self
    }

    /// Every controller's and observer's saved state, by key.
    fn saved_states(&self) -> ObserverStates {
        let controllers = self.controllers.iter().filter_map(|c| c.save_state());
        let observers = self.observers.iter().filter_map(|o| o.save_state());
        controllers
            .chain(observers)
            .map(|(k, v)| (k.to_string(), v))
            .collect()
    }
}

/// Observers' saved states by key (see [`Observer::save_state`], [`Controller::save_state`]).
pub type ObserverStates = std::collections::BTreeMap<String, serde_json::Value>;

/// A state carried through a checkpoint, for a resumed run: an observer's or controller's
/// history and running sums, under its one key (the type names it once, for writing and for
/// reading back).
pub trait SavedState: serde::Serialize + serde::de::DeserializeOwned {
    /// The key in the checkpoint's [`ObserverStates`].
    const KEY: &'static str;

    /// What `save_state` returns: this state under its key.
    fn saved(&self) -> Option<(&'static str, serde_json::Value)> {
        Some((Self::KEY, serde_json::to_value(self).ok()?))
    }
}

/// The state of type `T` a checkpoint holds under `T::KEY`; an error when the checkpoint does
/// not hold it or it does not read back.
pub fn restored_state<T: SavedState>(states: &ObserverStates) -> Result<T, SimError> {
    let key = T::KEY;
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

/// Runs until `end_time_s` (simulated) or until an observer or controller stops, reporting
/// progress in steps under `label` (see `greybox_core::progress`).
pub fn run(
    sim: &mut Solver,
    end_time_s: f64,
    label: &str,
    mut hooks: Hooks<'_>,
) -> Result<RunSummary, SimError> {
    const SNAPSHOT_EVERY: u64 = 200;
    let steps_ahead = ((end_time_s - sim.time) / sim.dt).ceil().max(0.0) as u64;
    let progress = greybox_core::progress::task(label, Some(sim.step + steps_ahead), "steps");
    progress.set(sim.step);
    for c in hooks.controllers.iter_mut() {
        c.start(sim)?;
    }
    for o in hooks.observers.iter_mut() {
        o.start(sim)?;
    }
    let t0 = std::time::Instant::now();
    let step0 = sim.step;
    let idle0 = sim.idle_steps;
    let work0 = sim.particle_steps;
    let mut last_good = sim.particles.clone();
    let mut last_good_at = (sim.step, sim.time);
    let mut stopped = false;
    // With local time stepping a run ends only at the end of a coarse step (see
    // `Solver::at_sync`): past the end time, or asked to stop, it takes the coarse step's
    // second step first.
    let mut stop_asked = false;
    while sim.time < end_time_s - 0.5 * sim.dt || !sim.at_sync() {
        // a stop on request, like a snapshot, only at the end of a coarse step (every step
        // without local time stepping), where nothing is pending
        if sim.at_sync() {
            greybox_core::interrupt::check()?;
        }
        if let Err(e) = sim.step() {
            report_failure(&mut hooks, sim, &last_good, last_good_at);
            return Err(e);
        }
        if sim.at_sync() && sim.step / SNAPSHOT_EVERY != sim.sync_step() / SNAPSHOT_EVERY {
            last_good.clone_from(&sim.particles);
            last_good_at = (sim.step, sim.time);
        }
        let stop = after_step(&mut hooks, sim)?;
        progress.set_with(sim.step, || {
            format!("t = {:.4e} of {:.4e} s", sim.time, end_time_s)
        });
        stop_asked |= stop;
        if stop_asked && sim.at_sync() {
            stopped = true;
            break;
        }
    }
    for c in hooks.controllers.iter_mut() {
        c.finish(sim)?;
    }
    for o in hooks.observers.iter_mut() {
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
        particle_steps_per_s: (sim.particle_steps - work0) as f64 / wall.max(1e-12),
        stopped_by_observer: stopped,
    })
}

/// After a step: the controllers, the observers, then the checkpoints that are due; whether
/// one of them asked to stop.
fn after_step(hooks: &mut Hooks<'_>, sim: &mut Solver) -> Result<bool, SimError> {
    let mut stop = false;
    for c in hooks.controllers.iter_mut() {
        if c.after_step(sim)? == Control::Stop {
            stop = true;
        }
    }
    for o in hooks.observers.iter_mut() {
        if o.after_step(sim)? == Control::Stop {
            stop = true;
        }
    }
    if hooks.checkpoints.iter().any(|c| c.checkpoint_due(sim)) {
        let states = hooks.saved_states();
        for c in hooks.checkpoints.iter_mut() {
            if c.checkpoint_due(sim) {
                c.write_checkpoint(sim, &states)?;
            }
        }
    }
    Ok(stop)
}

/// Hands the last good state to the observers and checkpoint writers after a failed step.
fn report_failure(
    hooks: &mut Hooks<'_>,
    sim: &Solver,
    last_good: &Particles,
    (step, time): (u64, f64),
) {
    for o in hooks.observers.iter_mut() {
        o.on_failure(sim, last_good, step, time);
    }
    for c in hooks.checkpoints.iter_mut() {
        c.on_failure(sim, last_good, step, time);
    }
}
