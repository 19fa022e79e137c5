//! Local time stepping (multi-rate) for refined models (`numerics.local_time_stepping`).
//!
//! The time step Δt follows the finest level (Δt = CFL h_min/(c + v)), so in a refined model
//! the coarse particles, whose stable step is at least 2Δt, would take twice the steps they
//! need. With local time stepping the particles are split in two rates at the start of every
//! *coarse step* of 2Δt:
//! * **fast**: the particles of the finest level, and every particle closer than 2h₀ (the
//!   level-0 support) to a tool, so that contact (whose penalty force is sized for one Δt)
//!   only ever acts on particles that take every step;
//! * **slow**: the rest. They advance once per coarse step, by 2Δt.
//!
//! The neighbour lists are split alike ([`NeighbourList::split_by_rate`]): the pairs of two
//! slow particles, and the pairs with a fast partner. A coarse step from t to t + 2Δt is two
//! solver steps:
//! 1. *first step* (t): the slow pairs' forces F_s(t) and the fast pairs' F_f(t); contact;
//!    the fast particles kick, drift and update by Δt; each slow particle keeps
//!    J = 2Δt F_s(t) + Δt F_f(t) (and the same for its conduction and viscous power) and does
//!    not move;
//! 2. *second step* (t + Δt): the fast pairs' forces F_f(t + Δt), with the slow partners
//!    where they were at t; contact; the fast particles advance by Δt; each slow particle
//!    adds Δt F_f(t + Δt) to J and kicks by J/m, then its velocity gradient is gathered over
//!    both lists (the slow pairs' kernel values of step 1: neither partner has moved since)
//!    with the new velocities and it drifts and updates by 2Δt.
//!
//! **Momentum is exact.** Every pair applies equal and opposite impulses to its two partners
//! over the coarse step — a slow pair 2Δt F_s on each, a fast pair Δt F_f on each at each of
//! the two steps (the slow partner's share is only collected until its kick) — so the total
//! momentum changes only by the contact and boundary impulses, as without local time
//! stepping (`tests/refinement.rs` checks it to round-off). The scheme is the impulse form
//! of multiple time stepping (Tuckerman, Berne & Martyna, J. Chem. Phys. 97, 1992, r-RESPA)
//! applied by particle rate rather than by force kind: the slow particles are frozen over
//! the coarse step and receive the fast pairs' impulses summed, the symplectic-Euler order
//! of the single-rate solver kept for each rate.
//!
//! **What it costs in accuracy.** The fast side sees a slow partner at its position and
//! velocity of t during both steps, and the slow side receives the fast pairs' forces of t and
//! t + Δt: a first-order, local error at the rate boundary, of the size of the single-rate
//! scheme's own time error there. The energy balance of a run with local time stepping is
//! stated against the same run without it in docs/simulator.md, "Local time stepping", and
//! docs/validation.md, "Dynamic refinement".
//!
//! Between the two steps of a coarse step the slow particles lag one step behind (their state
//! is that of t); observers that read the state then see it so. Checkpoints are written and
//! runs end only at the end of a coarse step ([`Solver::at_sync`]); splitting, removal and
//! the neighbour rebuild happen at its start, as the rates are set.

use super::{kinematics_pass, Advance, Rates, SimError, Solver};
use crate::contact;
use crate::neighbours::NeighbourList;
use rayon::prelude::*;

/// Local time stepping's state between steps (see the module documentation). Only `second`
/// is state of the run; the rest is rebuilt at the start of every coarse step, and a coarse
/// step's end (the only place a checkpoint is written) has nothing pending.
#[derive(Debug, Clone, Default)]
pub(crate) struct Multirate {
    /// Whether the next step is a coarse step's second.
    second: bool,
    /// Per particle: whether it takes every step (fast) or one of 2Δt per two (slow).
    fast: Vec<bool>,
    /// The pairs of two slow particles.
    slow_list: NeighbourList,
    /// The pairs with a fast partner.
    fast_list: NeighbourList,
    /// The full lists' build count and the rates the split lists were made for.
    split_build: Option<u64>,
    split_fast: Vec<bool>,
    /// The slow pairs' rates at the coarse step's start (accelerations, dT/dt, viscous
    /// power; then their kinematics sums at its end) and their per-pair buffers.
    slow_rates: Vec<Rates>,
    slow_wg: Vec<[f64; 2]>,
    slow_force: Vec<[f64; 3]>,
    /// Per slow particle: its rates summed over the coarse step so far, in units of Δt —
    /// [a_x, a_y, dT/dt, viscous power] (2 × the slow pairs' + the fast pairs' of each step).
    pending: Vec<[f64; 4]>,
}

impl Multirate {
    /// Whether the state is between the two steps of a coarse step.
    pub(crate) fn mid_step(&self) -> bool {
        self.second
    }
}

impl Solver {
    /// One step with local time stepping: a coarse step's first or second.
    pub(super) fn multirate_step(&mut self) -> Result<(), SimError> {
        let mut mr = self
            .multirate
            .take()
            .expect("called only with local time stepping on");
        let result = if mr.second {
            self.second_step(&mut mr)
        } else {
            self.first_step(&mut mr)
        };
        mr.second = !mr.second;
        self.multirate = Some(mr);
        result
    }

    /// The coarse step's first step (see the module documentation).
    fn first_step(&mut self, mr: &mut Multirate) -> Result<(), SimError> {
        self.prepare_lists();
        self.set_rates(mr);
        self.pack();
        let n = self.particles.len();
        mr.slow_rates.resize(n, Rates::default());
        self.pair_forces(
            &self.scratch.packed,
            &mr.slow_list,
            &mut mr.slow_rates,
            &mut mr.slow_wg,
            &mut mr.slow_force,
        );
        self.fast_pair_forces(mr);
        self.apply_contact();
        mr.pending.resize(n, [0.0; 4]);
        let rates = &self.scratch.rates;
        mr.pending
            .par_iter_mut()
            .enumerate()
            .filter(|(i, _)| !mr.fast[*i])
            .for_each(|(i, j)| {
                let (s, f) = (&mr.slow_rates[i], &rates[i]);
                *j = [
                    2.0 * s.ax + f.ax,
                    2.0 * s.ay + f.ay,
                    2.0 * s.dtemp + f.dtemp,
                    2.0 * s.av_power + f.av_power,
                ];
            });
        let advance = Advance::Fast(&mr.fast);
        self.book_boundaries(advance);
        self.kick(advance);
        self.fast_kinematics(mr);
        self.update(advance)?;
        self.advance_clock();
        self.particle_steps += mr.fast.iter().filter(|&&f| f).count() as u64;
        Ok(())
    }

    /// The coarse step's second step (see the module documentation).
    fn second_step(&mut self, mr: &mut Multirate) -> Result<(), SimError> {
        // every particle: a controller may have changed a slow one between the two steps
        self.pack();
        self.fast_pair_forces(mr);
        self.apply_contact();
        // The slow particles' rates become their means over the coarse step (the viscous
        // power in units of Δt, as the update books it).
        self.scratch
            .rates
            .par_iter_mut()
            .zip(mr.pending.par_iter())
            .enumerate()
            .filter(|(i, _)| !mr.fast[*i])
            .for_each(|(_, (r, j))| {
                r.ax = 0.5 * (j[0] + r.ax);
                r.ay = 0.5 * (j[1] + r.ay);
                r.dtemp = 0.5 * (j[2] + r.dtemp);
                r.av_power += j[3];
            });
        let advance = Advance::Both(&mr.fast);
        self.book_boundaries(advance);
        self.kick(advance);
        self.fast_kinematics(mr);
        let sc = &mut self.scratch;
        kinematics_pass(
            self.refined,
            self.particles.mass,
            &sc.packed,
            &mr.slow_list,
            &mr.slow_wg,
            &mut mr.slow_rates,
        );
        sc.rates
            .par_iter_mut()
            .zip(mr.slow_rates.par_iter())
            .enumerate()
            .filter(|(i, _)| !mr.fast[*i])
            .for_each(|(_, (r, s))| {
                for (a, b) in r.kin.iter_mut().zip(s.kin) {
                    *a += b;
                }
            });
        self.update(advance)?;
        self.advance_clock();
        self.particle_steps += self.particles.len() as u64;
        Ok(())
    }

    /// Sets the particles' rates for the coarse step and splits the lists when they or the
    /// rates changed.
    fn set_rates(&mut self, mr: &mut Multirate) {
        let finest = super::finest_level(&self.particles, self.refinement.as_ref());
        let p = &self.particles;
        p.level
            .par_iter()
            .map(|&l| l >= finest)
            .collect_into_vec(&mut mr.fast);
        contact::mark_near(&self.tools, p, 2.0 * self.kernel.h, &mut mr.fast);
        if mr.split_build != Some(self.neighbours.builds) || mr.split_fast != mr.fast {
            self.neighbours
                .split_by_rate(&mr.fast, &mut mr.slow_list, &mut mr.fast_list);
            mr.split_build = Some(self.neighbours.builds);
            mr.split_fast.clone_from(&mr.fast);
        }
    }

    /// Steps 3a and 3b over the fast pairs into the step's rates.
    fn fast_pair_forces(&mut self, mr: &Multirate) {
        let mut sc = std::mem::take(&mut self.scratch);
        self.pair_forces(
            &sc.packed,
            &mr.fast_list,
            &mut sc.rates,
            &mut sc.pair_wg,
            &mut sc.pair_force,
        );
        self.scratch = sc;
    }

    /// Step 6 over the fast pairs into the step's rates.
    fn fast_kinematics(&mut self, mr: &Multirate) {
        let sc = &mut self.scratch;
        kinematics_pass(
            self.refined,
            self.particles.mass,
            &sc.packed,
            &mr.fast_list,
            &sc.pair_wg,
            &mut sc.rates,
        );
    }
}
