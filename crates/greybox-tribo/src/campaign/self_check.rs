//! A segment's check against its own signal: a step cut from a sliding run (by μ's level
//! changes or the plan's timing) should hold one level of μ. Two flat levels inside it, apart
//! by more than their noise allows, mean a step boundary the cut missed (two steps merged, an
//! unplanned piece taken as a step): the row's steady window may then belong to a neighbour,
//! and the row is flagged `label-contradicted`.

use super::change_points::split_into;
use crate::signal::{linear_fit, mean_std};
use crate::uncertainty::WindowMean;

/// The test statistic's threshold: the two levels must differ by this many standard errors
/// of their difference (each level's error under serial correlation).
const LEVELS_APART_SE: f64 = 5.0;

/// Where μ's block means `x` (one segment, `block_s` s a block) hold two flat levels: the
/// best split into two pieces of at least a quarter of the segment each (a ramp or settling
/// at the segment's start is shorter), whose levels differ by more than
/// [`LEVELS_APART_SE`] standard errors of their difference and by more than `floor`, and
/// whose first piece is as flat as the second (its spread about its mean at most twice the
/// second's, and a line over it changing by less than a quarter of the difference: a ramp
/// into the step or a run-in decays, an earlier step holds). Returns the split's position,
/// s from the segment's start, and the two levels.
pub(super) fn two_levels(x: &[f64], block_s: f64, floor: f64) -> Option<(f64, f64, f64)> {
    let n = x.len();
    if n < 16 {
        return None;
    }
    let c = *split_into(x, 2, n / 4)?.first()?;
    let (a, b) = (WindowMean::of(&x[..c])?, WindowMean::of(&x[c..])?);
    let diff = (a.mean - b.mean).abs();
    let se = a.sem.hypot(b.sem);
    let t: Vec<f64> = (0..c).map(|k| k as f64).collect();
    let (_, slope, _) = linear_fit(&t, &x[..c]);
    let (spread_a, spread_b) = (mean_std(&x[..c]).1, mean_std(&x[c..]).1);
    let flat = (slope * c as f64).abs() < 0.25 * diff && spread_a <= 2.0 * spread_b;
    (diff > LEVELS_APART_SE * se && diff > floor && flat).then_some((
        c as f64 * block_s,
        a.mean,
        b.mean,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(k: usize) -> f64 {
        0.002 * ((k * 7919 % 101) as f64 / 50.0 - 1.0)
    }

    #[test]
    fn two_steps_are_found_a_run_in_and_one_level_are_not() {
        // two steps of 60 blocks, 0.30 then 0.32
        let merged: Vec<f64> = (0..120)
            .map(|k| if k < 60 { 0.30 } else { 0.32 } + noise(k))
            .collect();
        let (at, a, b) = two_levels(&merged, 0.05, 0.003).expect("two levels");
        assert!((at - 3.0).abs() < 0.11 && (a - 0.30).abs() < 0.002 && (b - 0.32).abs() < 0.002);
        // a run-in decaying into one level
        let run_in: Vec<f64> = (0..120)
            .map(|k| 0.30 + 0.1 * (-(k as f64) / 15.0).exp() + noise(k))
            .collect();
        assert_eq!(two_levels(&run_in, 0.05, 0.003), None);
        let one: Vec<f64> = (0..120).map(|k| 0.30 + noise(k)).collect();
        assert_eq!(two_levels(&one, 0.05, 0.003), None);
    }
}
