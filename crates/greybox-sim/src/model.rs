//! What is simulated: particles, material, tools, boundary groups and numerical settings.

use crate::particles::Particles;
use crate::tool::Tool;
use greybox_material::Material;
use serde::{Deserialize, Serialize};

/// Numerical settings. Defaults follow the ETH IWF SPH cutting recipe (Röthlin et al. 2019;
/// Afrasiabi et al. 2019) where it states a value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Numerics {
    /// Smoothing length over particle spacing, h/Δx.
    pub smoothing_ratio: f64,
    /// Courant number: Δt = cfl · h / (c + v_max), with c the longitudinal wave speed.
    pub cfl: f64,
    /// Monaghan artificial viscosity α (linear) and β (quadratic).
    pub av_alpha: f64,
    pub av_beta: f64,
    /// Gray–Monaghan artificial stress ε (exponent 4).
    pub artificial_stress: f64,
    /// XSPH velocity smoothing ε.
    pub xsph: f64,
    /// Penalty factor α of the contact force f_N = α m g / Δt².
    pub contact_penalty: f64,
    /// Share of the friction work that heats the workpiece (the tool is rigid and adiabatic).
    pub friction_heat_share: f64,
    /// Mass scaling factor (≥ 1): density and masses × f, so Δt × √f; heat capacity per
    /// volume is kept physical.
    pub mass_scaling: f64,
    /// Factor applied to the strain rate seen by the flow stress (for time-scaled quasi-static
    /// runs: physical speed / simulated speed; 1 = physical).
    pub strain_rate_scale: f64,
    /// Heat conduction and heating on/off (off: isothermal).
    pub thermal: bool,
    /// Verlet skin over h. Small is fast: a rebuild costs about one step, and at cutting
    /// speeds particles cross half of a 0.05 h skin in ~40 steps, while every pair in the
    /// skin costs work in every step (0.05 h: 3 % of the list entries; 0.3 h: 25 %).
    pub skin_ratio: f64,
    /// Instability guard: stop when a particle moves faster than this × the wave speed.
    pub max_speed_ratio: f64,
    /// Most particles a set-up may lay out (default [`DEFAULT_MAX_PARTICLES`], 5 million:
    /// about 20 GB at [`BYTES_PER_PARTICLE`]). The count follows from the spacing and the
    /// workpiece before anything is allocated; a finer set-up is refused unless this is
    /// raised. Unset, it is not written out (case ids and files of earlier runs stay).
    ///
    /// [`DEFAULT_MAX_PARTICLES`]: crate::particles::DEFAULT_MAX_PARTICLES
    /// [`BYTES_PER_PARTICLE`]: crate::particles::BYTES_PER_PARTICLE
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_particles: Option<ParticleCap>,
    /// Most time steps a run may take (default [`DEFAULT_MAX_STEPS`], 10⁸: about a day at
    /// the IWF case's size). The count follows from the duration and the stable time step
    /// before the first step; a cutting speed typed in m/min where m/s was meant would
    /// otherwise run for months. Unset, it is not written out.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_steps: Option<StepCap>,
    /// Local time stepping in a refined model (default off): the particles of the finest
    /// level and those near a tool take every step Δt, the coarser ones one step of 2Δt per
    /// two, with the pair impulses between the two exchanged so that momentum stays exact
    /// (see the solver's `multirate` module and docs/cutting.md, "Local time stepping").
    /// Without a refinement every particle is on the finest level and it changes nothing.
    /// Unset (off), it is not written out.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub local_time_stepping: bool,
}

/// Values `numerics.max_particles` may be raised to: 10⁹ particles are about 4 TB.
pub type ParticleCap = greybox_core::count::Count<1, 1_000_000_000>;
/// Values `numerics.max_steps` may be raised to.
pub type StepCap = greybox_core::count::Count<1, 1_000_000_000_000>;

/// Default of `numerics.max_steps`.
pub const DEFAULT_MAX_STEPS: u64 = 100_000_000;

impl Default for Numerics {
    fn default() -> Self {
        Numerics {
            smoothing_ratio: 1.5,
            cfl: 0.5,
            av_alpha: 1.0,
            av_beta: 1.0,
            artificial_stress: 0.3,
            xsph: 0.5,
            contact_penalty: 0.1,
            friction_heat_share: 1.0,
            mass_scaling: 1.0,
            strain_rate_scale: 1.0,
            thermal: true,
            skin_ratio: 0.05,
            max_speed_ratio: 0.5,
            max_particles: None,
            max_steps: None,
            local_time_stepping: false,
        }
    }
}

impl Numerics {
    pub fn validate(&self) -> greybox_core::Result<()> {
        greybox_core::rules::Rules::new("numerics")
            .within("smoothing_ratio", self.smoothing_ratio, 1.0, 3.0)
            .above_up_to("cfl", self.cfl, 0.0, 1.0)
            .non_negative("av_alpha", self.av_alpha)
            .non_negative("av_beta", self.av_beta)
            .within("artificial_stress", self.artificial_stress, 0.0, 1.0)
            .within("xsph", self.xsph, 0.0, 1.0)
            .above_up_to("contact_penalty", self.contact_penalty, 0.0, 1.0)
            .within("friction_heat_share", self.friction_heat_share, 0.0, 1.0)
            .physics(
                "mass_scaling",
                greybox_core::physics::Quantity::MassScaling,
                self.mass_scaling,
            )
            .positive("strain_rate_scale", self.strain_rate_scale)
            .positive("skin_ratio", self.skin_ratio)
            .positive("max_speed_ratio", self.max_speed_ratio)
            .finish()
    }
}

/// A group of particles with prescribed velocity components (None = free in that direction).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BoundaryGroup {
    pub name: String,
    pub vx: Option<f64>,
    pub vy: Option<f64>,
}

/// Everything the solver needs to start.
#[derive(Debug, Clone)]
pub struct Model {
    pub particles: Particles,
    pub material: Material,
    pub tools: Vec<Tool>,
    /// Boundary groups; particle group k ≥ 1 refers to `groups[k − 1]`.
    pub groups: Vec<BoundaryGroup>,
    pub numerics: Numerics,
    /// Regions, moving with a tool, where particles are split (`None`: one spacing).
    pub refinement: Option<crate::refine::Refinement>,
    /// The line above which free particles leave the model (`None`: none leave; see
    /// [`crate::sink`]).
    pub sink: Option<crate::sink::Sink>,
}
