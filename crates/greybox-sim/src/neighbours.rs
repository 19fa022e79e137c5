//! Verlet neighbour lists built from a cell list, as symmetric half lists.
//!
//! Lists hold every pair closer than 2h + skin; they are rebuilt when any particle has moved
//! more than skin/2 since the last build, so no pair inside 2h is ever missed. With
//! per-particle smoothing lengths (a refined model, [`NeighbourList::build_with_reach`]) a
//! pair is kept within 2h_ij + skin = h_i + h_j + skin; the cells are then as wide as the
//! finest pair's cut-off and each particle scans only the cells its own cut-offs reach.
//!
//! Every pair is stored once, with its lower index first (the half list): particle i's
//! partners j > i are `index[start[i]..start[i+1]]` (compressed rows), and pair `p` is the
//! position of j in `index`. A pair pass over the half list computes each pair's terms once,
//! adds i's share in place and stores j's share in a per-pair slot; the reverse lists
//! (`incoming(j)`: the pairs in which j is the second partner, in ascending pair order) then
//! let every particle gather its stored shares. No two threads write the same memory and the
//! sums run in a fixed order, so results are the same bytes on any thread count — the
//! scatter-free layout a GPU port uses as well.

use rayon::prelude::*;

/// The lists are private and written only by [`NeighbourList::build`]: the solver's
/// parallel pair passes rely on the row offsets never decreasing (disjoint pair ranges per
/// particle chunk).
#[derive(Debug, Clone, Default)]
pub struct NeighbourList {
    /// Row offsets of the half lists (n + 1 entries, non-decreasing).
    start: Vec<u32>,
    /// Second partners j > i of every pair, row by row.
    index: Vec<u32>,
    /// Row offsets of the reverse lists (n + 1 entries).
    rev_start: Vec<u32>,
    /// Pair numbers (positions in `index`) whose second partner is the row's particle.
    rev_pair: Vec<u32>,
    /// The first partner of each of those pairs.
    rev_first: Vec<u32>,
    /// Positions at the last build.
    x0: Vec<f64>,
    y0: Vec<f64>,
    /// Cell list and counting scratch.
    cell_start: Vec<u32>,
    cell_items: Vec<u32>,
    cell_fill: Vec<u32>,
    cell_of: Vec<u32>,
    /// The largest reach (smoothing length) in each cell, m (refined models only).
    cell_reach: Vec<f64>,
    /// Cut-off radius (2h + skin), m.
    pub cutoff: f64,
    pub skin: f64,
    pub builds: u64,
}

impl NeighbourList {
    pub fn new(support: f64, skin: f64) -> Self {
        NeighbourList {
            cutoff: support + skin,
            skin,
            ..Default::default()
        }
    }

    /// Positions at the last build and the squared displacement (skin/2)² beyond which the
    /// lists must be rebuilt (for callers that track the displacement in their own pass).
    pub fn reference(&self) -> (&[f64], &[f64], f64) {
        (&self.x0, &self.y0, 0.25 * self.skin * self.skin)
    }

    /// Whether a particle has moved more than skin/2 since the last build.
    pub fn needs_rebuild(&self, x: &[f64], y: &[f64]) -> bool {
        if self.x0.len() != x.len() {
            return true;
        }
        let lim = 0.25 * self.skin * self.skin;
        x.par_iter()
            .zip(y.par_iter())
            .zip(self.x0.par_iter().zip(self.y0.par_iter()))
            .any(|((x, y), (a, b))| (x - a).powi(2) + (y - b).powi(2) > lim)
    }

    /// Rebuilds the lists for positions (x, y), every pair within the cut-off.
    pub fn build(&mut self, x: &[f64], y: &[f64]) {
        self.build_with_reach(x, y, None);
    }

    /// Rebuilds the lists for positions (x, y); with `reach` (per particle, m: the
    /// smoothing length h_i) a pair is kept only within h_i + h_j + skin, which must not
    /// exceed the cut-off the list was made with.
    ///
    /// With one smoothing length the cells are the cut-off wide and each particle scans the
    /// 3 × 3 around its own. With several (a refined model, [`CellGrid::for_reach`]) the
    /// cells are as wide as the finest pair's cut-off, 2h_min + skin, and particle i scans
    /// the cells within h_i + h_max + skin, skipping each cell whose nearest point lies
    /// beyond h_i + (the largest h in that cell) + skin: a fine particle among fine ones
    /// tests the partners of about 3 × 3 fine cells instead of 3 × 3 cells of the coarsest
    /// cut-off (16 times the area at a 4:1 spacing), and a coarse one the disc of its own
    /// cut-off. The pairs are the same either way; their order in a row follows the scan.
    pub fn build_with_reach(&mut self, x: &[f64], y: &[f64], reach: Option<&[f64]>) {
        let n = x.len();
        let skin = self.skin;
        let grid = CellGrid::for_reach(x, y, self.cutoff, skin, reach);
        // Counting sort of particles into cells.
        self.cell_of.resize(n, 0);
        self.cell_of
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, cell)| *cell = grid.cell(x[i], y[i]) as u32);
        counting_offsets(&self.cell_of, grid.nx * grid.ny, &mut self.cell_start);
        self.cell_items.resize(n, 0);
        self.cell_fill.clone_from(&self.cell_start);
        for i in 0..n {
            let cell = self.cell_of[i] as usize;
            self.cell_items[self.cell_fill[cell] as usize] = i as u32;
            self.cell_fill[cell] += 1;
        }
        // The largest reach in each cell (refined models only).
        self.cell_reach.clear();
        if let Some(h) = reach {
            self.cell_reach.resize(grid.nx * grid.ny, f64::NEG_INFINITY);
            for (&cell, &hi) in self.cell_of.iter().zip(h) {
                let r = &mut self.cell_reach[cell as usize];
                *r = r.max(hi);
            }
        }
        let c = self.cutoff;
        let c2 = c * c;
        let (cs, ci, co) = (&self.cell_start, &self.cell_items, &self.cell_of);
        let cell_reach = &self.cell_reach;
        // Partners j > i of particle i within the cut-off, pushed onto `row`. A cell lists
        // its particles in ascending order (the counting sort above fills it in index
        // order), so the partners j > i are the tail after a binary search.
        let visit = |i: usize, row: &mut Vec<u32>| {
            let cell = co[i] as usize;
            let (cx, cy) = (cell % grid.nx, cell / grid.nx);
            let ring = reach.map_or(1, |h| grid.ring(h[i] + grid.h_max + skin));
            for gy in cy.saturating_sub(ring)..=(cy + ring).min(grid.ny - 1) {
                for gx in cx.saturating_sub(ring)..=(cx + ring).min(grid.nx - 1) {
                    let g = gy * grid.nx + gx;
                    if let Some(h) = reach {
                        if grid.beyond(gx, gy, x[i], y[i], h[i] + cell_reach[g] + skin) {
                            continue;
                        }
                    }
                    let items = &ci[cs[g] as usize..cs[g + 1] as usize];
                    let after_i = items.partition_point(|&j| j as usize <= i);
                    for &j in &items[after_i..] {
                        let ju = j as usize;
                        let cut2 = reach.map_or(c2, |h| (h[i] + h[ju] + skin).powi(2));
                        if (x[i] - x[ju]).powi(2) + (y[i] - y[ju]).powi(2) < cut2 {
                            row.push(j);
                        }
                    }
                }
            }
        };
        // One scan of the cells: each block of particles lists its rows, and the blocks are
        // joined in order.
        const BLOCK: usize = 256;
        let blocks: Vec<(Vec<u32>, Vec<u32>)> = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                let rows = b * BLOCK..((b + 1) * BLOCK).min(n);
                // About 14 partners per half-list row at the default smoothing.
                let mut partners = Vec::with_capacity(16 * rows.len());
                let mut ends = Vec::with_capacity(rows.len());
                for i in rows {
                    visit(i, &mut partners);
                    ends.push(partners.len() as u32);
                }
                (partners, ends)
            })
            .collect();
        self.start.clear();
        self.start.push(0);
        self.index.clear();
        for (partners, ends) in &blocks {
            let base = self.index.len() as u32;
            self.start.extend(ends.iter().map(|e| base + e));
            self.index.extend_from_slice(partners);
        }
        self.build_reverse(n);
        self.x0.clear();
        self.x0.extend_from_slice(x);
        self.y0.clear();
        self.y0.extend_from_slice(y);
        self.builds += 1;
    }

    /// The reverse lists of the half lists `start`/`index` of `n` particles: a counting sort
    /// of the pairs by their second partner, in pair order.
    fn build_reverse(&mut self, n: usize) {
        let total = self.index.len();
        counting_offsets(&self.index, n, &mut self.rev_start);
        self.rev_pair.clear();
        self.rev_pair.resize(total, 0);
        self.rev_first.clear();
        self.rev_first.resize(total, 0);
        self.cell_fill.clone_from(&self.rev_start);
        for i in 0..n {
            for p in self.pairs(i) {
                let slot = &mut self.cell_fill[self.index[p] as usize];
                self.rev_pair[*slot as usize] = p as u32;
                self.rev_first[*slot as usize] = i as u32;
                *slot += 1;
            }
        }
    }

    /// Splits these lists by the particles' rates (the solver's local time stepping,
    /// docs/simulator.md): the pairs of two slow particles go to `slow`, every pair with a
    /// fast partner to `fast`, each row keeping its order; both get their reverse lists. The
    /// two lists together hold every pair of these once. Their build positions and counts are
    /// not set: the displacement test stays with these lists.
    pub fn split_by_rate(
        &self,
        fast: &[bool],
        slow: &mut NeighbourList,
        fast_out: &mut NeighbourList,
    ) {
        let n = self.start.len().saturating_sub(1);
        for l in [&mut *slow, &mut *fast_out] {
            l.start.clear();
            l.start.push(0);
            l.index.clear();
        }
        for (i, &fast_i) in fast.iter().enumerate().take(n) {
            for &j in self.partners(i) {
                let to = if fast_i || fast[j as usize] {
                    &mut *fast_out
                } else {
                    &mut *slow
                };
                to.index.push(j);
            }
            slow.start.push(slow.index.len() as u32);
            fast_out.start.push(fast_out.index.len() as u32);
        }
        slow.build_reverse(n);
        fast_out.build_reverse(n);
    }

    /// Pair numbers of particle i's half-list row.
    #[inline]
    pub fn pairs(&self, i: usize) -> std::ops::Range<usize> {
        self.start[i] as usize..self.start[i + 1] as usize
    }

    /// Pair numbers of the rows of particles `first..last` (contiguous).
    #[inline]
    pub fn pairs_of_particles(&self, first: usize, last: usize) -> std::ops::Range<usize> {
        self.start[first] as usize..self.start[last] as usize
    }

    /// Particle i's partners j > i, in the order of its pair numbers.
    #[inline]
    pub fn partners(&self, i: usize) -> &[u32] {
        &self.index[self.pairs(i)]
    }

    /// The pairs in which particle j is the second partner.
    #[inline]
    pub fn incoming(&self, j: usize) -> &[u32] {
        &self.rev_pair[self.incoming_range(j)]
    }

    /// The first partners of the pairs in which particle j is the second partner.
    #[inline]
    pub fn incoming_first(&self, j: usize) -> &[u32] {
        &self.rev_first[self.incoming_range(j)]
    }

    #[inline]
    fn incoming_range(&self, j: usize) -> std::ops::Range<usize> {
        self.rev_start[j] as usize..self.rev_start[j + 1] as usize
    }

    /// Number of pairs (each counted once).
    pub fn pair_count(&self) -> usize {
        self.index.len()
    }
}

/// The square cells the particles are sorted into for a build: `nx` × `ny` cells of width
/// `width` from (`x0`, `y0`).
#[derive(Debug, Clone, Copy)]
struct CellGrid {
    x0: f64,
    y0: f64,
    width: f64,
    nx: usize,
    ny: usize,
    /// The largest reach (smoothing length) of any particle, m; 0 without reaches.
    h_max: f64,
}

impl CellGrid {
    /// The grid over the particles' bounding box. Without reaches, or with one reach for
    /// all, the cells are `cutoff` wide (the same cells, and so the same rows, as a uniform
    /// model's); with several, 2 h_min + skin wide: the finest pair's cut-off.
    fn for_reach(x: &[f64], y: &[f64], cutoff: f64, skin: f64, reach: Option<&[f64]>) -> Self {
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for i in 0..x.len() {
            xmin = xmin.min(x[i]);
            xmax = xmax.max(x[i]);
            ymin = ymin.min(y[i]);
            ymax = ymax.max(y[i]);
        }
        let (h_min, h_max) = reach.map_or((0.0, 0.0), |h| {
            h.iter()
                .fold((f64::MAX, 0.0_f64), |(lo, hi), &v| (lo.min(v), hi.max(v)))
        });
        let width = if h_min < h_max {
            2.0 * h_min + skin
        } else {
            cutoff
        };
        CellGrid {
            x0: xmin,
            y0: ymin,
            width,
            nx: (((xmax - xmin) / width).floor() as usize + 1).max(1),
            ny: (((ymax - ymin) / width).floor() as usize + 1).max(1),
            h_max,
        }
    }

    /// The cell of the point (x, y), row-major.
    fn cell(&self, x: f64, y: f64) -> usize {
        let cx = ((x - self.x0) / self.width) as usize;
        let cy = ((y - self.y0) / self.width) as usize;
        cy.min(self.ny - 1) * self.nx + cx.min(self.nx - 1)
    }

    /// How many cells on each side a particle must scan to reach every partner within
    /// `reach` m (at least 1).
    fn ring(&self, reach: f64) -> usize {
        ((reach / self.width).ceil() as usize).max(1)
    }

    /// Whether every point of cell (gx, gy) lies farther than `cut` from (x, y). The
    /// margin of 10⁻⁹ of the cut keeps a particle that round-off sorted into the next cell.
    fn beyond(&self, gx: usize, gy: usize, x: f64, y: f64, cut: f64) -> bool {
        let gap = |p: f64, lo: f64| (lo - p).max(p - (lo + self.width)).max(0.0);
        let dx = gap(x, self.x0 + gx as f64 * self.width);
        let dy = gap(y, self.y0 + gy as f64 * self.width);
        dx * dx + dy * dy > (cut * (1.0 + 1e-9)).powi(2)
    }
}

/// Offsets of a counting sort: `offsets[k]..offsets[k + 1]` is where key k goes.
fn counting_offsets(keys: &[u32], nkeys: usize, offsets: &mut Vec<u32>) {
    offsets.clear();
    offsets.resize(nkeys + 1, 0);
    for &k in keys {
        offsets[k as usize + 1] += 1;
    }
    accumulate(offsets);
}

/// Running sums in place: counts (after a leading 0) become row offsets.
fn accumulate(offsets: &mut [u32]) {
    for k in 1..offsets.len() {
        offsets[k] = offsets[k]
            .checked_add(offsets[k - 1])
            .expect("more than 2³² − 1 neighbour pairs: the model is too large for u32 lists");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [−0.5, 0.5) from a 64-bit linear congruential generator seeded
    /// with `seed` (Knuth's MMIX constants): the lattices' jitter.
    fn jitter(mut s: u64) -> impl FnMut() -> f64 {
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        }
    }

    /// Same pairs as brute force, for a jittered lattice.
    #[test]
    fn matches_brute_force() {
        let mut x = Vec::new();
        let mut y = Vec::new();
        let mut rnd = jitter(12345);
        for j in 0..30 {
            for i in 0..40 {
                x.push(i as f64 + 0.4 * rnd());
                y.push(j as f64 + 0.4 * rnd());
            }
        }
        let mut nl = NeighbourList::new(3.0, 0.3);
        nl.build(&x, &y);
        for i in 0..x.len() {
            assert!(nl.index[nl.pairs(i)].iter().all(|&j| j as usize > i));
            let mut got: Vec<u32> = nl.index[nl.pairs(i)].to_vec();
            // The pairs in which i is the second partner, by their first partner.
            for (&p, &f) in nl.incoming(i).iter().zip(nl.incoming_first(i)) {
                assert_eq!(nl.index[p as usize] as usize, i);
                assert!(nl.pairs(f as usize).contains(&(p as usize)));
                got.push(f);
            }
            got.sort();
            let want: Vec<u32> = (0..x.len() as u32)
                .filter(|&j| {
                    j as usize != i
                        && (x[i] - x[j as usize]).powi(2) + (y[i] - y[j as usize]).powi(2)
                            < 3.3 * 3.3
                })
                .collect();
            assert_eq!(got, want, "particle {i}");
        }
        assert_eq!(
            nl.pair_count() * 2,
            (0..x.len())
                .map(|i| nl.pairs(i).len() + nl.incoming(i).len())
                .sum::<usize>()
        );
        assert!(nl.incoming(5).windows(2).all(|w| w[0] < w[1]));
        assert!(!nl.needs_rebuild(&x, &y));
        x[7] += 0.2;
        assert!(nl.needs_rebuild(&x, &y));
    }

    /// Every pair within h_i + h_j + skin and no other, for three spacings side by side
    /// (1, 1/2, 1/4, h = 1.2 spacing, jittered), as brute force finds them; and one reach for
    /// all gives the rows of the plain build.
    #[test]
    fn per_particle_reach_matches_brute_force() {
        let mut rnd = jitter(777);
        let (mut x, mut y, mut h) = (Vec::new(), Vec::new(), Vec::new());
        for (x_from, spacing) in [(0.0, 1.0), (10.0, 0.5), (16.0, 0.25)] {
            let per_row = (6.0 / spacing) as usize;
            for row in 0..(12.0 / spacing) as usize {
                for col in 0..per_row {
                    x.push(x_from + (col as f64 + 0.5 + 0.3 * rnd()) * spacing);
                    y.push((row as f64 + 0.5 + 0.3 * rnd()) * spacing);
                    h.push(1.2 * spacing);
                }
            }
        }
        let skin = 0.05 * 1.2 * 0.25;
        let mut nl = NeighbourList::new(2.0 * 1.2, skin);
        nl.build_with_reach(&x, &y, Some(&h));
        let n = x.len();
        let mut got: Vec<(u32, u32)> = (0..n)
            .flat_map(|i| nl.partners(i).iter().map(move |&j| (i as u32, j)))
            .collect();
        got.sort();
        let mut want = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                let d2 = (x[i] - x[j]).powi(2) + (y[i] - y[j]).powi(2);
                if d2 < (h[i] + h[j] + skin).powi(2) {
                    want.push((i as u32, j as u32));
                }
            }
        }
        assert_eq!(got.len(), want.len());
        assert_eq!(got, want);
        // one reach for all: the plain build's rows, in its order
        let one = vec![1.2; n];
        let (mut a, mut b) = (NeighbourList::new(2.4, skin), NeighbourList::new(2.4, skin));
        a.build_with_reach(&x, &y, Some(&one));
        b.build(&x, &y);
        assert_eq!((a.start, a.index), (b.start, b.index));
    }
}
