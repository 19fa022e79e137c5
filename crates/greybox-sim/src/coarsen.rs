//! Coarsening: refined particles merged back where they no longer need the resolution.
//!
//! Dynamic refinement ([`crate::refine`]) splits the material the cutting edge reaches, and
//! the split particles stay fine wherever they go: the machined surface layer the tool
//! leaves behind (in a Ti6Al4V cut refined 10 → 5 µm, half of the fine particles after
//! 1.25 mm: docs/validation.md, "Where the time goes") and the chip above the contact, up
//! to its break. Coarsening regions, in the tool's frame and clear of every refinement
//! region, merge them back: **the four children of one split** (the particles that share
//! their family number at their level, [`Particles::family`]) become one particle of the
//! level above once all four lie in a coarsening region, of one boundary group, their damage
//! in one phase, and held together: each within one parent spacing of their centroid (a
//! split puts them 0.35 of it away; a simple shear γ moves the farthest to
//! ¼√((1 + γ)² + 1) of it, so the four of a chip sheared by γ ≤ 2.8 merge, and those the
//! secondary shear zone drew apart stay fine). On an undisturbed lattice the merge restores
//! the parent where it was. The rule does not look at a lattice, so it merges a sheared chip
//! as well as the machined surface; a family that lost a member (to the chip's break) never
//! merges.
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
//! merge pairs in fluids; Feldman & Bonet, IJNME 72, 2007, split only); merging a split's own
//! children back is this module's rule for solids, whose history variables need merge
//! partners from one material point.

use crate::particles::{spacing_factor, Particles, NO_FAMILY};
use crate::refine::Coarsening;

/// Four particles to merge (ascending indices; the first becomes the merged one).
pub type MergeGroup = [usize; 4];

/// The groups of four particles of level `level` ≥ 1 in `c`'s regions (placed at `origin`,
/// the tool's position) that merge into one of level − 1: the four children of one split,
/// all in a region, of one boundary group, with their damage in one phase (all initiating,
/// or all softening), each within one level-(level − 1) spacing of their centroid. Sorted
/// by their first index.
pub fn merge_groups(p: &Particles, level: u8, c: &Coarsening, origin: [f64; 2]) -> Vec<MergeGroup> {
    debug_assert!(level >= 1);
    let slot = usize::from(level) - 1;
    let parent_spacing = p.spacing * spacing_factor(level - 1);
    let mut members: Vec<(u64, usize)> = (0..p.len())
        .filter(|&i| {
            p.level[i] == level
                && p.family[i][slot] != NO_FAMILY
                && c.contains(p.x[i] - origin[0], p.y[i] - origin[1])
        })
        .map(|i| (p.family[i][slot], i))
        .collect();
    members.sort_unstable();
    let mut groups: Vec<MergeGroup> = members
        .chunk_by(|a, b| a.0 == b.0)
        .filter_map(|family| {
            let g: MergeGroup = match family {
                [a, b, c, d] => [a.1, b.1, c.1, d.1],
                _ => return None,
            };
            let same_group = g.iter().all(|&k| p.group[k] == p.group[g[0]]);
            let phase = |k: usize| p.damage[k] >= 1.0;
            let same_phase = g.iter().all(|&k| phase(k) == phase(g[0]));
            let centre = [
                0.25 * g.map(|k| p.x[k]).iter().sum::<f64>(),
                0.25 * g.map(|k| p.y[k]).iter().sum::<f64>(),
            ];
            let together = g
                .iter()
                .all(|&k| (p.x[k] - centre[0]).hypot(p.y[k] - centre[1]) <= parent_spacing);
            (same_group && same_phase && together).then_some(g)
        })
        .collect();
    groups.sort_unstable();
    groups
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
        p.family[first][usize::from(p.level[first])] = NO_FAMILY;
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
            regions: vec![everywhere()],
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

    /// Only the four children of one split merge, and only when all four lie in a region,
    /// belong to one boundary group, have their damage in one phase and are held together
    /// (within one parent spacing of their centroid); a family that lost a member never
    /// merges.
    #[test]
    fn only_whole_families_of_one_kind_merge() {
        let dx = 1e-5;
        let mut p = Particles::block(0.0, 0.0, 6, 1, dx, 4000.0, 300.0);
        let r = Refinement {
            tool: 0,
            regions: vec![everywhere()],
            pattern: SplitPattern::Square,
            coarsening: None,
        };
        split_in_regions(&mut p, &r, [0.0, 0.0]);
        let c = Coarsening {
            regions: vec![Region {
                x_max: 5.0 * dx,
                ..everywhere()
            }],
        };
        let family = |p: &Particles, parent: usize| {
            (0..p.len())
                .filter(|&k| (p.x[k] / dx).floor() as usize == parent)
                .collect::<Vec<_>>()
        };
        let merging = |p: &Particles| {
            merge_groups(p, 1, &c, [0.0, 0.0])
                .iter()
                .map(|g| (p.x[g[0]] / dx).floor() as usize)
                .collect::<Vec<_>>()
        };
        // the five parents inside the region merge, the sixth (outside) does not
        assert_eq!(merging(&p), vec![0, 1, 2, 3, 4]);
        // parent 0: a child drawn 1.6 spacings along x (1.47 from the four's centroid);
        // parent 2: one child in a second boundary group; parent 3: damage in two phases;
        // parent 4: a child lost
        let drawn = family(&p, 0)[3];
        p.x[drawn] += 1.6 * dx;
        let k = family(&p, 2)[0];
        p.group[k] = 1;
        let k = family(&p, 3)[1];
        p.damage[k] = 1.2;
        let mut keep = vec![true; p.len()];
        keep[family(&p, 4)[2]] = false;
        p.retain(&keep);
        assert_eq!(merging(&p), vec![1]);
        // drawn 0.9 spacings along x (0.96 from the four's centroid), parent 0 merges again
        p.x[drawn] -= 0.7 * dx;
        assert_eq!(merging(&p), vec![0, 1]);
    }
}
