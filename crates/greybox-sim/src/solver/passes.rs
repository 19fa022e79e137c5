//! The pair passes of a step over one neighbour list (steps 3a, 3b and 6 of the solver),
//! and which particles a step moves ([`Advance`]): shared by the single-rate step and local
//! time stepping's two ([`super::multirate`]).

use super::PAIR_CHUNK;
use crate::disjoint::DisjointMut;
use crate::kernel::PairTable;
use crate::model::Numerics;
use crate::neighbours::NeighbourList;
use crate::pair_lanes::{self, ForceConstants, Packed};
use crate::particles::Particles;
use crate::rates::Rates;
use greybox_material::Material;
use rayon::prelude::*;

/// Which particles a pass moves, and by how much (see [`super::multirate`]).
#[derive(Debug, Clone, Copy)]
pub(crate) enum Advance<'a> {
    /// Every particle, by Δt.
    All,
    /// The fast particles (`true`) by Δt; the slow ones wait (a coarse step's first step).
    Fast(&'a [bool]),
    /// The fast particles by Δt, the slow ones by 2Δt (a coarse step's second step).
    Both(&'a [bool]),
}

impl Advance<'_> {
    /// The step particle `i` moves by, given Δt; `None`: it does not move.
    #[inline]
    pub(crate) fn step_of(&self, i: usize, dt: f64) -> Option<f64> {
        match self {
            Advance::All => Some(dt),
            Advance::Fast(fast) => fast[i].then_some(dt),
            Advance::Both(fast) => Some(if fast[i] { dt } else { 2.0 * dt }),
        }
    }

    /// Whether particle `i` moves by 2Δt (a slow particle in a coarse step's second step).
    #[inline]
    pub(crate) fn is_slow(&self, i: usize) -> bool {
        matches!(self, Advance::Both(fast) if !fast[i])
    }
}

/// Step 3a over `list`: forces and conduction over the half list. Each pair's terms are
/// computed once: the first partner's share is summed in place into `rates`, the second
/// partner's share (equal and opposite force, opposite heat flow) is stored in `pair_force`
/// for step 3b; the pair kernel values are kept in `pair_wg` for step 6.
#[allow(clippy::too_many_arguments)]
pub(super) fn force_pass(
    refined: bool,
    table: &PairTable,
    constants: &ForceConstants,
    packed: &[Packed],
    list: &NeighbourList,
    rates: &mut [Rates],
    pair_wg: &mut Vec<[f64; 2]>,
    pair_force: &mut Vec<[f64; 3]>,
) {
    // Conduction needs no branch: k = 0 when thermal is off (see `pack`).
    let npairs = list.pair_count();
    pair_wg.resize(npairs, [0.0; 2]);
    pair_force.resize(npairs, [0.0; 3]);
    let pair_wg = DisjointMut::new(pair_wg);
    let pair_force = DisjointMut::new(pair_force);
    rates
        .par_chunks_mut(PAIR_CHUNK)
        .enumerate()
        .for_each(|(ch, rates)| {
            let first = ch * PAIR_CHUNK;
            let pairs = list.pairs_of_particles(first, first + rates.len());
            // SAFETY: chunks hold disjoint particles, hence disjoint half-list rows (the
            // row offsets are non-decreasing, see `NeighbourList`).
            let (wg_out, force_out) = unsafe {
                (
                    pair_wg.range(pairs.clone()),
                    pair_force.range(pairs.clone()),
                )
            };
            pair_lanes::force_rows(
                refined,
                first,
                rates,
                packed,
                list,
                table,
                constants,
                wg_out,
                force_out,
                pairs.start,
            );
        });
}

/// What step 3b reads to turn a conduction sum into dT/dt.
pub(super) struct HeatInputs<'a> {
    thermal: bool,
    specific_heat: &'a greybox_material::Table1d,
    f_mass: f64,
    rho: &'a [f64],
    temp: &'a [f64],
}

impl<'a> HeatInputs<'a> {
    pub(super) fn of(
        numerics: &Numerics,
        material: &'a Material,
        particles: &'a Particles,
    ) -> Self {
        HeatInputs {
            thermal: numerics.thermal,
            specific_heat: &material.thermal.specific_heat,
            f_mass: numerics.mass_scaling,
            rho: &particles.rho,
            temp: &particles.temp,
        }
    }
}

/// Step 3b over `list`: every particle adds the shares `shares` stored for it, then turns the
/// conduction sum into dT/dt = sum / (ρ c) (heat capacity per volume kept physical under mass
/// scaling).
pub(super) fn incoming_pass(
    heat: &HeatInputs<'_>,
    list: &NeighbourList,
    shares: &[[f64; 3]],
    rates: &mut [Rates],
) {
    rates
        .par_iter_mut()
        .with_min_len(PAIR_CHUNK)
        .enumerate()
        .for_each(|(i, out)| {
            let (mut ax, mut ay, mut cond) = (out.ax, out.ay, out.dtemp);
            for &p in list.incoming(i) {
                let [sx, sy, sc] = shares[p as usize];
                ax += sx;
                ay += sy;
                cond += sc;
            }
            out.ax = ax;
            out.ay = ay;
            out.dtemp = if heat.thermal {
                cond / (heat.rho[i] / heat.f_mass * heat.specific_heat.eval(heat.temp[i]))
            } else {
                0.0
            };
        });
}

/// Step 6 over `list`: continuity, velocity gradient and XSPH from the new velocities into
/// `rates[i].kin`. Each particle visits its own half-list row and its incoming pairs, with
/// the pair kernel values `pair_wg` of step 3a (this light pass recomputes the pair terms
/// from both sides: storing the partner's seven shares per pair and reading them back was
/// slower).
pub(super) fn kinematics_pass(
    refined: bool,
    mass: f64,
    packed: &[Packed],
    list: &NeighbourList,
    pair_wg: &[[f64; 2]],
    rates: &mut [Rates],
) {
    rates
        .par_chunks_mut(PAIR_CHUNK)
        .enumerate()
        .for_each(|(ch, rates)| {
            pair_lanes::kinematics_rows(
                refined,
                ch * PAIR_CHUNK,
                rates,
                packed,
                list,
                mass,
                pair_wg,
            );
        });
}
