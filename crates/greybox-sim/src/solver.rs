//! The explicit SPH solver: one [`Solver::step`] advances the state by Δt.
//!
//! Per step (Röthlin et al., Int J Adv Manuf Technol 2019; Gray, Monaghan & Swift, CMAME 190,
//! 2001; Libersky & Petschek 1991):
//! 1. rebuild the Verlet lists if a particle moved more than half the skin;
//! 2. per particle: pack σ/ρ², m/ρ, the artificial stress R and the conductivity (pure map);
//! 3. forces and conduction over the symmetric half list (each pair once; the kernel values
//!    of each pair are cached for step 6): (a) a pass over every particle's own row sums its
//!    share and writes the partner's share (equal and opposite force — all particles have
//!    the same mass — and opposite heat flow) into a per-pair slot; (b) every particle adds
//!    the slots of its incoming pairs through the reverse lists. No two threads write the
//!    same memory and every sum runs in a fixed order: the same bytes on any thread count.
//!    * momentum    dv_i/dt = Σ_j m (σ_i/ρ_i² + σ_j/ρ_j² − Π_ij I + f_ij⁴ (R_i + R_j))·∇_i W_ij,
//!    * Brookshaw   ρ c dT/dt = Σ_j (m/ρ_j)(k_i + k_j)(T_i − T_j) r_ij·∇_i W_ij / (r² + 0.01h²);
//! 4. rigid-tool contact: penalty f_N = α m g/Δt², incremental Coulomb friction per window;
//! 5. kick: v ← v + Δt a, prescribed velocities;
//! 6. kinematics gather with the *new* velocities (own row and incoming pairs):
//!    * continuity  dρ_i/dt = Σ_j m (v_i − v_j)·∇_i W_ij,
//!    * velocity gradient L_i = Σ_j (m/ρ_j)(v_j − v_i) ⊗ ∇_i W_ij,
//!    * XSPH        v̂_i = v_i + ε Σ_j (m/ρ̄_ij)(v_j − v_i) W_ij, 1/ρ̄_ij = (1/ρ_i + 1/ρ_j)/2;
//! 7. drift and constitutive update: x ← x + Δt v̂, ρ ← ρ + Δt ρ̇, p = c₀²(ρ − ρ₀), Jaumann
//!    stress rate, Johnson–Cook radial return, heating;
//! 8. the tools move; energies are booked; non-finite or runaway states stop the run.
//!
//! A step while the particles are exactly at rest and no tool touches them does steps 4 and
//! 8 only (see [`Solver::step`]). With `numerics.local_time_stepping` in a refined model the
//! coarse particles away from the tools take one step of 2Δt per two steps, the pair
//! impulses exchanged so that momentum stays exact (the `multirate` module; docs/simulator.md,
//! "Local time stepping").
//!
//! Steps 5–7 make the velocity–stress update symplectic (the stress rate uses v_{n+1}):
//! evaluating both from the old state is forward Euler for the elastic wave equation, which
//! amplifies every mode and is only kept alive by artificial viscosity at small Courant numbers.

use crate::coarsen;
use crate::contact;
use crate::kernel::{CubicSpline, PairTable};
use crate::model::{Model, Numerics};
use crate::neighbours::NeighbourList;
use crate::pair_lanes::{ForceConstants, Packed};
use crate::particles::{spacing_factor, Particles, FREE};
use crate::rates::Rates;
use crate::refine::{self, Refinement};
use crate::sink::Sink;
use crate::tool::Tool;
use greybox_material::Material;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

mod multirate;
mod passes;
mod update;

use passes::{force_pass, incoming_pass, kinematics_pass, Advance, HeatInputs};

/// Particles per parallel task of the pair passes.
const PAIR_CHUNK: usize = 64;

/// Why a run stopped early.
///
/// The causes from other crates are kept as values (match [`SimError::Core`] or
/// [`SimError::Interrupted`], or downcast an `anyhow::Error` to `SimError`); the messages are
/// the causes' own.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A step produced a non-finite or runaway state.
    #[error(
        "simulation went unstable at step {step} (t = {time_s:.4e} s): particle {particle} {reason}; \
         try a smaller cfl, a larger smoothing_ratio or less mass scaling"
    )]
    Unstable {
        step: u64,
        time_s: f64,
        particle: usize,
        reason: String,
    },
    /// A set-up, checkpoint or result the simulator itself refuses, with its message.
    #[error("{0}")]
    Invalid(String),
    /// An error of the core library (an invalid set-up, a failed write), kept as it is.
    #[error(transparent)]
    Core(#[from] greybox_core::Error),
    /// The run was stopped on request ([`greybox_core::interrupt`]): "interrupted".
    #[error("interrupted")]
    Interrupted,
}

impl SimError {
    /// Whether the run was stopped on request rather than failing.
    pub fn is_interrupted(&self) -> bool {
        matches!(
            self,
            SimError::Interrupted | SimError::Core(greybox_core::Error::Interrupted)
        )
    }
}

impl From<greybox_core::interrupt::Interrupted> for SimError {
    fn from(_: greybox_core::interrupt::Interrupted) -> Self {
        SimError::Interrupted
    }
}

/// Energy book-keeping, J per metre of thickness (cumulative works).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyBook {
    /// Work done on the workpiece by the tools and the prescribed-velocity boundaries.
    pub external_work: f64,
    /// Plastic dissipation Σ (m/ρ) σ_y Δε_p.
    pub plastic_work: f64,
    /// Work of the tangential contact forces on the relative sliding (friction).
    pub friction_work: f64,
    /// Work of the normal penalty forces on the relative motion (≈ stored penalty energy).
    pub penalty_work: f64,
    /// Dissipation by artificial viscosity.
    pub viscous_work: f64,
    /// Heat into thermal tools (across the interface plus their share of friction heat).
    #[serde(default)]
    pub tool_heat: f64,
    /// Kinetic and elastic energy carried out of the model by particles a [`Sink`] removed.
    #[serde(default)]
    pub removed: f64,
    /// Particles a [`Sink`] removed.
    #[serde(default)]
    pub removed_particles: u64,
    /// Kinetic and elastic energy the merging of refined particles averaged out (see
    /// [`crate::coarsen`]).
    #[serde(default)]
    pub coarsened: f64,
    /// Particles merged away by coarsening (three per merge).
    #[serde(default)]
    pub coarsened_particles: u64,
}

/// Energies of a state, J/m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EnergyBalance {
    pub kinetic: f64,
    pub elastic: f64,
    pub plastic: f64,
    pub friction: f64,
    pub penalty: f64,
    pub viscous: f64,
    /// Carried out by removed particles (see [`crate::sink`]).
    pub removed: f64,
    /// Averaged out by merged particles (see [`crate::coarsen`]).
    pub coarsened: f64,
    pub external: f64,
    /// (kinetic + elastic + plastic + friction + penalty + viscous + removed + coarsened −
    /// external) / external.
    pub relative_error: f64,
}

/// Material constants derived once.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Derived {
    pub rho0: f64,
    pub shear: f64,
    /// c₀² = K/ρ₀ for the equation of state.
    pub c0_sq: f64,
    /// Longitudinal wave speed √((K + 4G/3)/ρ₀), m/s.
    pub c_long: f64,
}

/// What one step computes and the next overwrites: the per-particle and per-pair working
/// buffers of the passes, kept between steps only so that they are allocated once. None of
/// it is the run's state (a checkpoint saves none of it; [`Scratch::for_particles`] sizes it
/// afresh for a restored state).
#[derive(Debug, Clone, Default)]
pub(crate) struct Scratch {
    /// Per particle: the rates of steps 3–6 (accelerations, strain rates, heating).
    pub(crate) rates: Vec<Rates>,
    /// Per particle: the packed record the pair passes read (step 2).
    pub(crate) packed: Vec<Packed>,
    /// Per pair of the half list: W (1/m²) and (1/r) dW/dr (1/m⁴) at the current positions
    /// (computed by the force pass, reused by the kinematics pass).
    pub(crate) pair_wg: Vec<[f64; 2]>,
    /// Per pair: the second partner's share of the force pass — acceleration x, y (m/s²) and
    /// the conduction term ρ c dT/dt (W/m³) — gathered through the reverse lists.
    pub(crate) pair_force: Vec<[f64; 3]>,
    /// Per update chunk: (plastic work, viscous power, first bad particle, largest squared
    /// displacement since the last neighbour build).
    pub(crate) chunk_sums: Vec<(f64, f64, usize, f64)>,
}

impl Scratch {
    /// The per-particle buffers sized for `n` particles (the per-pair ones grow as needed).
    pub(crate) fn for_particles(&mut self, n: usize) {
        self.rates.resize(n, Rates::default());
        self.packed.resize(n, Packed::default());
    }
}

/// The solver: the run's state (particles, tools, boundary groups, time, step, energy book,
/// neighbour lists) and, apart from it, the step's working buffers ([`Scratch`]).
pub struct Solver {
    pub particles: Particles,
    pub material: Material,
    pub tools: Vec<Tool>,
    pub groups: Vec<crate::model::BoundaryGroup>,
    pub numerics: Numerics,
    /// The kernel of the level-0 particles (every particle's in a uniform model).
    pub kernel: CubicSpline,
    /// The pair table: of `kernel` in a uniform model, of the unit kernel (h = 1) in a refined
    /// one (see [`crate::pair_lanes::force_row`]).
    table: PairTable,
    pub neighbours: NeighbourList,
    /// The regions where particles are split (see [`crate::refine`]).
    pub refinement: Option<Refinement>,
    /// The line above which free particles leave the model (see [`crate::sink`]).
    pub sink: Option<Sink>,
    /// Whether the pair passes use per-particle masses and smoothing lengths: with a
    /// refinement, or when the particles were refined (a restored state).
    pub(crate) refined: bool,
    pub(crate) derived: Derived,
    /// Time step, s.
    pub dt: f64,
    pub time: f64,
    pub step: u64,
    pub energy: EnergyBook,
    /// Reaction force of each boundary group on the body (force the boundary applies), N/m.
    pub group_force: Vec<[f64; 2]>,
    /// The step's working buffers (see [`Scratch`]): no part of the run's state.
    pub(crate) scratch: Scratch,
    /// Set by the update when a particle moved more than half the skin.
    rebuild_due: bool,
    /// Reciprocal of W(Δx) for the artificial-stress factor f = W(r)/W(Δx).
    inv_w_dx: f64,
    /// The particles are exactly at rest (see [`Solver::step`]); false once a step has done
    /// work, for good.
    at_rest: bool,
    /// Steps that skipped the particle passes because nothing could move (see
    /// [`Solver::step`]).
    pub idle_steps: u64,
    /// Σ particles over the steps that did the particle passes (a refined run's count grows;
    /// with local time stepping a slow particle counts once per two steps).
    pub particle_steps: u64,
    /// Local time stepping's state (see [`multirate`]); `None`: every particle takes every
    /// step.
    multirate: Option<multirate::Multirate>,
    /// The step the latest coarse step started at (see [`Solver::at_sync`]).
    sync_step: u64,
}

impl Solver {
    /// Checks the model, applies mass scaling, builds neighbour lists and sets Δt.
    pub fn new(model: Model) -> Result<Self, SimError> {
        let Model {
            mut particles,
            material,
            tools,
            groups,
            numerics,
            refinement,
            sink,
        } = model;
        numerics.validate()?;
        material.validate()?;
        for t in &tools {
            t.validate()?;
        }
        if particles.is_empty() || !particles.check_lengths() {
            return Err(SimError::Invalid(
                "the model has no particles or inconsistent particle arrays".into(),
            ));
        }
        if let Some(r) = &refinement {
            r.validate(tools.len()).map_err(SimError::Invalid)?;
        }
        if let Some(s) = &sink {
            s.validate().map_err(SimError::Invalid)?;
        }
        if let Some(&g) = particles.group.iter().find(|&&g| g as usize > groups.len()) {
            return Err(SimError::Invalid(format!(
                "particle boundary group {g} does not exist ({} groups)",
                groups.len()
            )));
        }
        let f = numerics.mass_scaling;
        particles.mass *= f;
        particles.rho.iter_mut().for_each(|r| *r *= f);
        let rho0 = material.density_kg_m3 * f;
        let bulk = material.elastic.bulk_modulus();
        let shear = material.elastic.shear_modulus();
        let derived = Derived {
            rho0,
            shear,
            c0_sq: bulk / rho0,
            c_long: (material.elastic.p_wave_modulus() / rho0).sqrt(),
        };
        let kernel = CubicSpline::new(numerics.smoothing_ratio * particles.spacing);
        let refined = refinement.is_some() || particles.is_refined();
        let h_min = kernel.h * spacing_factor(finest_level(&particles, refinement.as_ref()));
        let neighbours = NeighbourList::new(kernel.radius(), numerics.skin_ratio * h_min);
        let (table, inv_w_dx) = pair_table(&kernel, refined, &numerics, particles.spacing);
        let vmax_tool = tools
            .iter()
            .flat_map(|t| t.motion.segments.iter())
            .map(|s| s.velocity[0].hypot(s.velocity[1]))
            .fold(0.0, f64::max);
        let dt = numerics.cfl * h_min / (derived.c_long + vmax_tool);
        let mut tools = tools;
        for t in tools.iter_mut() {
            if let Some(tt) = t.thermal.as_mut() {
                tt.set_solver_step(dt, particles.spacing);
            }
        }
        let n = particles.len();
        let ngroups = groups.len();
        let multirate =
            (numerics.local_time_stepping && refined).then(multirate::Multirate::default);
        let mut solver = Solver {
            inv_w_dx,
            particles,
            material,
            tools,
            groups,
            numerics,
            table,
            kernel,
            neighbours,
            refinement,
            sink,
            refined,
            derived,
            dt,
            time: 0.0,
            step: 0,
            energy: EnergyBook::default(),
            group_force: vec![[0.0; 2]; ngroups],
            scratch: Scratch {
                rates: vec![Rates::default(); n],
                packed: vec![Packed::default(); n],
                ..Scratch::default()
            },
            rebuild_due: false,
            at_rest: false,
            idle_steps: 0,
            particle_steps: 0,
            multirate,
            sync_step: 0,
        };
        solver.rebuild_lists();
        solver.check_rest();
        Ok(solver)
    }

    /// Rebuilds the neighbour lists at the current positions (per-pair cut-offs in a refined
    /// model). The displacement that made a rebuild due is then measured from here: a
    /// checkpoint's rebuild clears it as a resumed run's does, so that both make the next
    /// rebuild (and the splits, merges and removals that wait for it) at the same step.
    pub(crate) fn rebuild_lists(&mut self) {
        self.rebuild_due = false;
        let p = &self.particles;
        if self.refined {
            let h0 = self.kernel.h;
            let h: Vec<f64> = p.level.iter().map(|&l| h0 * spacing_factor(l)).collect();
            self.neighbours.build_with_reach(&p.x, &p.y, Some(&h));
        } else {
            self.neighbours.build(&p.x, &p.y);
        }
    }

    /// Splits the particles inside the refinement regions at the tools' current positions
    /// (see [`crate::refine`]); returns whether any particle was split (the per-particle
    /// arrays have then grown and the neighbour lists must be rebuilt).
    fn refine(&mut self) -> bool {
        let Some(r) = &self.refinement else {
            return false;
        };
        let origin = self.tools[r.tool].position;
        if refine::split_in_regions(&mut self.particles, r, origin) == 0 {
            return false;
        }
        let n = self.particles.len();
        self.scratch.for_particles(n);
        true
    }

    /// Merges the refined particles in the coarsening regions at the tools' current positions
    /// (see [`crate::coarsen`]), finest level first, booking the kinetic and elastic energy
    /// the merges average out (the per-particle arrays may shrink: called just before the
    /// neighbour lists are rebuilt).
    fn coarsen(&mut self) {
        let Some((tool, finest)) = self
            .refinement
            .as_ref()
            .filter(|r| r.coarsening.is_some())
            .map(|r| (r.tool, r.finest_level()))
        else {
            return;
        };
        let origin = self.tools[tool].position;
        let mut merged = false;
        for level in (1..=finest).rev() {
            let groups = match self.refinement.as_ref().and_then(|r| r.coarsening.as_ref()) {
                Some(c) => coarsen::merge_groups(&self.particles, level, c, origin),
                None => Vec::new(),
            };
            if groups.is_empty() {
                continue;
            }
            // in group order, serially: the same bytes whatever the thread count
            let energy = |s: &Solver, k: usize| {
                let (kinetic, elastic) = s.particle_energy(k);
                kinetic + elastic
            };
            let before: f64 = groups.iter().flatten().map(|&k| energy(self, k)).sum();
            let keep = coarsen::merge(&mut self.particles, &groups);
            let after: f64 = groups.iter().map(|g| energy(self, g[0])).sum();
            self.energy.coarsened += before - after;
            self.energy.coarsened_particles += self.particles.retain(&keep) as u64;
            merged = true;
        }
        if merged {
            let n = self.particles.len();
            self.scratch.for_particles(n);
        }
    }

    /// Notes whether the particles are exactly at rest — unstressed, at ρ₀ and one
    /// temperature, the boundary groups holding still — so that the steps before a tool
    /// first touches them skip the particle passes; called on a new or restored state.
    pub(crate) fn check_rest(&mut self) {
        let groups_hold_still = self
            .groups
            .iter()
            .all(|g| g.vx.unwrap_or(0.0) == 0.0 && g.vy.unwrap_or(0.0) == 0.0);
        self.at_rest = groups_hold_still && self.particles.at_rest(self.derived.rho0);
    }

    /// Whether a step from the current state is idle: the particles are at rest (every pair
    /// term, the kick and the update would be exact zeros) and no particle touches a tool
    /// (contact's own test, so no contact force arises).
    fn idle(&self) -> bool {
        self.at_rest && !contact::any(&self.tools, &self.particles, self.kernel.h)
    }

    /// Longitudinal elastic wave speed used for the time step (with mass scaling), m/s.
    pub fn wave_speed(&self) -> f64 {
        self.derived.c_long
    }

    /// Advances one step (with local time stepping, the first or the second step of a
    /// coarse step: see [`Solver::at_sync`] and docs/simulator.md, "Local time stepping").
    ///
    /// While the particles are exactly at rest and no particle touches a tool (the approach
    /// before the first contact), a step does only its bookkeeping — contact (which
    /// finds no particle, but counts the windows' steps and sub-steps a thermal tool), the
    /// boundary reactions (zero) and the clock — because its particle passes would leave
    /// every value as it is (they add exact zeros; only the sign of a zero velocity could
    /// differ). The first step that is not idle ends this for good.
    pub fn step(&mut self) -> Result<(), SimError> {
        if self.at_sync() {
            self.sync_step = self.step;
        }
        // The regions follow the tool during the approach too: a particle split only once
        // it touched the tool would put its children up to half its spacing inside it.
        // Children of particles at rest are at rest, so the approach stays idle.
        if self.at_rest && self.refine() {
            self.rebuild_due = true;
        }
        if self.idle() {
            self.apply_contact();
            self.book_boundaries(Advance::All);
            self.advance_clock();
            self.idle_steps += 1;
            return Ok(());
        }
        self.at_rest = false;
        if self.multirate.is_some() {
            return self.multirate_step();
        }
        self.prepare_lists();
        self.pack();
        self.gather_forces();
        self.apply_contact();
        self.book_boundaries(Advance::All);
        self.kick(Advance::All);
        self.gather_kinematics();
        self.update(Advance::All)?;
        self.advance_clock();
        self.particle_steps += self.particles.len() as u64;
        Ok(())
    }

    /// Whether the state is at the end of a coarse step: always without local time
    /// stepping; with it, after the second of a coarse step's two steps (between them the
    /// slow particles lag one step behind). Checkpoints, failure snapshots, stops on request
    /// and the ends of runs happen only here.
    pub fn at_sync(&self) -> bool {
        self.multirate.as_ref().is_none_or(|m| !m.mid_step())
    }

    /// The step the latest coarse step started at: `step − 1` after a step without local
    /// time stepping, `step − 2` at the end of a coarse step with it.
    pub fn sync_step(&self) -> u64 {
        self.sync_step
    }

    /// Splits, merges, removes and rebuilds the neighbour lists as the step's start needs.
    ///
    /// Splitting, merging and removal change the particle arrays, so the lists must be
    /// rebuilt after them; they wait for the rebuild that the particles' motion makes due
    /// (some particle moved half the skin), instead of each forcing one of its own. A
    /// particle therefore splits, merges or leaves at most one list's life late: a few tens
    /// of steps, in which the tool moves well under a micrometre (the regions reach
    /// 0.1–0.3 mm round the edge) and the chip rises well under the skin. On the refined
    /// Ti6Al4V template cut they forced three rebuilds in five (5 500 in all, 10 % of the
    /// cut's time). They depend only on the state at a rebuild, which a checkpoint's own
    /// rebuild and a resumed run's share: resume stays bit for bit.
    fn prepare_lists(&mut self) {
        // The displacement test runs inside the previous update; a restored solver (lists
        // built for other positions) is checked here, and a new run's first step splits
        // what its regions hold (a rebuild at the positions the lists were built at gives
        // the same lists).
        let due = self.rebuild_due
            || self.step == 0
            || self.neighbours.reference().0.len() != self.particles.len()
                && self
                    .neighbours
                    .needs_rebuild(&self.particles.x, &self.particles.y);
        if due {
            self.refine();
            self.coarsen();
            self.sink();
            self.rebuild_lists();
        }
    }

    /// Step 8's motion: the tools move by their velocity at the step's start, the clock by Δt.
    fn advance_clock(&mut self) {
        let t = self.time;
        let dt = self.dt;
        for tool in &mut self.tools {
            let v = tool.motion.velocity(t);
            tool.position[0] += v[0] * dt;
            tool.position[1] += v[1] * dt;
        }
        self.time += dt;
        self.step += 1;
    }

    /// Step 2: the per-particle packed record.
    fn pack(&mut self) {
        let p = &self.particles;
        let eps = self.numerics.artificial_stress;
        let th = &self.material.thermal;
        let thermal = self.numerics.thermal;
        let h0 = self.kernel.h;
        self.scratch
            .packed
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, q)| {
                let m = p.mass_of(i);
                let rho = p.rho[i];
                let ir2 = 1.0 / (rho * rho);
                let sxx = p.sxx[i] - p.p[i];
                let syy = p.syy[i] - p.p[i];
                let sxy = p.sxy[i];
                // Gray–Monaghan artificial stress: principal tensile stresses σ' > 0 get R' = −ε σ'/ρ².
                let (mut rxx, mut rxy, mut ryy) = (0.0, 0.0, 0.0);
                if eps > 0.0 {
                    let c = 0.5 * (sxx + syy);
                    let d = 0.5 * (sxx - syy);
                    // sqrt, not hypot: stresses are far from overflow and hypot is slow.
                    let r = (d * d + sxy * sxy).sqrt();
                    let (s1, s2) = (c + r, c - r);
                    if s1 > 0.0 {
                        let r1 = -eps * s1 * ir2;
                        let r2 = if s2 > 0.0 { -eps * s2 * ir2 } else { 0.0 };
                        // Principal direction: cos 2θ = d/r, sin 2θ = sxy/r.
                        let (c2, s2t) = if r > 0.0 {
                            (d / r, sxy / r)
                        } else {
                            (1.0, 0.0)
                        };
                        let cc = 0.5 * (1.0 + c2);
                        let ss = 0.5 * (1.0 - c2);
                        rxx = r1 * cc + r2 * ss;
                        ryy = r1 * ss + r2 * cc;
                        rxy = (r1 - r2) * 0.5 * s2t;
                    }
                }
                *q = Packed {
                    x: p.x[i],
                    y: p.y[i],
                    vx: p.vx[i],
                    vy: p.vy[i],
                    vol: m / rho,
                    inv_rho: 1.0 / rho,
                    m,
                    h: h0 * spacing_factor(p.level[i]),
                    txx: sxx * ir2,
                    txy: sxy * ir2,
                    tyy: syy * ir2,
                    rxx,
                    rxy,
                    ryy,
                    temp: p.temp[i],
                    k: if thermal {
                        th.conductivity.eval(p.temp[i])
                    } else {
                        0.0
                    },
                };
            });
    }

    /// Steps 3a and 3b over the neighbour lists into the step's rates and per-pair buffers.
    fn gather_forces(&mut self) {
        let mut sc = std::mem::take(&mut self.scratch);
        self.pair_forces(
            &sc.packed,
            &self.neighbours,
            &mut sc.rates,
            &mut sc.pair_wg,
            &mut sc.pair_force,
        );
        self.scratch = sc;
    }

    /// Steps 3a and 3b over `list` into `rates` (see [`force_pass`], [`incoming_pass`]).
    fn pair_forces(
        &self,
        packed: &[Packed],
        list: &NeighbourList,
        rates: &mut [Rates],
        pair_wg: &mut Vec<[f64; 2]>,
        pair_force: &mut Vec<[f64; 3]>,
    ) {
        let constants = self.force_constants();
        force_pass(
            self.refined,
            &self.table,
            &constants,
            packed,
            list,
            rates,
            pair_wg,
            pair_force,
        );
        let heat = HeatInputs::of(&self.numerics, &self.material, &self.particles);
        incoming_pass(&heat, list, pair_force, rates);
    }

    /// The constants of the force pass.
    fn force_constants(&self) -> ForceConstants {
        ForceConstants {
            mass: self.particles.mass,
            alpha: self.numerics.av_alpha,
            beta: self.numerics.av_beta,
            c_long: self.derived.c_long,
            inv_w_dx: self.inv_w_dx,
            artificial_stress_on: if self.numerics.artificial_stress > 0.0 {
                1.0
            } else {
                0.0
            },
        }
    }

    /// Step 5: v ← v + Δt a with the prescribed velocity components imposed, for the
    /// particles `advance` moves (by their step).
    fn kick(&mut self, advance: Advance<'_>) {
        let dt = self.dt;
        let groups = &self.groups;
        let rates = &self.scratch.rates;
        let p = &mut self.particles;
        p.vx.par_iter_mut()
            .zip(p.vy.par_iter_mut())
            .zip(self.scratch.packed.par_iter_mut())
            .enumerate()
            .for_each(|(i, ((vx, vy), q))| {
                let Some(dt) = advance.step_of(i, dt) else {
                    return;
                };
                let mut nvx = *vx + dt * rates[i].ax;
                let mut nvy = *vy + dt * rates[i].ay;
                let g = p.group[i];
                if g != FREE {
                    let g = &groups[g as usize - 1];
                    if let Some(v) = g.vx {
                        nvx = v;
                    }
                    if let Some(v) = g.vy {
                        nvy = v;
                    }
                }
                *vx = nvx;
                *vy = nvy;
                q.vx = nvx;
                q.vy = nvy;
            });
    }

    /// Step 6: continuity, velocity gradient and XSPH from the new velocities (see
    /// [`kinematics_pass`]).
    fn gather_kinematics(&mut self) {
        let sc = &mut self.scratch;
        kinematics_pass(
            self.refined,
            self.particles.mass,
            &sc.packed,
            &self.neighbours,
            &sc.pair_wg,
            &mut sc.rates,
        );
    }

    /// Reaction forces and external work of the prescribed-velocity groups.
    /// Tool contact forces on the particles (see [`contact`]), and their work booked.
    fn apply_contact(&mut self) {
        let params = contact::ContactParams {
            dt: self.dt,
            time: self.time,
            penalty: self.numerics.contact_penalty,
            reach: self.kernel.h,
            heat_share: if self.numerics.thermal {
                self.numerics.friction_heat_share
            } else {
                0.0
            },
            mass_scaling: self.numerics.mass_scaling,
            thermal: &self.material.thermal,
            thermal_on: self.numerics.thermal,
            velocity_scale: self.numerics.strain_rate_scale,
        };
        let w = contact::apply(
            &params,
            &mut self.particles,
            &mut self.scratch.rates,
            &mut self.tools,
        );
        self.energy.friction_work += w.friction;
        self.energy.penalty_work += w.penalty;
        self.energy.external_work += w.external;
        self.energy.tool_heat += w.tool_heat;
    }

    ///
    /// Of the particles `advance` moves: the reaction is that of the step's accelerations,
    /// its work over each particle's own step (with local time stepping, the groups' force
    /// is that of the fast particles' latest step and the slow ones' coarse step together).
    fn book_boundaries(&mut self, advance: Advance<'_>) {
        if self.groups.is_empty() {
            return;
        }
        let p = &self.particles;
        for f in self.group_force.iter_mut() {
            *f = [0.0; 2];
        }
        // The reactions of the particles moved by Δt and (with local time stepping, in a
        // coarse step's second step) of those moved by 2Δt.
        let both = matches!(advance, Advance::Both(_));
        let mut slow_force = vec![[0.0; 2]; if both { self.groups.len() } else { 0 }];
        for i in 0..p.len() {
            let g = p.group[i];
            if g == FREE || advance.step_of(i, self.dt).is_none() {
                continue;
            }
            let forces = if advance.is_slow(i) {
                &mut slow_force
            } else {
                &mut self.group_force
            };
            let gf = &mut forces[g as usize - 1];
            let m = p.mass_of(i);
            gf[0] -= m * self.scratch.rates[i].ax;
            gf[1] -= m * self.scratch.rates[i].ay;
        }
        let work = |forces: &[[f64; 2]]| -> f64 {
            let mut w = 0.0;
            for (gf, g) in forces.iter().zip(&self.groups) {
                w += gf[0] * g.vx.unwrap_or(0.0) + gf[1] * g.vy.unwrap_or(0.0);
            }
            w
        };
        self.energy.external_work += work(&self.group_force) * self.dt;
        if both {
            self.energy.external_work += work(&slow_force) * 2.0 * self.dt;
            for (f, s) in self.group_force.iter_mut().zip(&slow_force) {
                f[0] += s[0];
                f[1] += s[1];
            }
        }
    }

    /// The error for the unstable particle `bad`: a non-finite state, a non-positive
    /// density or a speed above the allowed fraction of the wave speed.
    fn instability(&self, bad: usize) -> SimError {
        let p = &self.particles;
        let reason = if !(p.x[bad].is_finite() && p.rho[bad].is_finite() && p.sxx[bad].is_finite())
        {
            "has a non-finite state".to_string()
        } else if p.rho[bad] <= 0.0 {
            format!("has density {:.3e} kg/m³", p.rho[bad])
        } else {
            format!(
                "moves at {:.1} m/s, above {:.0} % of the wave speed {:.0} m/s",
                p.vx[bad].hypot(p.vy[bad]),
                100.0 * self.numerics.max_speed_ratio,
                self.derived.c_long
            )
        };
        SimError::Unstable {
            step: self.step,
            time_s: self.time,
            particle: bad,
            reason,
        }
    }

    /// The energy balance of the current state.
    pub fn energy_balance(&self) -> EnergyBalance {
        // Serial sum in particle order: the same bytes whatever the thread count.
        let (mut kin, mut ela) = (0.0, 0.0);
        for i in 0..self.particles.len() {
            let (k, e) = self.particle_energy(i);
            kin += k;
            ela += e;
        }
        let e = &self.energy;
        let stored = kin
            + ela
            + e.plastic_work
            + e.friction_work
            + e.penalty_work
            + e.viscous_work
            + e.removed
            + e.coarsened;
        EnergyBalance {
            kinetic: kin,
            elastic: ela,
            plastic: e.plastic_work,
            friction: e.friction_work,
            penalty: e.penalty_work,
            viscous: e.viscous_work,
            removed: e.removed,
            coarsened: e.coarsened,
            external: e.external_work,
            relative_error: (stored - e.external_work)
                / e.external_work.abs().max(f64::MIN_POSITIVE),
        }
    }

    /// Kinetic energy ½ m v² and elastic energy of particle `i`, J/m: the deviatoric
    /// (m/ρ) s:s / 4G plus the linear equation of state's m c₀² [ln(ρ/ρ₀) + ρ₀/ρ − 1]; of a
    /// damaged particle in tension, (1 − d) of the latter, as its pressure is (the share
    /// of its present degradation: the energy released as d grew under tension is not
    /// followed step by step).
    fn particle_energy(&self, i: usize) -> (f64, f64) {
        let p = &self.particles;
        let d = self.derived;
        let v2 = p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i];
        let rho = p.rho[i];
        let m = p.mass_of(i);
        let ss = p.sxx[i].powi(2) + p.syy[i].powi(2) + p.szz[i].powi(2) + 2.0 * p.sxy[i].powi(2);
        let mut vol_e = m * d.c0_sq * ((rho / d.rho0).ln() + d.rho0 / rho - 1.0);
        if let Some(damage) = &self.material.damage {
            vol_e *= damage.mean_stress_share(p.damage[i], rho < d.rho0);
        }
        (0.5 * m * v2, m / rho * ss / (4.0 * d.shear) + vol_e)
    }

    /// Removes the free particles above the sink's line (see [`crate::sink`]), booking the
    /// energy they carry (the per-particle arrays may shrink: called just before the
    /// neighbour lists are rebuilt).
    fn sink(&mut self) {
        let Some(keep) = self.sink.and_then(|s| s.keep(&self.particles)) else {
            return;
        };
        // in particle order, serially: the same bytes whatever the thread count
        for i in (0..keep.len()).filter(|&i| !keep[i]) {
            let (k, e) = self.particle_energy(i);
            self.energy.removed += k + e;
        }
        self.energy.removed_particles += self.particles.retain(&keep) as u64;
        let n = self.particles.len();
        self.scratch.for_particles(n);
    }

    /// Particle-steps per second helper: particle count.
    pub fn particle_count(&self) -> usize {
        self.particles.len()
    }
}

/// The finest level any particle has or can reach: it sets the skin and the time step.
fn finest_level(particles: &Particles, refinement: Option<&Refinement>) -> u8 {
    refinement
        .map_or(0, Refinement::finest_level)
        .max(particles.level.iter().copied().max().unwrap_or(0))
}

/// The pair table and 1/W(Δx) of the artificial-stress factor: of `kernel` (spacing Δx =
/// `spacing`) in a uniform model, of the unit kernel (h = 1, Δx = 1/smoothing ratio) in a
/// `refined` one, whose pairs scale it by their own h_ij (see
/// [`crate::pair_lanes::force_row`]).
fn pair_table(
    kernel: &CubicSpline,
    refined: bool,
    numerics: &Numerics,
    spacing: f64,
) -> (PairTable, f64) {
    if refined {
        let unit = CubicSpline::new(1.0);
        let inv_w_dx = 1.0 / unit.w(1.0 / numerics.smoothing_ratio);
        (PairTable::new(&unit), inv_w_dx)
    } else {
        (PairTable::new(kernel), 1.0 / kernel.w(spacing))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cutting::InsertGeometry;
    use crate::model::BoundaryGroup;
    use crate::tool::{ConstantMu, Motion};
    use std::sync::Arc;

    /// A block at rest with its base clamped, and an insert starting 5 spacings to its right,
    /// moving left at 10 m/s, 20 µm deep.
    fn approach_model() -> Model {
        let dx = 20e-6;
        let (nx, ny) = (20, 10);
        let material = Material::aisi1045_article();
        let mut particles = Particles::block(0.0, 0.0, nx, ny, dx, material.density_kg_m3, 293.15);
        for i in 0..nx {
            particles.group[i] = 1;
        }
        let shape = InsertGeometry {
            rake_deg: 0.0,
            clearance_deg: 7.0,
            edge_radius_m: 10e-6,
            rake_length_m: 0.2e-3,
            flank_length_m: 0.1e-3,
        }
        .shape()
        .unwrap();
        let (lo, _) = shape.bounding_box();
        let lowest = shape.closest([0.0, -1.0]).distance - 1.0;
        let position = [
            nx as f64 * dx + 5.0 * dx - lo[0],
            ny as f64 * dx - dx - lowest,
        ];
        let tool = Tool::with_uniform_law(
            "insert",
            shape,
            position,
            Motion::constant([-10.0, 0.0]),
            Arc::new(ConstantMu(0.3)),
        );
        Model {
            particles,
            material,
            tools: vec![tool],
            groups: vec![BoundaryGroup {
                name: "base".into(),
                vx: Some(0.0),
                vy: Some(0.0),
            }],
            numerics: Numerics {
                mass_scaling: 100.0,
                ..Numerics::default()
            },
            refinement: None,
            sink: None,
        }
    }

    /// The steps of the approach skip the particle passes, and the run is the one that does
    /// every pass: every value equal (a zero's sign aside), through and after first contact.
    #[test]
    fn idle_approach_steps_change_nothing() {
        idle_approach_changes_nothing(approach_model);
    }

    /// The same with a refinement region that reaches the block before the tool does: the
    /// approach splits the particles as the region passes them, as the full run does, and
    /// not all at once when the first coarse particle touches the tool (which put children
    /// up to half a spacing inside it).
    #[test]
    fn a_refined_approach_splits_as_the_full_run_does() {
        let refined = || {
            let mut m = approach_model();
            let dx = m.particles.spacing;
            m.refinement = Some(crate::refine::Refinement {
                tool: 0,
                regions: vec![crate::refine::Region {
                    x_min: -4.0 * dx,
                    x_max: dx,
                    y_min: -3.0 * dx,
                    y_max: 6.0 * dx,
                }],
                pattern: Default::default(),
                coarsening: None,
            });
            m
        };
        let split = idle_approach_changes_nothing(refined);
        assert!(split.particles.is_refined());
    }

    /// Runs `model` once skipping the idle approach and once doing every pass, and checks
    /// that every value is the same; returns the skipping solver. Both rebuild their lists
    /// (and split, merge and remove) at every step: a run doing every pass from the start
    /// would otherwise split only once the particles' motion makes a rebuild due, which is
    /// the rule for moving particles, not what this compares.
    fn idle_approach_changes_nothing(model: impl Fn() -> Model) -> Solver {
        let mut skipping = Solver::new(model()).unwrap();
        let mut full = Solver::new(model()).unwrap();
        full.at_rest = false;
        let mut idle_steps = 0;
        let mut steps_in_contact = 0;
        while steps_in_contact < 200 {
            idle_steps += usize::from(skipping.idle());
            skipping.rebuild_due = true;
            full.rebuild_due = true;
            skipping.step().unwrap();
            full.step().unwrap();
            assert_eq!(
                skipping.tools[0].force, full.tools[0].force,
                "step {}",
                full.step
            );
            if full.tools[0].contacts > 0 {
                steps_in_contact += 1;
            }
            assert!(full.step < 5_000, "no contact");
        }
        assert!(idle_steps > 100, "{idle_steps} idle steps");
        assert!(!skipping.at_rest);
        let (a, b) = (&skipping.particles, &full.particles);
        for (name, u, v) in [
            ("x", &a.x, &b.x),
            ("y", &a.y, &b.y),
            ("vx", &a.vx, &b.vx),
            ("vy", &a.vy, &b.vy),
            ("rho", &a.rho, &b.rho),
            ("sxx", &a.sxx, &b.sxx),
            ("sxy", &a.sxy, &b.sxy),
            ("syy", &a.syy, &b.syy),
            ("temp", &a.temp, &b.temp),
        ] {
            assert!(u.iter().zip(v).all(|(p, q)| p == q), "{name} differs");
        }
        assert!(a.vx.iter().any(|&v| v != 0.0), "nothing moved");
        assert_eq!(skipping.time.to_bits(), full.time.to_bits());
        assert_eq!(skipping.energy.external_work, full.energy.external_work);
        skipping
    }
}
