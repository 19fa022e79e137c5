//! The grey-box loop, in process: every N steps each friction window's μ is re-evaluated by
//! its law from the window's contact state averaged over those N steps (pressure, sliding
//! velocity, temperature) — what the article's restart loop did through DEFORM user
//! routines (digest §6, §8), without restarts.
//!
//! A window that saw no contact in an interval keeps its μ. Every update is recorded (the μ
//! history per window), and the raw interval sums are kept so that time-averaged contact
//! profiles can be formed afterwards over any part of the run (e.g. the steady part).
//!
//! One interval's average over one window is noisy: a few particles enter and leave it, so
//! a window's pressure jumps from update to update and from its neighbours', and so does
//! the μ a pressure-dependent law gives. [`Smoothing`] steadies the state the law sees:
//! * in space, the window's interval sums are combined with those of its `space_windows`
//!   neighbours on each side with triangular weights 1 − |k|/(n + 1) (contact-weighted, as
//!   the window's own averages are: pressure Σ w f_N / Σ w contacts, velocity and
//!   temperature f_N-weighted);
//! * in time, an exponential average over updates, x ← x + (x_new − x)/N with
//!   N = `time_updates` (N = 1: none), started at the window's first contact.

use crate::executor::{Control, Controller};
use crate::solver::{SimError, Solver};
use crate::tool::{WindowAccumulator, WindowStats};
use greybox_core::ContactState;

/// How the state a window hands to its law is smoothed (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Smoothing {
    /// Exponential average over this many updates (1: the interval's own state).
    pub time_updates: f64,
    /// Neighbouring windows on each side averaged in (0: none).
    pub space_windows: usize,
}

impl Default for Smoothing {
    fn default() -> Self {
        Smoothing {
            time_updates: 1.0,
            space_windows: 0,
        }
    }
}

impl Smoothing {
    pub fn validate(&self) -> greybox_core::Result<()> {
        greybox_core::rules::Rules::new("friction.smoothing")
            .within("time_updates", self.time_updates, 1.0, 1e6)
            .finish()
    }
}

/// One re-evaluation of one window.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WindowUpdate {
    pub step: u64,
    pub time_s: f64,
    pub window: usize,
    /// The state averaged over the interval that ends here.
    pub stats: WindowStats,
    /// The state the law was evaluated at (`stats` smoothed in space and time).
    #[serde(default)]
    pub law_state: Option<ContactState>,
    /// μ the law gives at that state; the window uses it from here on.
    pub mu: f64,
}

/// The accumulated sums of every window over one update interval.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Interval {
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub windows: Vec<WindowAccumulator>,
    /// Closed by the run's end before the loop's cadence came round (no μ update): shorter
    /// than the others. The per-interval series leave it out, so that they hold the samples
    /// the stop rule read while the cut ran ([`crate::cut_series::contact_series`]).
    #[serde(default)]
    pub partial: bool,
}

/// The controller running the loop on one tool.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct FrictionUpdater {
    pub tool: usize,
    pub every: u64,
    #[serde(default)]
    pub smoothing: Smoothing,
    /// Per window: the time-smoothed state, from the window's first contact on.
    #[serde(default)]
    pub smoothed: Vec<Option<ContactState>>,
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
            smoothing: Smoothing::default(),
            smoothed: Vec::new(),
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
        tool.last_close_step = Some(step);
        let sums: Vec<WindowAccumulator> = tool.windows.iter().map(|w| w.acc).collect();
        let lengths: Vec<f64> = tool.windows.iter().map(|w| w.length()).collect();
        self.smoothed.resize(sums.len(), None);
        for (k, w) in tool.windows.iter_mut().enumerate() {
            w.last_interval = w.acc;
            w.acc = WindowAccumulator::default();
            if !update {
                continue;
            }
            let Some(stats) = sums[k].stats(spacing, lengths[k]) else {
                continue;
            };
            let n = self.smoothing.space_windows;
            let state = if n == 0 {
                state_of(&stats)
            } else {
                let (mut acc, mut len) = (WindowAccumulator::default(), 0.0);
                for j in k.saturating_sub(n)..(k + n + 1).min(sums.len()) {
                    let wgt = 1.0 - j.abs_diff(k) as f64 / (n + 1) as f64;
                    acc.add(&sums[j].scaled(wgt));
                    len += wgt * lengths[j];
                }
                acc.stats(spacing, len)
                    .map_or(state_of(&stats), |s| state_of(&s))
            };
            let a = 1.0 / self.smoothing.time_updates;
            // Without time smoothing (a = 1) the state is taken as it is, not as
            // `old + 1·(state − old)`, which differs from it by round-off.
            let law_state = match self.smoothed[k] {
                Some(old) if a < 1.0 => ContactState {
                    pressure_pa: old.pressure_pa + a * (state.pressure_pa - old.pressure_pa),
                    sliding_velocity_m_s: old.sliding_velocity_m_s
                        + a * (state.sliding_velocity_m_s - old.sliding_velocity_m_s),
                    temperature_k: old.temperature_k
                        + a * (state.temperature_k - old.temperature_k),
                },
                _ => state,
            };
            self.smoothed[k] = Some(law_state);
            let mu = w.law.mu(&law_state);
            if !(mu.is_finite() && mu >= 0.0) {
                return Err(SimError::Invalid(format!(
                    "friction law '{}' gave μ = {mu} in window {k} of tool '{}' at p = {:.1} MPa, v = {:.2} m/min, T = {:.1} K (expected a finite μ ≥ 0)",
                    w.law.name(),
                    tool.name,
                    law_state.pressure_pa * 1e-6,
                    law_state.sliding_velocity_m_s * 60.0,
                    law_state.temperature_k
                )));
            }
            w.mu = mu;
            self.history.push(WindowUpdate {
                step,
                time_s: time,
                window: k,
                stats,
                law_state: Some(law_state),
                mu,
            });
        }
        self.intervals.push(Interval {
            t_start_s: self.t_start,
            t_end_s: time,
            windows: sums,
            partial: !update,
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

fn state_of(s: &WindowStats) -> ContactState {
    s.contact_state()
}

impl Controller for FrictionUpdater {
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
        crate::executor::SavedState::saved(self)
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

impl crate::executor::SavedState for FrictionUpdater {
    const KEY: &'static str = "friction_updates";
}
