//! Steady-force detection: the tool force is averaged over consecutive blocks of simulated
//! time; the force counts as steady once, over the last `blocks` blocks, (a) every block mean
//! lies within a relative `tolerance` of their common mean and (b) the least-squares trend
//! changes the force by less than the tolerance across those blocks (a slow rise of a few
//! per cent per block passes (a) but not (b)). Both components are checked, the tolerance
//! taken relative to the larger one, so that a small feed force does not stall the test on
//! its noise.

use crate::executor::{Control, Observer};
use crate::solver::{SimError, Solver};

/// Mean tool force over one block, N/m.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ForceBlock {
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub force: [f64; 2],
}

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SteadyForce {
    pub tool: usize,
    pub block_s: f64,
    pub blocks_needed: usize,
    pub tolerance: f64,
    /// Stop the run when steady.
    pub stop: bool,
    pub blocks: Vec<ForceBlock>,
    /// Start time of the first steady block, once steady.
    pub steady_since_s: Option<f64>,
    /// No steady state before this simulated time, s (the set-up's minimum cut length).
    #[serde(default)]
    pub min_time_s: f64,
    sum: [f64; 2],
    n: u64,
    t_start: f64,
    /// Restored from a checkpoint: the block in progress started before this run.
    #[serde(skip)]
    pub resumed: bool,
}

impl SteadyForce {
    pub fn new(tool: usize, block_s: f64, blocks: usize, tolerance: f64, stop: bool) -> Self {
        SteadyForce {
            tool,
            block_s,
            blocks_needed: blocks.max(2),
            tolerance,
            stop,
            blocks: Vec::new(),
            steady_since_s: None,
            min_time_s: 0.0,
            sum: [0.0; 2],
            n: 0,
            t_start: 0.0,
            resumed: false,
        }
    }

    /// No steady state before `t` s.
    pub fn not_before(mut self, t: f64) -> Self {
        self.min_time_s = t;
        self
    }

    /// Closes the block in progress at time `now`, s; true when the force became steady
    /// with it (the last `blocks_needed` blocks agree and `now` is past `min_time_s`).
    fn close_block(&mut self, now: f64) -> bool {
        let n = self.n.max(1) as f64;
        self.blocks.push(ForceBlock {
            t_start_s: self.t_start,
            t_end_s: now,
            force: [self.sum[0] / n, self.sum[1] / n],
        });
        self.sum = [0.0; 2];
        self.n = 0;
        self.t_start = now;
        let long_enough = now >= self.min_time_s * (1.0 - 1e-9);
        if self.steady_since_s.is_some() || !long_enough || !self.last_blocks_steady() {
            return false;
        }
        self.steady_since_s = Some(self.blocks[self.blocks.len() - self.blocks_needed].t_start_s);
        true
    }

    /// Whether the last `blocks_needed` blocks agree within the tolerance.
    fn last_blocks_steady(&self) -> bool {
        let k = self.blocks_needed;
        if self.blocks.len() < k {
            return false;
        }
        let tail = &self.blocks[self.blocks.len() - k..];
        let mean = |c: usize| tail.iter().map(|b| b.force[c]).sum::<f64>() / k as f64;
        let m = [mean(0), mean(1)];
        let scale = m[0].abs().max(m[1].abs());
        // Least-squares trend over the tail: a slow drift passes the scatter test block by
        // block, so the fitted change across the tail must stay within the tolerance too.
        let ic = 0.5 * (k - 1) as f64;
        let sxx: f64 = (0..k).map(|i| (i as f64 - ic).powi(2)).sum();
        let change = |c: usize| {
            let sxy: f64 = tail
                .iter()
                .enumerate()
                .map(|(i, b)| (i as f64 - ic) * (b.force[c] - m[c]))
                .sum();
            (sxy / sxx * (k - 1) as f64).abs()
        };
        let tol = self.tolerance * scale;
        scale > 0.0
            && (0..2).all(|c| change(c) <= tol)
            && tail
                .iter()
                .all(|b| (0..2).all(|c| (b.force[c] - m[c]).abs() <= tol))
    }

    /// Mean force over the steady blocks (from `steady_since_s` on), N/m.
    pub fn steady_mean(&self) -> Option<[f64; 2]> {
        let t0 = self.steady_since_s?;
        let b: Vec<&ForceBlock> = self.blocks.iter().filter(|b| b.t_start_s >= t0).collect();
        let n = b.len() as f64;
        Some([
            b.iter().map(|b| b.force[0]).sum::<f64>() / n,
            b.iter().map(|b| b.force[1]).sum::<f64>() / n,
        ])
    }
}

impl Observer for SteadyForce {
    fn start(&mut self, sim: &Solver) -> Result<(), SimError> {
        if !self.resumed {
            self.t_start = sim.time;
        }
        Ok(())
    }
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        Some(("steady", serde_json::to_value(self).ok()?))
    }
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        let f = sim.tools.get(self.tool).map_or([0.0; 2], |t| t.force);
        self.sum[0] += f[0];
        self.sum[1] += f[1];
        self.n += 1;
        let block_done = sim.time - self.t_start >= self.block_s * (1.0 - 1e-9);
        if block_done && self.close_block(sim.time) && self.stop {
            return Ok(Control::Stop);
        }
        Ok(Control::Continue)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn detector(forces: &[[f64; 2]]) -> SteadyForce {
        let mut d = SteadyForce::new(0, 1.0, 3, 0.03, true);
        for (k, f) in forces.iter().enumerate() {
            d.blocks.push(ForceBlock {
                t_start_s: k as f64,
                t_end_s: k as f64 + 1.0,
                force: *f,
            });
            if d.steady_since_s.is_none() && d.last_blocks_steady() {
                d.steady_since_s = Some(d.blocks[d.blocks.len() - 3].t_start_s);
            }
        }
        d
    }

    #[test]
    fn rising_force_is_not_steady_until_it_levels_off() {
        let d = detector(&[
            [50.0, 10.0],
            [150.0, 40.0],
            [250.0, 60.0],
            [290.0, 70.0],
            [300.0, 72.0],
            [296.0, 71.0],
            [302.0, 73.0],
        ]);
        // Blocks 3–5 (290, 300, 296) are the first three within 3 % of their mean.
        assert_eq!(d.steady_since_s, Some(3.0));
        let m = d.steady_mean().unwrap();
        assert!((m[0] - 297.0).abs() < 1e-9 && (m[1] - 71.5).abs() < 1e-9);
        // Still rising by 5 % per block: never steady.
        let d = detector(&[[100.0, 0.0], [105.0, 0.0], [110.25, 0.0], [115.8, 0.0]]);
        assert_eq!(d.steady_since_s, None);
        // Rising by 2 % per block: each block within 3 % of the mean, but a 4 % trend.
        let d = detector(&[[100.0, 0.0], [102.0, 0.0], [104.0, 0.0], [106.0, 0.0]]);
        assert_eq!(d.steady_since_s, None);
        assert_eq!(d.steady_mean(), None);
    }

    /// Blocks of constant force 100 N/m, one per second, closed through the observer's path.
    fn closed_blocks(min_time_s: f64, count: usize) -> (SteadyForce, Option<usize>) {
        let mut d = SteadyForce::new(0, 1.0, 3, 0.03, true).not_before(min_time_s);
        let mut first = None;
        for k in 0..count {
            d.sum = [100.0, 20.0];
            d.n = 1;
            if d.close_block(k as f64 + 1.0) && first.is_none() {
                first = Some(k + 1);
            }
        }
        (d, first)
    }

    #[test]
    fn no_steady_state_before_the_minimum_cut_length() {
        // Without a minimum: steady when the third block closes (t = 3 s).
        let (d, first) = closed_blocks(0.0, 8);
        assert_eq!((first, d.steady_since_s), (Some(3), Some(0.0)));
        // A minimum of 5.5 s: the first block closing after it (t = 6 s), averaged over the
        // three blocks before.
        let (d, first) = closed_blocks(5.5, 8);
        assert_eq!((first, d.steady_since_s), (Some(6), Some(3.0)));
        assert_eq!(d.steady_mean(), Some([100.0, 20.0]));
        // Never, when the run is shorter.
        assert_eq!(closed_blocks(9.0, 8).1, None);
    }
}
