//! Verlet neighbour lists built from a cell list.
//!
//! Lists hold every pair closer than 2h + skin; they are rebuilt when any particle has moved
//! more than skin/2 since the last build, so no pair inside 2h is ever missed. Storage is
//! padded rows of a common width, built in two parallel passes (count, fill).

use rayon::prelude::*;

#[derive(Debug, Clone, Default)]
pub struct NeighbourList {
    /// Row width: particle i's neighbours are `index[i·stride .. i·stride + count[i]]`.
    pub stride: usize,
    /// Neighbour count per particle.
    pub count: Vec<u32>,
    /// Neighbour indices (self excluded), padded rows.
    pub index: Vec<u32>,
    /// Positions at the last build.
    x0: Vec<f64>,
    y0: Vec<f64>,
    /// Cell list scratch.
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

    /// Rebuilds the lists for positions (x, y).
    pub fn build(&mut self, x: &[f64], y: &[f64]) {
        let n = x.len();
        let c = self.cutoff;
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
        self.cell_start.clear();
        self.cell_start.resize(ncx * ncy + 1, 0);
        for &cell in &self.cell_of {
            self.cell_start[cell as usize + 1] += 1;
        }
        for k in 0..ncx * ncy {
            self.cell_start[k + 1] += self.cell_start[k];
        }
        self.cell_items.resize(n, 0);
        self.cell_fill.clone_from(&self.cell_start);
        for i in 0..n {
            let cell = self.cell_of[i] as usize;
            self.cell_items[self.cell_fill[cell] as usize] = i as u32;
            self.cell_fill[cell] += 1;
        }
        let c2 = c * c;
        let (cs, ci, co) = (&self.cell_start, &self.cell_items, &self.cell_of);
        let visit = |i: usize, f: &mut dyn FnMut(u32)| {
            let cell = co[i] as usize;
            let (cx, cy) = (cell % ncx, cell / ncx);
            for gy in cy.saturating_sub(1)..=(cy + 1).min(ncy - 1) {
                for gx in cx.saturating_sub(1)..=(cx + 1).min(ncx - 1) {
                    let g = gy * ncx + gx;
                    for &j in &ci[cs[g] as usize..cs[g + 1] as usize] {
                        let ju = j as usize;
                        if ju != i && (x[i] - x[ju]).powi(2) + (y[i] - y[ju]).powi(2) < c2 {
                            f(j);
                        }
                    }
                }
            }
        };
        self.count.resize(n, 0);
        self.count.par_iter_mut().enumerate().for_each(|(i, k)| {
            let mut m = 0u32;
            visit(i, &mut |_| m += 1);
            *k = m;
        });
        // Padded rows of `stride` entries (the classic fixed-width neighbour list): uniform
        // chunks parallelise without bookkeeping and port directly to a GPU.
        let stride = self.count.iter().copied().max().unwrap_or(0).max(1) as usize;
        self.stride = stride;
        self.index.clear();
        self.index.resize(n * stride, 0);
        self.index
            .par_chunks_mut(stride)
            .enumerate()
            .for_each(|(i, row)| {
                let mut k = 0;
                visit(i, &mut |j| {
                    row[k] = j;
                    k += 1;
                });
            });
        self.x0.clear();
        self.x0.extend_from_slice(x);
        self.y0.clear();
        self.y0.extend_from_slice(y);
        self.builds += 1;
    }

    #[inline]
    pub fn of(&self, i: usize) -> &[u32] {
        &self.index[i * self.stride..i * self.stride + self.count[i] as usize]
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
            let mut got: Vec<u32> = nl.of(i).to_vec();
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
        assert!(!nl.needs_rebuild(&x, &y));
        x[7] += 0.2;
        assert!(nl.needs_rebuild(&x, &y));
    }
}
