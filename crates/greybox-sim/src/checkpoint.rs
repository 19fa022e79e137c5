//! Checkpoints: the complete mutable solver state as JSON (f64 round-trip exact), written
//! atomically, so a long run can resume bit-for-bit from the last checkpoint.

use crate::executor::{CheckpointWriter, ObserverStates};
use crate::particles::Particles;
use crate::solver::{EnergyBook, SimError, Solver};
use crate::tool::WindowAccumulator;
use greybox_core::atomic::write_string_atomic;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// v2 added the observers' histories (forces, window updates, steady blocks).
const FORMAT: &str = "greybox-sim checkpoint v2";

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Checkpoint {
    pub format: String,
    /// Fingerprint of the set-up the checkpoint belongs to (checked on resume).
    pub setup: String,
    pub step: u64,
    pub time_s: f64,
    pub dt_s: f64,
    pub particles: Particles,
    pub tools: Vec<ToolState>,
    pub energy: EnergyBook,
    /// The observers' histories at this step ([`crate::executor::Observer::save_state`], [`crate::executor::Controller::save_state`]).
    #[serde(default)]
    pub observers: ObserverStates,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ToolState {
    pub position: [f64; 2],
    pub window_mu: Vec<f64>,
    pub window_acc: Vec<WindowAccumulator>,
}

impl Checkpoint {
    pub fn of(sim: &Solver, setup: &str) -> Self {
        Self::with_particles(sim, setup, &sim.particles, sim.step, sim.time)
    }

    fn with_particles(sim: &Solver, setup: &str, p: &Particles, step: u64, time: f64) -> Self {
        Checkpoint {
            format: FORMAT.into(),
            setup: setup.into(),
            step,
            time_s: time,
            dt_s: sim.dt,
            particles: p.clone(),
            tools: sim
                .tools
                .iter()
                .map(|t| ToolState {
                    position: t.position,
                    window_mu: t.windows.iter().map(|w| w.mu).collect(),
                    window_acc: t.windows.iter().map(|w| w.acc).collect(),
                })
                .collect(),
            energy: sim.energy,
            observers: ObserverStates::new(),
        }
    }

    pub fn write(&self, path: &Path) -> greybox_core::Result<()> {
        let s = serde_json::to_string(self)
            .map_err(|e| greybox_core::Error::invalid("checkpoint", e.to_string()))?;
        write_string_atomic(path, &s)
    }

    pub fn read(path: &Path) -> greybox_core::Result<Self> {
        let text = greybox_core::input::read_data_text(path, "checkpoint")?;
        let mut c: Checkpoint = serde_json::from_str(&text).map_err(|e| {
            greybox_core::Error::invalid(
                format!(
                    "{}, line {}, column {}",
                    path.display(),
                    e.line(),
                    e.column()
                ),
                format!("not a greybox-sim checkpoint: {e}"),
            )
        })?;
        c.particles.fill_missing_fields();
        if c.format != FORMAT || !c.particles.check_lengths() {
            return Err(greybox_core::Error::invalid(
                path.display().to_string(),
                format!("expected format '{FORMAT}' with consistent particle arrays"),
            ));
        }
        c.check().map_err(|m| {
            greybox_core::Error::invalid(
                format!("checkpoint {}", path.display()),
                format!("{m}: the file is damaged or was edited; resume from another checkpoint or run again"),
            )
        })?;
        Ok(c)
    }

    /// Every number of the state checked like any input (a checkpoint is a file anybody
    /// could have written): the step within what a run may take, time and time step finite
    /// and positive, every particle value and tool position finite, every window's μ inside
    /// the physics table's possible range. The error names the field and the value.
    pub fn check(&self) -> Result<(), String> {
        use greybox_core::physics::{self, Quantity};
        let max_step = crate::model::StepCap::MAX;
        if self.step > max_step {
            return Err(format!(
                "step {} is beyond any run (numerics.max_steps is at most {max_step})",
                self.step
            ));
        }
        if !(self.time_s.is_finite() && self.time_s >= 0.0) {
            return Err(format!(
                "time_s = {}: expected a finite time ≥ 0 s",
                self.time_s
            ));
        }
        if !(self.dt_s.is_finite() && self.dt_s > 0.0) {
            return Err(format!(
                "dt_s = {}: expected a finite time step > 0 s",
                self.dt_s
            ));
        }
        let p = &self.particles;
        for (name, v) in [("particles.mass", p.mass), ("particles.spacing", p.spacing)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} = {v}: expected a finite value > 0"));
            }
        }
        for (name, values) in crate::particles::REAL_FIELD_NAMES
            .iter()
            .zip(p.real_fields())
        {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "particles.{name}[{i}] = {}: expected a finite number",
                    values[i]
                ));
            }
        }
        if let Some(i) = p.damage.iter().position(|d| !(0.0..2.0).contains(d)) {
            return Err(format!(
                "particles.damage[{i}] = {}: expected a damage state in [0, 2) (ω before initiation, 1 + d after)",
                p.damage[i]
            ));
        }
        for (k, t) in self.tools.iter().enumerate() {
            if t.position.iter().any(|x| !x.is_finite()) {
                return Err(format!(
                    "tools[{k}].position = {:?}: expected finite coordinates",
                    t.position
                ));
            }
            if t.window_mu.len() != t.window_acc.len() {
                return Err(format!(
                    "tools[{k}]: {} window μ but {} window accumulators",
                    t.window_mu.len(),
                    t.window_acc.len()
                ));
            }
            for (j, &mu) in t.window_mu.iter().enumerate() {
                physics::check(Quantity::Mu, mu, &format!("tools[{k}].window_mu[{j}]"))?;
            }
        }
        Ok(())
    }

    /// Restore `resume` (if any) into `sim` and hand back the observers' saved histories.
    pub fn resume_into(
        resume: Option<Self>,
        sim: &mut Solver,
        setup: &str,
    ) -> Result<Option<ObserverStates>, SimError> {
        resume
            .map(|c| {
                let states = c.observers.clone();
                c.restore(sim, setup).map(|()| states)
            })
            .transpose()
    }

    /// Restores into a solver built from the same set-up.
    pub fn restore(self, sim: &mut Solver, setup: &str) -> Result<(), SimError> {
        let shape_ok = self.tools.len() == sim.tools.len()
            && self
                .tools
                .iter()
                .zip(&sim.tools)
                .all(|(a, b)| a.window_mu.len() == b.windows.len());
        // A refined run has split particles since the set-up laid them out, one with a sink
        // has removed some.
        let count_ok = self.particles.len() == sim.particles.len()
            || sim.refinement.is_some() && self.particles.len() > sim.particles.len()
            || sim.sink.is_some();
        if self.setup != setup || !shape_ok || !count_ok {
            return Err(SimError::Invalid(
                "the checkpoint belongs to a different set-up (configuration changed since it was written)".into(),
            ));
        }
        // the set-up's boundary groups (1..=groups; 0 is free): an index past them would
        // book a force into a group that does not exist
        let groups = sim.groups.len();
        if let Some((i, g)) = self
            .particles
            .group
            .iter()
            .enumerate()
            .find(|(_, &g)| g as usize > groups)
        {
            return Err(SimError::Invalid(format!(
                "the checkpoint's particles.group[{i}] = {g}, but the set-up has {groups} boundary group(s) (0 = free): the file is damaged or was edited"
            )));
        }
        sim.particles = self.particles;
        let n = sim.particles.len();
        sim.scratch.for_particles(n);
        sim.step = self.step;
        sim.time = self.time_s;
        sim.dt = self.dt_s;
        sim.energy = self.energy;
        for (t, s) in sim.tools.iter_mut().zip(self.tools) {
            t.position = s.position;
            for (w, (mu, acc)) in t
                .windows
                .iter_mut()
                .zip(s.window_mu.into_iter().zip(s.window_acc))
            {
                w.mu = mu;
                w.acc = acc;
            }
        }
        sim.rebuild_lists();
        sim.check_rest();
        Ok(())
    }
}

/// Writes a checkpoint every `every` steps and, on failure, the last good state.
pub struct Checkpointer {
    pub path: PathBuf,
    pub every: u64,
    pub setup: String,
    pub failure_path: Option<PathBuf>,
}

impl Checkpointer {
    pub fn new(path: &Path, every: u64, setup: &str) -> Self {
        Checkpointer {
            path: path.to_path_buf(),
            every: every.max(1),
            setup: setup.into(),
            failure_path: None,
        }
    }
}

impl CheckpointWriter for Checkpointer {
    /// At the end of the coarse step that reached a multiple of `every` (every step is a
    /// coarse step without local time stepping).
    fn checkpoint_due(&self, sim: &Solver) -> bool {
        sim.at_sync() && sim.step / self.every != sim.sync_step() / self.every
    }
    fn write_checkpoint(
        &mut self,
        sim: &mut Solver,
        states: &ObserverStates,
    ) -> Result<(), SimError> {
        // Rebuild the neighbour lists here so that a resumed run (which rebuilds on restore)
        // sums in exactly the same order: resume is bit-for-bit.
        sim.rebuild_lists();
        let mut c = Checkpoint::of(sim, &self.setup);
        c.observers = states.clone();
        Ok(c.write(&self.path)?)
    }
    fn on_failure(&mut self, sim: &Solver, last_good: &Particles, step: u64, time: f64) {
        let path = self.path.with_extension("last_good.json");
        if Checkpoint::with_particles(sim, &self.setup, last_good, step, time)
            .write(&path)
            .is_ok()
        {
            self.failure_path = Some(path);
        }
    }
}
