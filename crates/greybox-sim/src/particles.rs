//! Particle state, structure of arrays (one `Vec<f64>` per field, SI units, per metre of
//! thickness in plane strain). Flat arrays and no pointers, so that a GPU port can copy them.

use serde::{Deserialize, Serialize};

/// Memory of a run per particle, bytes: the state arrays, neighbour lists, rates and
/// scratch (the estimate the Slurm executor asks for; docs/scaling.md).
pub const BYTES_PER_PARTICLE: u64 = 4096;

/// Default of `numerics.max_particles`: 5 million particles (about 20 GB).
pub const DEFAULT_MAX_PARTICLES: u64 = 5_000_000;

/// Checks the particle count of a `length` × `height` workpiece (m) at spacing `dx` (m), as
/// [`Particles::workpiece`] would lay it out, against `max` (`numerics.max_particles`;
/// `None`: [`DEFAULT_MAX_PARTICLES`]) before anything is allocated. `what` names the set-up
/// in the error, which states the count and the memory it would take.
pub fn check_workpiece_budget(
    what: &str,
    length: f64,
    height: f64,
    dx: f64,
    max: Option<u64>,
) -> greybox_core::Result<()> {
    let count = (length / dx).ceil() * (height / dx).ceil();
    check_particle_budget(what, length, height, dx, count, false, max)
}

/// [`check_workpiece_budget`] for a workpiece that ends with `count` particles; `refined`:
/// the count is its level-0 lattice and the children of its refinement.
pub fn check_particle_budget(
    what: &str,
    length: f64,
    height: f64,
    dx: f64,
    count: f64,
    refined: bool,
    max: Option<u64>,
) -> greybox_core::Result<()> {
    let max = max.unwrap_or(DEFAULT_MAX_PARTICLES);
    if count <= max as f64 {
        return Ok(());
    }
    let found = format!(
        "spacing_m = {dx:e} lays out a {:.3} mm × {:.3} mm workpiece as {count:.3e} particles{}, about {} at {} kB per particle",
        length * 1e3,
        height * 1e3,
        if refined { " (its refinement included)" } else { "" },
        greybox_core::budget::bytes_text(count * BYTES_PER_PARTICLE as f64),
        BYTES_PER_PARTICLE / 1024
    );
    let refusal = greybox_core::budget::over_cap(
        &found,
        "numerics.max_particles",
        &max.to_string(),
        "numerics.max_particles in the set-up or `max_particles`",
    );
    Err(greybox_core::Error::invalid(
        what,
        format!("{refusal}; otherwise coarsen spacing_m"),
    ))
}

/// Number of per-particle arrays of reals in [`Particles`].
pub const REAL_FIELDS: usize = 14;

/// The names of the per-particle arrays of reals, in the order of `real_fields!`.
pub const REAL_FIELD_NAMES: [&str; REAL_FIELDS] = [
    "x", "y", "vx", "vy", "rho", "p", "sxx", "sxy", "syy", "szz", "eps_p", "eps_rate", "temp",
    "damage",
];

/// The per-particle arrays of reals of `$p`, each borrowed with `$borrow` (`&` or `&mut`):
/// the one list of them.
macro_rules! real_fields {
    ($p:expr, $($borrow:tt)+) => {
        [
            $($borrow)+ $p.x,
            $($borrow)+ $p.y,
            $($borrow)+ $p.vx,
            $($borrow)+ $p.vy,
            $($borrow)+ $p.rho,
            $($borrow)+ $p.p,
            $($borrow)+ $p.sxx,
            $($borrow)+ $p.sxy,
            $($borrow)+ $p.syy,
            $($borrow)+ $p.szz,
            $($borrow)+ $p.eps_p,
            $($borrow)+ $p.eps_rate,
            $($borrow)+ $p.temp,
            $($borrow)+ $p.damage,
        ]
    };
}

/// How far ductile damage has gone in the particles of a state (`greybox_material::damage`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DamageState {
    /// Particles in the state.
    pub particles: usize,
    /// Particles whose damage has initiated (ω = 1 reached).
    pub initiated: usize,
    /// Mean degradation d over the initiated particles (0 when none).
    pub mean_degradation: f64,
    /// Largest degradation d of any particle.
    pub max_degradation: f64,
}

/// Boundary group index of free particles.
pub const FREE: u8 = 0;

/// The workpiece particles.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Particles {
    /// Position, m.
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Velocity, m/s.
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    /// Density, kg/m³.
    pub rho: Vec<f64>,
    /// Pressure, Pa (from the equation of state).
    pub p: Vec<f64>,
    /// Deviatoric stress, Pa (plane strain: zz is carried).
    pub sxx: Vec<f64>,
    pub sxy: Vec<f64>,
    pub syy: Vec<f64>,
    pub szz: Vec<f64>,
    /// Equivalent plastic strain.
    pub eps_p: Vec<f64>,
    /// Equivalent plastic strain rate of the last step, 1/s.
    pub eps_rate: Vec<f64>,
    /// Temperature, K.
    pub temp: Vec<f64>,
    /// Ductile damage state (`greybox_material::damage`): the initiation indicator ω in
    /// [0, 1), then 1 + the degradation d; 0 without a damage model. Empty in a checkpoint
    /// written before damage existed (read as all 0).
    #[serde(default)]
    pub damage: Vec<f64>,
    /// Boundary group (0 = free; others index `Model::groups`).
    pub group: Vec<u8>,
    /// Refinement level: a particle of level l has spacing Δx/2ˡ, mass m/4ˡ and smoothing
    /// length h/2ˡ (see [`crate::refine`]). Empty in a checkpoint written before refinement
    /// existed (read as all 0).
    #[serde(default)]
    pub level: Vec<u8>,
    /// The splits that made a refined particle: `family[i][l − 1]` numbers the split that
    /// gave particle i level l, which its three siblings share ([`crate::refine::split`]);
    /// [`NO_FAMILY`] for the levels above the particle's. Only four siblings merge back
    /// ([`crate::coarsen`]). Empty in a checkpoint written before families existed (read
    /// as no family: those particles stay fine).
    #[serde(default)]
    pub family: Vec<[u64; MAX_LEVEL as usize]>,
    /// Splits made so far: the number the next split's children share.
    #[serde(default)]
    pub splits: u64,
    /// Mass of a level-0 particle per metre of thickness, kg/m.
    pub mass: f64,
    /// Initial spacing Δx of the level-0 particles, m.
    pub spacing: f64,
}

/// Keeps `v[i]` where `keep[i]`, in order.
fn retain_by<T: Copy>(v: &mut Vec<T>, keep: &[bool]) {
    let mut k = keep.iter();
    v.retain(|_| *k.next().unwrap_or(&true));
}

/// Deepest refinement level: a level-3 particle has 1/8 of the base spacing.
pub const MAX_LEVEL: u8 = 3;

/// A particle's family at a level it was not split to ([`Particles::family`]).
pub const NO_FAMILY: u64 = u64::MAX;

/// The family of a particle no split has made.
pub const UNSPLIT: [u64; MAX_LEVEL as usize] = [NO_FAMILY; MAX_LEVEL as usize];

/// 1/2ˡ and 1/4ˡ for l = 0..=[`MAX_LEVEL`]: exact powers of two, so a child's spacing and
/// mass are the parent's divided exactly and the children's masses add up to the parent's
/// to the bit.
const SPACING_FACTOR: [f64; MAX_LEVEL as usize + 1] = [1.0, 0.5, 0.25, 0.125];
const MASS_FACTOR: [f64; MAX_LEVEL as usize + 1] = [1.0, 0.25, 0.0625, 0.015625];

/// Spacing (or smoothing length) factor 1/2ˡ of level `l`.
#[inline(always)]
pub fn spacing_factor(l: u8) -> f64 {
    SPACING_FACTOR[l as usize]
}

/// Mass factor 1/4ˡ of level `l`.
#[inline(always)]
pub fn mass_factor(l: u8) -> f64 {
    MASS_FACTOR[l as usize]
}

impl Particles {
    pub fn len(&self) -> usize {
        self.x.len()
    }
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Mass of particle `i` per metre of thickness, kg/m.
    #[inline(always)]
    pub fn mass_of(&self, i: usize) -> f64 {
        self.mass * mass_factor(self.level[i])
    }

    /// Spacing of particle `i` (the length of surface and the width of chip it stands
    /// for), m.
    #[inline(always)]
    pub fn spacing_of(&self, i: usize) -> f64 {
        self.spacing * spacing_factor(self.level[i])
    }

    /// Whether any particle has been refined (the solver then uses per-particle masses and
    /// smoothing lengths).
    pub fn is_refined(&self) -> bool {
        self.level.iter().any(|&l| l > 0)
    }

    /// Every per-particle array of reals: what a check or a copy of a whole particle walks
    /// (`group`, `level` and `family` are the other per-particle arrays).
    pub fn real_fields(&self) -> [&Vec<f64>; REAL_FIELDS] {
        real_fields!(self, &)
    }

    /// [`Particles::real_fields`], writable.
    pub fn real_fields_mut(&mut self) -> [&mut Vec<f64>; REAL_FIELDS] {
        real_fields!(self, &mut)
    }

    /// Keeps the particles with `keep[i]` and drops the others, every per-particle array
    /// alike and in order (the kept particles keep their relative order, so a run that drops
    /// the same particles stays the same bytes). Returns how many were dropped.
    pub fn retain(&mut self, keep: &[bool]) -> usize {
        debug_assert_eq!(keep.len(), self.len());
        let before = self.len();
        for field in self.real_fields_mut() {
            retain_by(field, keep);
        }
        retain_by(&mut self.group, keep);
        retain_by(&mut self.level, keep);
        retain_by(&mut self.family, keep);
        before - self.len()
    }

    /// Fills the arrays a state written before they existed lacks: the levels (all level
    /// 0, before refinement), the damage (all 0, before damage) and the families (none,
    /// before coarsening by family).
    pub fn fill_missing_fields(&mut self) {
        if self.level.is_empty() {
            self.level = vec![0; self.len()];
        }
        if self.family.is_empty() {
            self.family = vec![UNSPLIT; self.len()];
        }
        if self.damage.is_empty() {
            self.damage = vec![0.0; self.len()];
        }
    }

    /// A workpiece of `length` × `height` (m, rounded up to whole spacings) with its top
    /// surface at y = 0 and its left edge at x = 0; returns the particles and the lattice
    /// size (nx, ny), particle (i, j) at index j·nx + i (j = 0 the bottom row).
    pub fn workpiece(
        length: f64,
        height: f64,
        dx: f64,
        rho0: f64,
        t0: f64,
    ) -> (Self, usize, usize) {
        let nx = (length / dx).ceil() as usize;
        let ny = (height / dx).ceil() as usize;
        (
            Self::block(0.0, -(ny as f64) * dx, nx, ny, dx, rho0, t0),
            nx,
            ny,
        )
    }

    /// A rectangular block of particles on a square lattice with spacing `dx`, lower-left
    /// corner (x0, y0), `nx` × `ny` particles, at rest, density `rho0`, temperature `t0`.
    #[allow(clippy::too_many_arguments)]
    pub fn block(x0: f64, y0: f64, nx: usize, ny: usize, dx: f64, rho0: f64, t0: f64) -> Self {
        let n = nx * ny;
        let mut p = Particles {
            mass: rho0 * dx * dx,
            spacing: dx,
            ..Default::default()
        };
        p.x.reserve(n);
        p.y.reserve(n);
        for j in 0..ny {
            for i in 0..nx {
                p.x.push(x0 + (i as f64 + 0.5) * dx);
                p.y.push(y0 + (j as f64 + 0.5) * dx);
            }
        }
        for v in [
            &mut p.vx,
            &mut p.vy,
            &mut p.p,
            &mut p.sxx,
            &mut p.sxy,
            &mut p.syy,
            &mut p.szz,
            &mut p.eps_p,
            &mut p.eps_rate,
            &mut p.damage,
        ] {
            *v = vec![0.0; n];
        }
        p.rho = vec![rho0; n];
        p.temp = vec![t0; n];
        p.group = vec![FREE; n];
        p.level = vec![0; n];
        p.family = vec![UNSPLIT; n];
        p
    }

    /// Von Mises equivalent stress of particle `i`, Pa.
    pub fn von_mises(&self, i: usize) -> f64 {
        (1.5 * (self.sxx[i].powi(2)
            + self.syy[i].powi(2)
            + self.szz[i].powi(2)
            + 2.0 * self.sxy[i].powi(2)))
        .sqrt()
    }

    /// Whether every particle is at rest, unstressed, at density `rho0` and at one
    /// temperature: a state in which every pair term, the update and the kick are exact
    /// zeros (see [`crate::solver::Solver::step`]).
    pub fn at_rest(&self, rho0: f64) -> bool {
        let t0 = self.temp.first().copied().unwrap_or(0.0);
        let zero = |v: &[f64]| v.iter().all(|&a| a == 0.0);
        [
            &self.vx,
            &self.vy,
            &self.p,
            &self.sxx,
            &self.sxy,
            &self.syy,
            &self.szz,
            &self.eps_rate,
        ]
        .into_iter()
        .all(|v| zero(v))
            && self.rho.iter().all(|&r| r == rho0)
            && self.temp.iter().all(|&t| t == t0)
    }

    /// How far damage has gone (counts over the particles now in the state: a chip that
    /// broke off took its particles with it).
    pub fn damage_state(&self) -> DamageState {
        let (mut initiated, mut sum, mut max) = (0usize, 0.0, 0.0f64);
        use greybox_material::damage::{degradation_of, initiated as has_initiated};
        for &d in self.damage.iter().filter(|&&d| has_initiated(d)) {
            initiated += 1;
            sum += degradation_of(d);
            max = max.max(degradation_of(d));
        }
        DamageState {
            particles: self.len(),
            initiated,
            mean_degradation: if initiated > 0 {
                sum / initiated as f64
            } else {
                0.0
            },
            max_degradation: max,
        }
    }

    /// Checks that every array has the particle count (after reading a checkpoint).
    pub fn check_lengths(&self) -> bool {
        let n = self.len();
        self.real_fields().iter().all(|v| v.len() == n)
            && self.group.len() == n
            && self.level.len() == n
            && self.family.len() == n
            && self.level.iter().all(|&l| l <= MAX_LEVEL)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Counts over the particles whose indicator reached 1; d = state − 1 there.
    #[test]
    fn damage_state_counts_initiated_particles() {
        let mut p = Particles::block(0.0, 0.0, 5, 1, 1e-5, 4430.0, 293.15);
        assert_eq!(
            p.damage_state(),
            DamageState {
                particles: 5,
                initiated: 0,
                mean_degradation: 0.0,
                max_degradation: 0.0
            }
        );
        p.damage = vec![0.0, 0.99, 1.0, 1.5, 1.99];
        let s = p.damage_state();
        assert_eq!((s.particles, s.initiated), (5, 3));
        assert!((s.mean_degradation - (0.0 + 0.5 + 0.99) / 3.0).abs() < 1e-15);
        assert_eq!(s.max_degradation, 0.99f64.max(1.99 - 1.0));
    }

    /// A state written before damage existed reads with every particle undamaged.
    #[test]
    fn missing_damage_reads_as_zero() {
        let mut p = Particles::block(0.0, 0.0, 3, 2, 1e-5, 4430.0, 293.15);
        p.damage.clear();
        p.level.clear();
        p.family.clear();
        assert!(!p.check_lengths());
        p.fill_missing_fields();
        assert!(p.check_lengths());
        assert_eq!(p.damage, vec![0.0; 6]);
        assert_eq!(p.family, vec![UNSPLIT; 6]);
    }
}
