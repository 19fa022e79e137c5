//! Rigid tools: a shape, a prescribed motion and friction windows along the surface.

use crate::geometry::RoundedPolygon;
use greybox_core::{ContactState, FrictionLaw};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Prescribed velocity in segments: segment k lasts `duration_s`; during its first `ramp_s`
/// seconds the velocity goes linearly from the previous segment's velocity (0 before the
/// first) to `velocity`, then stays there. After the last segment the tool keeps the last
/// velocity. Ramps avoid exciting the particle-scale stick–slip oscillation that a sudden
/// start of sliding sets off.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    pub segments: Vec<MotionSegment>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MotionSegment {
    pub duration_s: f64,
    pub velocity: [f64; 2],
    #[serde(default)]
    pub ramp_s: f64,
}

impl Motion {
    pub fn constant(velocity: [f64; 2]) -> Self {
        Motion {
            segments: vec![MotionSegment {
                duration_s: f64::INFINITY,
                velocity,
                ramp_s: 0.0,
            }],
        }
    }

    /// Velocity at time t, m/s.
    pub fn velocity(&self, t: f64) -> [f64; 2] {
        let mut t0 = 0.0;
        let mut prev = [0.0, 0.0];
        for s in &self.segments {
            if t < t0 + s.duration_s {
                let tau = t - t0;
                if tau < s.ramp_s {
                    let f = tau / s.ramp_s;
                    return [
                        prev[0] + f * (s.velocity[0] - prev[0]),
                        prev[1] + f * (s.velocity[1] - prev[1]),
                    ];
                }
                return s.velocity;
            }
            t0 += s.duration_s;
            prev = s.velocity;
        }
        self.segments.last().map_or([0.0, 0.0], |s| s.velocity)
    }

    /// Total duration of the finite segments, s.
    pub fn duration(&self) -> f64 {
        self.segments.iter().map(|s| s.duration_s).sum()
    }
}

/// Time-integrated contact statistics of one friction window (sums over steps and contact
/// particles; divide as in [`WindowStats`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct WindowAccumulator {
    /// Number of steps accumulated.
    pub steps: u64,
    /// Σ particle-steps in contact, each particle weighted by its spacing over the level-0
    /// spacing Δx (1 in an unrefined model), so that contacts · Δx is the contact length.
    pub contacts: f64,
    /// Σ f_N, N/m.
    pub normal: f64,
    /// Σ |f_t|, N/m.
    pub tangential: f64,
    /// Σ f_N |v_slip|, N/m · m/s.
    pub normal_x_slip: f64,
    /// Σ f_N T, N/m · K.
    pub normal_x_temp: f64,
    /// Σ particle-steps slipping (weighted as `contacts`).
    pub slipping: f64,
    /// Σ f_N T_tool, N/m · K (thermal tools only).
    #[serde(default)]
    pub normal_x_tool_temp: f64,
}

/// Time-averaged state of a window over an accumulation interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WindowStats {
    /// Mean contact pressure where in contact, Pa (Σ f_N / (Σ contacts · Δx)): what a node
    /// in contact sees, and what the friction law is evaluated at.
    pub pressure_pa: f64,
    /// Normal stress averaged over the whole window and interval, Pa (Σ f_N / (steps · L)):
    /// the continuum contact-stress profile, which falls to zero where contact becomes
    /// intermittent (= pressure × contact fraction).
    pub normal_stress_pa: f64,
    /// Force-weighted mean sliding velocity, m/s.
    pub sliding_velocity_m_s: f64,
    /// Force-weighted mean temperature, K.
    pub temperature_k: f64,
    /// Mean frictional shear stress where in contact, Pa.
    pub shear_stress_pa: f64,
    /// Effective μ = Σ|f_t| / Σ f_N.
    pub mu_effective: f64,
    /// Mean fraction of the window length in contact.
    pub contact_fraction: f64,
    /// Fraction of contact particle-steps that slipped.
    pub slip_fraction: f64,
    /// Force-weighted mean tool surface temperature, K (thermal tools only).
    #[serde(default)]
    pub tool_temperature_k: Option<f64>,
}

impl WindowStats {
    /// The contact state a friction law is evaluated at: the pressure where in contact, the
    /// force-weighted sliding velocity and temperature.
    pub fn contact_state(&self) -> ContactState {
        ContactState {
            pressure_pa: self.pressure_pa,
            sliding_velocity_m_s: self.sliding_velocity_m_s,
            temperature_k: self.temperature_k,
        }
    }
}

impl WindowAccumulator {
    /// Adds the sums of another interval.
    pub fn add(&mut self, o: &WindowAccumulator) {
        self.steps += o.steps;
        self.contacts += o.contacts;
        self.normal += o.normal;
        self.tangential += o.tangential;
        self.normal_x_slip += o.normal_x_slip;
        self.normal_x_temp += o.normal_x_temp;
        self.slipping += o.slipping;
        self.normal_x_tool_temp += o.normal_x_tool_temp;
    }

    /// Every sum times `w` (a weight for combining windows).
    pub fn scaled(&self, w: f64) -> WindowAccumulator {
        WindowAccumulator {
            steps: self.steps,
            contacts: w * self.contacts,
            normal: w * self.normal,
            tangential: w * self.tangential,
            normal_x_slip: w * self.normal_x_slip,
            normal_x_temp: w * self.normal_x_temp,
            slipping: w * self.slipping,
            normal_x_tool_temp: w * self.normal_x_tool_temp,
        }
    }

    /// Averages; `None` when the window saw no contact.
    pub fn stats(&self, spacing: f64, window_length: f64) -> Option<WindowStats> {
        if self.contacts <= 0.0 || self.normal <= 0.0 {
            return None;
        }
        Some(WindowStats {
            pressure_pa: self.normal / (self.contacts * spacing),
            normal_stress_pa: self.normal / (self.steps.max(1) as f64 * window_length),
            sliding_velocity_m_s: self.normal_x_slip / self.normal,
            temperature_k: self.normal_x_temp / self.normal,
            shear_stress_pa: self.tangential / (self.contacts * spacing),
            mu_effective: self.tangential / self.normal,
            contact_fraction: (self.contacts * spacing
                / (self.steps.max(1) as f64 * window_length))
                .min(1.0),
            slip_fraction: self.slipping / self.contacts,
            tool_temperature_k: (self.normal_x_tool_temp > 0.0)
                .then(|| self.normal_x_tool_temp / self.normal),
        })
    }
}

/// A stretch [s_start, s_end) of the tool surface with its own friction law.
#[derive(Clone, Serialize, Deserialize)]
pub struct Window {
    pub s_start: f64,
    pub s_end: f64,
    /// The law (not serialised; rebuilt from the configuration on resume).
    #[serde(skip, default = "default_law")]
    pub law: Arc<dyn FrictionLaw>,
    /// The μ the contact currently uses.
    pub mu: f64,
    pub acc: WindowAccumulator,
    /// The sums of the last interval the grey-box loop closed (what it set μ from), kept so
    /// that observers can read the contact of the loop's intervals
    /// ([`crate::steady::RunUntilSure`]).
    #[serde(default)]
    pub last_interval: WindowAccumulator,
}

fn default_law() -> Arc<dyn FrictionLaw> {
    Arc::new(ConstantMu(0.0))
}

impl std::fmt::Debug for Window {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Window")
            .field("s_start", &self.s_start)
            .field("s_end", &self.s_end)
            .field("law", &self.law.name())
            .field("mu", &self.mu)
            .finish()
    }
}

impl Window {
    /// A window whose μ starts as the law evaluated at `start`.
    pub fn new(s_start: f64, s_end: f64, law: Arc<dyn FrictionLaw>, start: &ContactState) -> Self {
        let mu = law.mu(start);
        Window {
            s_start,
            s_end,
            law,
            mu,
            acc: WindowAccumulator::default(),
            last_interval: WindowAccumulator::default(),
        }
    }
    pub fn length(&self) -> f64 {
        self.s_end - self.s_start
    }
}

/// Constant Coulomb μ (the solver's own minimal law; any `FrictionLaw` can be used).
#[derive(Debug, Clone, Copy)]
pub struct ConstantMu(pub f64);

impl FrictionLaw for ConstantMu {
    fn name(&self) -> String {
        format!("Coulomb mu = {}", self.0)
    }
    fn mu(&self, _: &ContactState) -> f64 {
        self.0
    }
}

/// A rigid tool.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Tool {
    pub name: String,
    pub shape: RoundedPolygon,
    /// Translation of the local frame, m.
    pub position: [f64; 2],
    pub motion: Motion,
    /// Windows sorted by s, non-overlapping; surface outside every window is frictionless.
    pub windows: Vec<Window>,
    /// Force of the workpiece on the tool in the last step, N/m.
    pub force: [f64; 2],
    /// Number of particles in contact in the last step.
    pub contacts: usize,
    /// Heat conduction in the tool; `None`: adiabatic (no heat enters the tool).
    #[serde(default)]
    pub thermal: Option<crate::tool_thermal::ToolThermal>,
    /// The step at which the grey-box loop last closed an interval (each window's
    /// [`Window::last_interval`] holds its sums); `None` before the first close. Observers
    /// read the loop's intervals when it equals the current step, whatever the loop's cadence.
    #[serde(default)]
    pub last_close_step: Option<u64>,
    /// The limiting shear stress of the contact, Pa: a particle's friction force is at most
    /// τ_max times its share of the surface (its spacing), besides μ f_N (`None`: Coulomb
    /// alone; [`crate::cutting::FrictionSetup::shear_limit_pa`]).
    #[serde(default)]
    pub shear_limit_pa: Option<f64>,
}

impl Tool {
    /// A tool with one window covering the whole surface.
    pub fn with_uniform_law(
        name: &str,
        shape: RoundedPolygon,
        position: [f64; 2],
        motion: Motion,
        law: Arc<dyn FrictionLaw>,
    ) -> Self {
        let w = Window::new(
            0.0,
            shape.perimeter() + 1e-12,
            law,
            &ContactState::new(0.0, 0.0),
        );
        Tool {
            name: name.into(),
            shape,
            position,
            motion,
            windows: vec![w],
            force: [0.0, 0.0],
            contacts: 0,
            thermal: None,
            last_close_step: None,
            shear_limit_pa: None,
        }
    }

    /// Index of the window containing arc length s.
    #[inline]
    pub fn window_at(&self, s: f64) -> Option<usize> {
        let k = self.windows.partition_point(|w| w.s_end <= s);
        (k < self.windows.len() && self.windows[k].s_start <= s).then_some(k)
    }

    /// Checks that windows are ordered, non-overlapping and have finite μ ≥ 0.
    pub fn validate(&self) -> greybox_core::Result<()> {
        for (k, w) in self.windows.iter().enumerate() {
            if w.s_end.partial_cmp(&w.s_start) != Some(std::cmp::Ordering::Greater)
                || w.mu.is_nan()
                || w.mu < 0.0
                || !w.mu.is_finite()
            {
                return Err(greybox_core::Error::invalid(
                    format!("tool '{}', window {k}", self.name),
                    format!(
                        "expected s_end > s_start and finite μ ≥ 0, got [{}, {}) μ = {}",
                        w.s_start, w.s_end, w.mu
                    ),
                ));
            }
            if k > 0 && w.s_start < self.windows[k - 1].s_end {
                return Err(greybox_core::Error::invalid(
                    format!("tool '{}', window {k}", self.name),
                    "windows overlap or are not sorted by s",
                ));
            }
        }
        Ok(())
    }
}
