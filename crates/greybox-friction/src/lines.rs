//! Axis lines with constant-time lookup, and the interpolation shared by the tables.
//!
//! [`Lines::rank`] counts the lines below `x` without a binary search (whose branches
//! mispredict on hundreds of lines): a uniform bucket index maps `x` to the first line that
//! can lie at or above it, and a short scan finishes. The bucket of `x` is
//! `min(⌊(x − lo) · scale⌋, buckets − 1)`, a monotone function of `x` under rounding, so a
//! bucket's first line (the count of lines in lower buckets) never overshoots, and the scan
//! only passes the lines of its own bucket.

use greybox_core::{Error, Result};

/// Most buckets of one axis (256 kB of `u32`).
const MAX_BUCKETS: usize = 1 << 16;
/// Bucket occupancy the index aims for.
const TARGET_PER_BUCKET: usize = 4;

/// Ascending, finite, distinct axis lines with a bucket index.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Lines {
    /// The lines followed by [`PAD`] +∞ sentinels (end every scan without a bounds check).
    padded: Vec<f64>,
    lo: f64,
    scale: f64,
    /// first[k]: number of lines in buckets below k.
    first: Vec<u32>,
}

/// Sentinels after the lines.
const PAD: usize = 1;

impl Lines {
    /// Index `lines`; `what` names the field in errors. Lines must be finite and strictly
    /// ascending (an empty axis is allowed: every x ranks 0).
    pub fn new(lines: &[f64], what: &str) -> Result<Self> {
        if let Some(i) = lines.iter().position(|x| !x.is_finite()) {
            return Err(Error::invalid(
                what,
                format!("value {} ({}) is not finite", i + 1, lines[i]),
            ));
        }
        if let Some(i) = lines.windows(2).position(|w| !(w[1] > w[0])) {
            return Err(Error::invalid(
                what,
                format!(
                    "values must be strictly ascending: value {} ({}) follows {}",
                    i + 2,
                    lines[i + 1],
                    lines[i]
                ),
            ));
        }
        if lines.len() >= u32::MAX as usize {
            return Err(Error::invalid(what, "too many lines"));
        }
        let mut padded = lines.to_vec();
        padded.extend([f64::INFINITY; PAD]);
        let mut s = Lines {
            padded,
            lo: lines.first().copied().unwrap_or(0.0),
            scale: 0.0,
            first: vec![0],
        };
        let n = lines.len();
        if n < 2 {
            return Ok(s);
        }
        let span = lines[n - 1] - lines[0];
        let mut buckets = n.next_power_of_two();
        loop {
            s.scale = if span.is_finite() && span > 0.0 {
                buckets as f64 / span
            } else {
                0.0
            };
            s.first = vec![0; buckets];
            let mut count = vec![0u32; buckets];
            for &x in lines {
                count[s.bucket_of(x, buckets)] += 1;
            }
            let mut acc = 0;
            for (f, c) in s.first.iter_mut().zip(&count) {
                *f = acc;
                acc += c;
            }
            let crowded = count.iter().copied().max().unwrap_or(0) as usize;
            if crowded <= TARGET_PER_BUCKET || buckets >= MAX_BUCKETS || buckets >= 64 * n {
                return Ok(s);
            }
            buckets *= 2;
        }
    }

    #[inline]
    fn bucket_of(&self, x: f64, buckets: usize) -> usize {
        // `as usize` saturates: below lo (and NaN) → 0, overflow → the last bucket
        (((x - self.lo) * self.scale) as usize).min(buckets - 1)
    }

    /// Number of lines strictly below `x` (0 for NaN): `x` lies in cell `rank` of the cells
    /// `l[r−1] < x ≤ l[r]`.
    #[inline]
    pub fn rank(&self, x: f64) -> usize {
        let k = self.bucket_of(x, self.first.len());
        let mut i = self.first[k] as usize;
        while self.padded[i] < x {
            i += 1;
        }
        i
    }

    /// Number of lines at or below `x` (0 for NaN): [`Lines::rank`] with `<=`, so that a
    /// node `x = l[k]` opens cell k rather than closing cell k − 1.
    #[inline]
    pub fn rank_le(&self, x: f64) -> usize {
        let x = if x > f64::MAX { f64::MAX } else { x }; // +∞ stops at the sentinel, NaN stays
        let k = self.bucket_of(x, self.first.len());
        let mut i = self.first[k] as usize;
        while self.padded[i] <= x {
            i += 1;
        }
        i
    }

    /// The lines.
    pub fn as_slice(&self) -> &[f64] {
        &self.padded[..self.len()]
    }

    /// Number of lines.
    pub fn len(&self) -> usize {
        self.padded.len() - PAD
    }

    /// Whether there are no lines.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Buckets of the index (for reports).
    pub fn buckets(&self) -> usize {
        self.first.len()
    }
}

/// Linear interpolation from `a` (f = 0) to `b` (f = 1) that is exact at both ends and where
/// `a == b`: a + f(b − a) for f ≤ ½, b + (1 − f)(a − b) above (1 − f is exact there). Both
/// are computed and one selected, without a branch to mispredict.
#[inline]
pub fn lerp(a: f64, b: f64, f: f64) -> f64 {
    let from_a = a + f * (b - a);
    let from_b = b + (1.0 - f) * (a - b);
    if f <= 0.5 {
        from_a
    } else {
        from_b
    }
}

/// Cell `j` (between lines j and j + 1) and fraction in it of `x` on nodes `l` (≥ 1 node),
/// clamped to the first and last node; `rank` is the number of nodes below `x`.
#[inline]
pub fn cell_of(l: &[f64], rank: usize, x: f64) -> (usize, f64) {
    let n = l.len();
    if n < 2 {
        return (0, 0.0);
    }
    let j = rank.clamp(1, n - 1) - 1;
    let f = ((x - l[j]) / (l[j + 1] - l[j])).clamp(0.0, 1.0);
    (j, f)
}

/// Multilinear interpolation on the tensor grid of `axes` (first axis fastest in `values`),
/// clamped at the edges; an axis with one node is constant along it. A plain reference
/// implementation (binary search per axis) for checks, not the tables' hot path.
pub fn multilinear(axes: [&[f64]; 3], values: &[f64], x: [f64; 3]) -> f64 {
    let mut idx = [(0usize, 0.0f64); 3];
    for a in 0..3 {
        let r = axes[a].partition_point(|&l| l < x[a]);
        idx[a] = cell_of(axes[a], r, x[a]);
    }
    let (n0, n1) = (axes[0].len(), axes[1].len());
    let at = |i: usize, j: usize, k: usize| values[(k * n1 + j) * n0 + i];
    let step = |a: usize, i: usize| (i + 1).min(axes[a].len() - 1);
    let plane = |k: usize| {
        let (i, fi) = idx[0];
        let (j, fj) = idx[1];
        let (i1, j1) = (step(0, i), step(1, j));
        let lo = lerp(at(i, j, k), at(i1, j, k), fi);
        let hi = lerp(at(i, j1, k), at(i1, j1, k), fi);
        lerp(lo, hi, fj)
    };
    let (k, fk) = idx[2];
    lerp(plane(k), plane(step(2, k)), fk)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn check(lines: &[f64], probes: &[f64]) {
        let l = Lines::new(lines, "test").unwrap();
        for &x in probes {
            let want = lines.partition_point(|&b| b < x);
            assert_eq!(l.rank(x), want, "x = {x:e}, lines {}", lines.len());
            let want = lines.partition_point(|&b| b <= x);
            assert_eq!(l.rank_le(x), want, "x = {x:e}, lines {}", lines.len());
        }
    }

    #[test]
    fn rank_equals_partition_point_everywhere() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for n in [0, 1, 2, 3, 17, 300, 2000] {
            // clustered lines: a few centres with tight spreads, plus ulp neighbours
            let mut lines: Vec<f64> = (0..n)
                .map(|i| {
                    let c = (i % 7) as f64 * 1e8 + 9e8;
                    c + rng.gen_range(-1e3..1e3) * if i % 3 == 0 { 1e-9 } else { 1.0 }
                })
                .collect();
            lines.sort_by(f64::total_cmp);
            lines.dedup();
            let mut probes = vec![f64::NAN, f64::NEG_INFINITY, f64::INFINITY, -1.0, 0.0];
            for &b in &lines {
                probes.extend([b.next_down(), b, b.next_up()]);
            }
            for _ in 0..2000 {
                probes.push(rng.gen_range(8e8..1.7e9));
            }
            check(&lines, &probes);
        }
        check(
            &[-f64::MAX, 0.0, f64::MAX],
            &[-1e308, -0.0, 1.0, f64::MAX, 1e300],
        );
    }

    #[test]
    fn bad_lines_name_the_field() {
        let e = Lines::new(&[1.0, 1.0], "pressure_Pa")
            .unwrap_err()
            .to_string();
        assert!(e.contains("pressure_Pa") && e.contains("ascending"), "{e}");
        let e = Lines::new(&[1.0, f64::NAN], "temperature_K")
            .unwrap_err()
            .to_string();
        assert!(e.contains("temperature_K") && e.contains("finite"), "{e}");
    }

    #[test]
    fn lerp_is_exact_at_ends_and_for_constants() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        for _ in 0..10_000 {
            let (a, b): (f64, f64) = (rng.gen(), rng.gen());
            let f: f64 = rng.gen();
            assert_eq!(lerp(a, b, 0.0), a);
            assert_eq!(lerp(a, b, 1.0), b);
            assert_eq!(lerp(a, a, f), a);
        }
    }
}
