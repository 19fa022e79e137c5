//! Verlet neighbour lists built from a cell list, as symmetric half lists.
//!
//! Lists hold every pair closer than 2h + skin; they are rebuilt when any particle has moved
//! more than skin/2 since the last build, so no pair inside 2h is ever missed. With
//! per-particle smoothing lengths (a refined model, [`NeighbourList::build_with_reach`]) a
//! pair is kept within 2h_ij + skin = h_i + h_j + skin, the cells are sized by the largest
//! such cut-off.
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
    pub fn build_with_reach(&mut self, x: &[f64], y: &[f64], reach: Option<&[f64]>) {
        let n = x.len();
        let c = self.cutoff;
        let skin = self.skin;
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for i in 0..n {
            xmin = xmin.min(x[i]);
            xmax = xmax.max(x[i]);
            ymin = ymin.min(y[i]);
            ymax = ymax.max(y[i]);
        }
        let ncx = (((xmax - xmin) / c).floor() as usize + 1).max(1);
        let ncy = (((ymax - ymin) / c).floor() as usize + 1).max(1);
        // Counting sort of particles into cells.
        self.cell_of.resize(n, 0);
        self.cell_of
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, cell)| {
                let cx = ((x[i] - xmin) / c) as usize;
                let cy = ((y[i] - ymin) / c) as usize;
                *cell = (cy.min(ncy - 1) * ncx + cx.min(ncx - 1)) as u32;
            });
        counting_offsets(&self.cell_of, ncx * ncy, &mut self.cell_start);
        self.cell_items.resize(n, 0);
        self.cell_fill.clone_from(&self.cell_start);
        for i in 0..n {
            let cell = self.cell_of[i] as usize;
            self.cell_items[self.cell_fill[cell] as usize] = i as u32;
            self.cell_fill[cell] += 1;
        }
        let c2 = c * c;
        let (cs, ci, co) = (&self.cell_start, &self.cell_items, &self.cell_of);
        // Partners j > i of particle i within the cut-off, pushed onto `row`. A cell lists
        // its particles in ascending order (the counting sort above fills it in index
        // order), so the partners j > i are the tail after a binary search.
        let visit = |i: usize, row: &mut Vec<u32>| {
            let cell = co[i] as usize;
            let (cx, cy) = (cell % ncx, cell / ncx);
            for gy in cy.saturating_sub(1)..=(cy + 1).min(ncy - 1) {
                for gx in cx.saturating_sub(1)..=(cx + 1).min(ncx - 1) {
                    let g = gy * ncx + gx;
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

    /// Same pairs as brute force, for a jittered lattice.
    #[test]
    fn matches_brute_force() {
        let mut x = Vec::new();
        let mut y = Vec::new();
        let mut s = 12345u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
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
}
