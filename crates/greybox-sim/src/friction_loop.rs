//! The grey-box loop, in process: every N steps each friction window's μ is re-evaluated by
//! its law from the window's contact state averaged over those N steps (pressure, sliding
//! velocity, temperature) — what the article's restart loop did through DEFORM user
//! routines (digest §6, §8), without restarts.
//!
//! A window that saw no contact in an interval keeps its μ. Every update is recorded (the μ
//! history per window), and the raw interval sums are kept so that time-averaged contact
//! profiles can be formed afterwards over any part of the run (e.g. the steady part).

use crate::executor::{Control, Observer};
use crate::solver::{SimError, Solver};
use crate::tool::{WindowAccumulator, WindowStats};
use greybox_core::ContactState;

/// One re-evaluation of one window.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WindowUpdate {
    pub step: u64,
    pub time_s: f64,
    pub window: usize,
    /// The state averaged over the interval that ends here.
    pub stats: WindowStats,
    /// μ the law gives at that state; the window uses it from here on.
    pub mu: f64,
}

/// The accumulated sums of every window over one update interval.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Interval {
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub windows: Vec<WindowAccumulator>,
}

/// Observer running the loop on one tool.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct FrictionUpdater {
    pub tool: usize,
    pub every: u64,
    pub history: Vec<WindowUpdate>,
    pub intervals: Vec<Interval>,
    t_start: f64,
    /// Restored from a checkpoint: the interval in progress started before this run.
    #[serde(skip)]
    pub resumed: bool,
}

impl FrictionUpdater {
    pub fn new(tool: usize, every_steps: u64) -> Self {
        FrictionUpdater {
            tool,
            every: every_steps.max(1),
            history: Vec::new(),
            intervals: Vec::new(),
            t_start: 0.0,
            resumed: false,
        }
    }

    /// Closes the current interval; with `update` also re-evaluates every window's μ.
    fn close_interval(&mut self, sim: &mut Solver, update: bool) -> Result<(), SimError> {
        let spacing = sim.particles.spacing;
        let (step, time) = (sim.step, sim.time);
        let tool = sim
            .tools
            .get_mut(self.tool)
            .ok_or_else(|| SimError::Invalid(format!("no tool {}", self.tool)))?;
        let mut sums = Vec::with_capacity(tool.windows.len());
        for (k, w) in tool.windows.iter_mut().enumerate() {
            sums.push(w.acc);
            if update {
                if let Some(stats) = w.acc.stats(spacing, w.length()) {
                    let state = ContactState {
                        pressure_pa: stats.pressure_pa,
                        sliding_velocity_m_s: stats.sliding_velocity_m_s,
                        temperature_k: stats.temperature_k,
                    };
                    let mu = w.law.mu(&state);
                    if !(mu.is_finite() && mu >= 0.0) {
                        return Err(SimError::Invalid(format!(
                            "friction law '{}' gave μ = {mu} in window {k} of tool '{}' at p = {:.1} MPa, v = {:.2} m/min, T = {:.1} K (expected a finite μ ≥ 0)",
                            w.law.name(),
                            tool.name,
                            stats.pressure_pa * 1e-6,
                            stats.sliding_velocity_m_s * 60.0,
                            stats.temperature_k
                        )));
                    }
                    w.mu = mu;
                    self.history.push(WindowUpdate {
                        step,
                        time_s: time,
                        window: k,
                        stats,
                        mu,
                    });
                }
            }
            w.acc = WindowAccumulator::default();
        }
        self.intervals.push(Interval {
            t_start_s: self.t_start,
            t_end_s: time,
            windows: sums,
        });
        self.t_start = time;
        Ok(())
    }

    /// Window sums over the intervals that start at or after `t_from_s`.
    pub fn sums_since(&self, t_from_s: f64) -> Vec<WindowAccumulator> {
        let n = self.intervals.first().map_or(0, |i| i.windows.len());
        let mut total = vec![WindowAccumulator::default(); n];
        for iv in self.intervals.iter().filter(|i| i.t_start_s >= t_from_s) {
            for (t, w) in total.iter_mut().zip(&iv.windows) {
                t.add(w);
            }
        }
        total
    }
}

impl Observer for FrictionUpdater {
    fn start(&mut self, sim: &mut Solver) -> Result<(), SimError> {
        // The windows' sums are kept: after a resume they hold the interval in progress
        // (restored from the checkpoint), so the μ updates continue as in an uninterrupted run;
        // so does the interval's start time, restored with the history.
        if !self.resumed {
            self.t_start = sim.time;
        }
        Ok(())
    }
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        Some(("friction_updates", serde_json::to_value(self).ok()?))
    }
    fn after_step(&mut self, sim: &mut Solver) -> Result<Control, SimError> {
        if sim.step.is_multiple_of(self.every) {
            self.close_interval(sim, true)?;
        }
        Ok(Control::Continue)
    }
    fn finish(&mut self, sim: &mut Solver) -> Result<(), SimError> {
        if sim.time > self.t_start {
            self.close_interval(sim, false)?;
        }
        Ok(())
    }
}
