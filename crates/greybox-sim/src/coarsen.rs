//! Coarsening: refined particles merged back where the tool has left them.
//!
//! Dynamic refinement ([`crate::refine`]) splits the material the cutting edge reaches; the
//! chip leaves the model at its break, but the machined surface layer stays behind the tool,
//! fine, for the rest of the cut (in a Ti6Al4V cut refined 10 → 5 µm, half of the fine
//! particles after 1.25 mm: docs/validation.md, "Where the time goes"). A coarsening region,
//! in the tool's frame and clear of every refinement region, merges them back: each
//! particle of level l ≥ 1 in it joins the cell of the level-(l − 1) lattice it lies in, and
//! a cell holding exactly four such particles (of one boundary group, their damage in one
//! phase) becomes one particle of level l − 1, again until level 0. On an undisturbed
//! lattice the four are a split particle's four children and the merge restores the parent
//! where it was; where the material was sheared, any four particles in one cell merge and a
//! cell with three or five stays fine.
//!
//! **The merged state** (four particles k of mass m each; volumes V_k = m/ρ_k, V = Σ V_k):
//! * mass 4m (exact in binary, the level's mass), position the centroid, velocity the mean:
//!   mass and momentum are kept to round-off;
//! * density 4m/V (the volume is kept); pressure and deviatoric stress the volume-weighted
//!   means (for the linear equation of state the mean pressure is c₀²(ρ − ρ₀) of the merged
//!   density exactly);
//! * plastic strain, its rate, temperature and damage the means (equal masses; the
//!   temperature mean keeps the heat for a constant specific heat).
//!
//! Averaging takes out the kinetic energy of the four velocities about their mean and the
//! elastic energy of their stresses about theirs; the solver books it (`coarsened` in the
//! energy book) so that the balance still closes. Merges happen at the start of a step
//! (of a coarse step with local time stepping), in particle order: the same particles merge
//! on every thread count and after a resume.
//!
//! Refs: the merging half of adaptive particle refinement (Vacondio et al., CMAME 256, 2013,
//! merge pairs in fluids; Feldman & Bonet, IJNME 72, 2007, split only); the lattice cells
//! are this module's own rule for solids, whose history variables need a merge partner at
//! the same material point.

use crate::particles::{spacing_factor, Particles};
use crate::refine::Coarsening;

/// Four particles to merge (ascending indices; the first becomes the merged one).
pub type MergeGroup = [usize; 4];

/// The groups of four particles of level `level` ≥ 1 in `c`'s region (placed at `origin`,
/// the tool's position) that merge into one of level − 1: the cells of the level-(level − 1)
/// lattice holding exactly four of them, of one boundary group and with their damage in
/// one phase (all initiating, or all softening). Sorted by their first index.
pub fn merge_groups(p: &Particles, level: u8, c: &Coarsening, origin: [f64; 2]) -> Vec<MergeGroup> {
    debug_assert!(level >= 1);
    let cell = p.spacing * spacing_factor(level - 1);
    let centre = lattice_point(c.lattice_point, p.spacing, level - 1);
    let mut members: Vec<(i64, i64, usize)> = (0..p.len())
        .filter(|&i| {
            p.level[i] == level && c.region.contains(p.x[i] - origin[0], p.y[i] - origin[1])
        })
        .map(|i| {
            let ix = ((p.x[i] - centre[0]) / cell + 0.5).floor() as i64;
            let iy = ((p.y[i] - centre[1]) / cell + 0.5).floor() as i64;
            (iy, ix, i)
        })
        .collect();
    members.sort_unstable();
    let mut groups: Vec<MergeGroup> = members
        .chunk_by(|a, b| (a.0, a.1) == (b.0, b.1))
        .filter_map(|cell| {
            let g: MergeGroup = match cell {
                [a, b, c, d] => [a.2, b.2, c.2, d.2],
                _ => return None,
            };
            let same_group = g.iter().all(|&k| p.group[k] == p.group[g[0]]);
            let phase = |k: usize| p.damage[k] >= 1.0;
            let same_phase = g.iter().all(|&k| phase(k) == phase(g[0]));
            (same_group && same_phase).then_some(g)
        })
        .collect();
    for g in groups.iter_mut() {
        g.sort_unstable();
    }
    groups.sort_unstable();
    groups
}

/// A point of the level-`level` lattice, given a point of the level-0 lattice and the
/// level-0 spacing: each split moves the first child by −Δx_l/4 from its parent.
fn lattice_point(level0: [f64; 2], spacing: f64, level: u8) -> [f64; 2] {
    let shift: f64 = (0..level).map(|l| 0.25 * spacing * spacing_factor(l)).sum();
    [level0[0] - shift, level0[1] - shift]
}

/// Merges every group into its first particle (see the module documentation for the
/// state) and returns the keep mask that drops the others (for [`Particles::retain`]).
pub fn merge(p: &mut Particles, groups: &[MergeGroup]) -> Vec<bool> {
    let mut keep = vec![true; p.len()];
    for g in groups {
        let volumes = g.map(|k| 1.0 / p.rho[k]);
        let volume: f64 = volumes.iter().sum();
        let by_volume = |v: &[f64]| -> f64 {
            g.iter().zip(&volumes).map(|(&k, w)| w * v[k]).sum::<f64>() / volume
        };
        let mean = |v: &[f64]| -> f64 { g.iter().map(|&k| v[k]).sum::<f64>() * 0.25 };
        let first = g[0];
        let merged_rho = 4.0 / volume;
        let stresses = [
            by_volume(&p.p),
            by_volume(&p.sxx),
            by_volume(&p.sxy),
            by_volume(&p.syy),
            by_volume(&p.szz),
        ];
        let means = [
            mean(&p.x),
            mean(&p.y),
            mean(&p.vx),
            mean(&p.vy),
            mean(&p.eps_p),
            mean(&p.eps_rate),
            mean(&p.temp),
            mean(&p.damage),
        ];
        p.rho[first] = merged_rho;
        [
            p.p[first],
            p.sxx[first],
            p.sxy[first],
            p.syy[first],
            p.szz[first],
        ] = stresses;
        [
            p.x[first],
            p.y[first],
            p.vx[first],
            p.vy[first],
            p.eps_p[first],
            p.eps_rate[first],
            p.temp[first],
            p.damage[first],
        ] = means;
        p.level[first] -= 1;
        for &k in &g[1..] {
            keep[k] = false;
        }
    }
    keep
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::refine::{split_in_regions, Refinement, Region, SplitPattern};

    fn everywhere() -> Region {
        Region {
            x_min: -1.0,
            x_max: 1.0,
            y_min: -1.0,
            y_max: 1.0,
        }
    }

    /// Splitting a lattice twice and merging it back restores it: every particle at its
    /// parent's place and level, mass and momentum to round-off, the volume and the
    /// volume-weighted stress kept.
    #[test]
    fn merging_undoes_a_split() {
        let dx = 1e-5;
        let mut p = Particles::block(0.0, -6.0 * dx, 8, 6, dx, 4000.0, 300.0);
        for i in 0..p.len() {
            p.vx[i] = 1.0 + 0.1 * i as f64;
            p.sxx[i] = 1e6 * i as f64;
            p.temp[i] = 300.0 + i as f64;
        }
        let original = p.clone();
        let r = Refinement {
            tool: 0,
            regions: vec![everywhere(), everywhere()],
            pattern: SplitPattern::Square,
            coarsening: None,
        };
        split_in_regions(&mut p, &r, [0.0, 0.0]);
        assert_eq!(p.len(), 16 * original.len());
        // a child state that differs from its siblings: velocity and density spread
        for i in (0..p.len()).step_by(3) {
            p.vx[i] += 0.5;
            p.rho[i] *= 1.01;
        }
        let c = Coarsening {
            region: everywhere(),
            lattice_point: [0.5 * dx, -5.5 * dx],
        };
        let (m0, q0) = (p.len() as f64 * p.mass_of(0), momentum(&p));
        let volume0: f64 = (0..p.len()).map(|i| p.mass_of(i) / p.rho[i]).sum();
        for level in [2, 1] {
            let groups = merge_groups(&p, level, &c, [0.0, 0.0]);
            assert_eq!(groups.len(), p.len() / 4, "every cell holds four");
            let keep = merge(&mut p, &groups);
            p.retain(&keep);
        }
        assert_eq!(p.len(), original.len());
        assert!(p.level.iter().all(|&l| l == 0));
        let mut xs: Vec<(f64, f64)> = p.x.iter().copied().zip(p.y.iter().copied()).collect();
        let mut want: Vec<(f64, f64)> = original
            .x
            .iter()
            .copied()
            .zip(original.y.iter().copied())
            .collect();
        xs.sort_by(|a, b| a.partial_cmp(b).unwrap());
        want.sort_by(|a, b| a.partial_cmp(b).unwrap());
        for (a, b) in xs.iter().zip(&want) {
            assert!(
                (a.0 - b.0).abs() < 1e-15 && (a.1 - b.1).abs() < 1e-15,
                "{a:?} {b:?}"
            );
        }
        let m: f64 = (0..p.len()).map(|i| p.mass_of(i)).sum();
        assert!((m - m0).abs() <= 1e-15 * m0);
        let q = momentum(&p);
        assert!((q[0] - q0[0]).abs() <= 1e-14 * q0[0].abs());
        let volume: f64 = (0..p.len()).map(|i| p.mass_of(i) / p.rho[i]).sum();
        assert!((volume - volume0).abs() <= 1e-14 * volume0);
        // the stress and temperature of an undisturbed parent come back (its children
        // carried its own)
        let sum = |v: &[f64]| v.iter().sum::<f64>();
        assert!((sum(&p.temp) - sum(&original.temp)).abs() < 1e-9 * sum(&original.temp));
    }

    fn momentum(p: &Particles) -> [f64; 2] {
        (0..p.len()).fold([0.0, 0.0], |a, i| {
            [a[0] + p.mass_of(i) * p.vx[i], a[1] + p.mass_of(i) * p.vy[i]]
        })
    }

    /// A cell with three or five particles, or four of two boundary groups, or four with
    /// damage in two phases, does not merge; particles outside the region are not looked at.
    #[test]
    fn only_whole_cells_of_one_kind_merge() {
        let dx = 1e-5;
        let mut p = Particles::block(0.0, 0.0, 4, 1, dx, 4000.0, 300.0);
        let r = Refinement {
            tool: 0,
            regions: vec![everywhere()],
            pattern: SplitPattern::Square,
            coarsening: None,
        };
        split_in_regions(&mut p, &r, [0.0, 0.0]);
        let c = Coarsening {
            region: Region {
                x_max: 3.0 * dx,
                ..everywhere()
            },
            lattice_point: [0.5 * dx, 0.5 * dx],
        };
        let cell_of = |p: &Particles, k: usize| (p.x[k] / dx).floor() as usize;
        let in_cell = |p: &Particles, cell: usize| {
            (0..p.len())
                .filter(|&k| cell_of(p, k) == cell)
                .collect::<Vec<_>>()
        };
        // cell 0: a child moved into cell 1 (three and five); cell 2: a second group
        let moved = in_cell(&p, 0)[0];
        p.x[moved] += dx;
        let k = in_cell(&p, 2)[0];
        p.group[k] = 1;
        let groups = merge_groups(&p, 1, &c, [0.0, 0.0]);
        assert!(groups.is_empty(), "{groups:?}");
        // cell 2 back to one group, damage in two phases
        p.group.iter_mut().for_each(|g| *g = 0);
        let k = in_cell(&p, 2)[1];
        p.damage[k] = 1.2;
        assert!(merge_groups(&p, 1, &c, [0.0, 0.0]).is_empty());
        p.damage.iter_mut().for_each(|d| *d = 0.5);
        // cell 2 merges; cell 3 lies outside the region
        assert_eq!(merge_groups(&p, 1, &c, [0.0, 0.0]).len(), 1);
    }
}
