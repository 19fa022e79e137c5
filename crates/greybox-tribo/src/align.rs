//! Segments matched to a plan's steps by sequence alignment instead of count and order.
//!
//! The segments found in the recordings and the plan's steps are two sequences; matching
//! them is an edit-distance problem (Needleman & Wunsch 1970, "A general method applicable
//! to the search for similarities in the amino acid sequence of two proteins") solved by
//! dynamic programming over their prefixes. Each pairing costs the segment's distance to the
//! step — relative load, relative speed where the segment has one, relative duration where
//! the plan has one — each as a log ratio divided by its tolerance and averaged, so a
//! pairing within tolerance costs at most 1 and one outside any tolerance is not allowed
//! (`match_load_tolerance`, `match_speed_tolerance`, `match_duration_tolerance`: the
//! duration's is wide, a factor 2 by default, since a segment is the step's sliding time
//! without its ramps). The
//! other moves are:
//!
//! * an **extra segment** (an unplanned run-in, a repeated step): `unmatched_segment_cost`,
//!   halved for the first segment of a file whose μ was still running in or drifting (a
//!   run-in the plan omits sits there) and 0.9× for any other first segment of a file;
//! * a **missing step** (never run, or lost): `unmatched_step_cost`;
//! * a **merged step**, where the plan gives durations: one segment spanning two consecutive
//!   steps at the same load whose durations it adds up to better than either alone; the row
//!   goes to the later step (the steady part is the segment's end) and the earlier is
//!   reported as merged.
//!
//! Files are aligned in plan order: each file's segments are first placed against the whole
//! plan (free start and end), files are ordered by where they fit, and the concatenation is
//! aligned globally; a file recorded out of the plan's order is reported as reordered.
//! Steps a rig ran out of the plan's order within a file are then paired from what the
//! alignment left over, where the segments have a measured speed (nearest load and speed
//! first), and reported as reordered. A count mismatch alone is never an error: unmatched
//! steps and extra segments are reported by name.

use crate::config::IdentifyConfig;
use crate::expected::ExpectedStep;

/// A segment as the alignment sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Candidate {
    pub file: usize,
    pub load_n: f64,
    pub velocity_m_s: Option<f64>,
    pub duration_s: f64,
    /// The first measured segment of its file.
    pub first_in_file: bool,
    /// μ was still running in or drifting over the segment.
    pub running_in: bool,
    /// The segment's boundaries come from the recording's step column or blocks.
    pub step_column: bool,
    /// The segment's boundaries come from the plan's step durations.
    pub plan_timed: bool,
}

/// What each segment became.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Assigned {
    Step(usize),
    /// A row for the later step; the earlier one was merged into the segment.
    Merged {
        earlier: usize,
        later: usize,
    },
    Extra,
}

/// The largest alignment table, cells (segments × steps); a campaign beyond it is refused
/// with this cap named (about 10 bytes a cell).
pub const MAX_ALIGNMENT_CELLS: usize = 20_000_000;

/// Costs and tolerances of one alignment.
struct Costs<'a> {
    cfg: &'a IdentifyConfig,
}

impl Costs<'_> {
    /// Cost of pairing segment `s` with step `e` (`None`: outside the load or speed
    /// tolerance); `duration_s` overrides the step's planned duration (a merged pair).
    fn pair(&self, s: &Candidate, e: &ExpectedStep, duration_s: Option<f64>) -> Option<f64> {
        let (tol_f, tol_v) = (
            (1.0 + self.cfg.match_load_tolerance).ln(),
            (1.0 + self.cfg.match_speed_tolerance).ln(),
        );
        let df = (s.load_n / e.normal_force_n).ln().abs() / tol_f;
        if !(df <= 1.0) {
            return None;
        }
        let mut sum = df;
        let mut dims = 1.0;
        if let Some(v) = s.velocity_m_s {
            let dv = (v / e.sliding_velocity_m_s).ln().abs() / tol_v;
            if !(dv <= 1.0) {
                return None;
            }
            sum += dv;
            dims += 1.0;
        }
        if let Some(d) = duration_s.or(e.duration_s) {
            let tol_d = (1.0 + self.cfg.match_duration_tolerance).ln();
            let dd = (s.duration_s.max(1e-9) / d).ln().abs() / tol_d;
            if !(dd <= 1.0) {
                return None;
            }
            sum += dd;
            dims += 1.0;
        }
        Some(sum / dims)
    }

    fn extra(&self, s: &Candidate) -> f64 {
        let c = self.cfg.unmatched_segment_cost;
        match (s.first_in_file, s.running_in) {
            (true, true) => 0.5 * c,
            (true, false) => 0.9 * c,
            _ => c,
        }
    }

    fn missing(&self) -> f64 {
        self.cfg.unmatched_step_cost
    }

    /// Cost of segment `s` spanning steps `a` and `b = a + 1` (durations known, loads and
    /// speeds alike), when that fits better than `b` alone.
    fn merged(&self, s: &Candidate, a: &ExpectedStep, b: &ExpectedStep) -> Option<f64> {
        let (da, db) = (a.duration_s?, b.duration_s?);
        if a.pin != b.pin {
            return None;
        }
        let both = self.pair(s, b, Some(da + db))?;
        self.pair(s, a, None)?;
        let alone = self.pair(s, b, None).unwrap_or(f64::INFINITY);
        (both < alone).then_some(both + 0.5 * self.missing())
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Move {
    Pair,
    Merge,
    Extra,
    Missing,
    Start,
}

/// The forward table of the alignment of `segs` with `steps`: `cost[i·(m+1) + j]` the least
/// cost of aligning the first i segments with the first j steps, and the move that reached
/// each cell; `free_ends`: steps before the first pairing cost nothing.
fn forward(
    segs: &[Candidate],
    steps: &[ExpectedStep],
    costs: &Costs,
    free_ends: bool,
) -> (Vec<f64>, Vec<Move>) {
    let (n, m) = (segs.len(), steps.len());
    let w = m + 1;
    let mut cost = vec![f64::INFINITY; (n + 1) * w];
    let mut back = vec![Move::Start; (n + 1) * w];
    cost[0] = 0.0;
    for j in 1..=m {
        cost[j] = if free_ends {
            0.0
        } else {
            j as f64 * costs.missing()
        };
        back[j] = Move::Missing;
    }
    for i in 1..=n {
        let s = &segs[i - 1];
        cost[i * w] = cost[(i - 1) * w] + costs.extra(s);
        back[i * w] = Move::Extra;
        for j in 1..=m {
            let mut best = (cost[(i - 1) * w + j] + costs.extra(s), Move::Extra);
            let miss = cost[i * w + j - 1] + costs.missing();
            if miss < best.0 {
                best = (miss, Move::Missing);
            }
            if let Some(c) = costs.pair(s, &steps[j - 1], None) {
                let v = cost[(i - 1) * w + j - 1] + c;
                if v <= best.0 {
                    best = (v, Move::Pair);
                }
            }
            if j >= 2 {
                if let Some(c) = costs.merged(s, &steps[j - 2], &steps[j - 1]) {
                    let v = cost[(i - 1) * w + j - 2] + c;
                    if v < best.0 {
                        best = (v, Move::Merge);
                    }
                }
            }
            cost[i * w + j] = best.0;
            back[i * w + j] = best.1;
        }
    }
    (cost, back)
}

/// The backward table: `cost[i·(m+1) + j]` the least cost of aligning the segments from i on
/// with the steps from j on (every step consumed), by the same moves as [`forward`].
fn backward(segs: &[Candidate], steps: &[ExpectedStep], costs: &Costs) -> Vec<f64> {
    let (n, m) = (segs.len(), steps.len());
    let w = m + 1;
    let mut cost = vec![f64::INFINITY; (n + 1) * w];
    for j in (0..=m).rev() {
        cost[n * w + j] = (m - j) as f64 * costs.missing();
    }
    for i in (0..n).rev() {
        let s = &segs[i];
        for j in (0..=m).rev() {
            let mut best = cost[(i + 1) * w + j] + costs.extra(s);
            if j < m {
                best = best.min(cost[i * w + j + 1] + costs.missing());
                if let Some(c) = costs.pair(s, &steps[j], None) {
                    best = best.min(cost[(i + 1) * w + j + 1] + c);
                }
            }
            if j + 1 < m {
                if let Some(c) = costs.merged(s, &steps[j], &steps[j + 1]) {
                    best = best.min(cost[(i + 1) * w + j + 2] + c);
                }
            }
            cost[i * w + j] = best;
        }
    }
    cost
}

/// Align `segs` (in their order) with `steps`; `free_ends`: steps before the first and after
/// the last pairing cost nothing (placing one file against the whole plan). Returns the
/// total cost and, per segment, what it became (step indices into `steps`).
fn align_sequence(
    segs: &[Candidate],
    steps: &[ExpectedStep],
    costs: &Costs,
    free_ends: bool,
) -> (f64, Vec<Assigned>) {
    let (n, m) = (segs.len(), steps.len());
    let w = m + 1;
    let (cost, back) = forward(segs, steps, costs, free_ends);
    // the end: all steps consumed, or (free ends) wherever the last pairing left off
    let mut j = m;
    if free_ends {
        j = (0..=m)
            .min_by(|a, b| cost[n * w + a].total_cmp(&cost[n * w + b]))
            .unwrap_or(m);
    }
    let total = cost[n * w + j];
    let mut out = vec![Assigned::Extra; n];
    let mut i = n;
    while i > 0 || j > 0 {
        match back[i * w + j] {
            Move::Pair => {
                out[i - 1] = Assigned::Step(j - 1);
                i -= 1;
                j -= 1;
            }
            Move::Merge => {
                out[i - 1] = Assigned::Merged {
                    earlier: j - 2,
                    later: j - 1,
                };
                i -= 1;
                j -= 2;
            }
            Move::Extra => i -= 1,
            Move::Missing | Move::Start => {
                if j == 0 {
                    i -= 1;
                } else {
                    j -= 1;
                }
            }
        }
    }
    (total, out)
}

/// Per segment of a full alignment (`assigned`, every step consumed), whether another
/// alignment costing less than `margin` more than the best places it elsewhere (another step
/// for its row, or no step): the least total cost of each other outcome of segment i is
/// forward(i, j) + the move's cost + backward(after the move), over every j.
fn ambiguous(
    segs: &[Candidate],
    steps: &[ExpectedStep],
    costs: &Costs,
    assigned: &[Assigned],
    margin: f64,
) -> Vec<bool> {
    let (n, m) = (segs.len(), steps.len());
    let w = m + 1;
    let (fwd, _) = forward(segs, steps, costs, false);
    let bwd = backward(segs, steps, costs);
    let best = fwd[n * w + m];
    let row_of = |a: Assigned| match a {
        Assigned::Step(e) | Assigned::Merged { later: e, .. } => Some(e),
        Assigned::Extra => None,
    };
    (0..n)
        .map(|i| {
            let s = &segs[i];
            let own = row_of(assigned[i]);
            let mut alt = f64::INFINITY;
            for j in 0..=m {
                let f = fwd[i * w + j];
                if !f.is_finite() {
                    continue;
                }
                if own.is_some() {
                    alt = alt.min(f + costs.extra(s) + bwd[(i + 1) * w + j]);
                }
                if j < m && own != Some(j) {
                    if let Some(c) = costs.pair(s, &steps[j], None) {
                        alt = alt.min(f + c + bwd[(i + 1) * w + j + 1]);
                    }
                }
                if j + 1 < m && own != Some(j + 1) {
                    if let Some(c) = costs.merged(s, &steps[j], &steps[j + 1]) {
                        alt = alt.min(f + c + bwd[(i + 1) * w + j + 2]);
                    }
                }
            }
            alt - best < margin
        })
        .collect()
}

/// What a pairing of segment `s` with step `steps[e]` rests on
/// ([`greybox_core::dataset::label_evidence`]), strongest first: the recording's step
/// column, the plan's timing, a measured speed, a load no other planned step has, a duration
/// no other planned step at that load fits, else the order alone.
pub(crate) fn evidence(
    s: &Candidate,
    e: usize,
    steps: &[ExpectedStep],
    cfg: &IdentifyConfig,
) -> &'static str {
    use greybox_core::dataset::label_evidence as ev;
    let costs = Costs { cfg };
    let others = || steps.iter().enumerate().filter(move |(k, _)| *k != e);
    let load_only = Candidate {
        velocity_m_s: None,
        ..*s
    };
    let no_duration = |x: &ExpectedStep| ExpectedStep {
        duration_s: None,
        ..x.clone()
    };
    if s.step_column {
        ev::STEP_COLUMN
    } else if s.plan_timed {
        ev::PLAN_TIMING
    } else if s.velocity_m_s.is_some() {
        ev::MEASURED_SPEED
    } else if others().all(|(_, x)| costs.pair(&load_only, &no_duration(x), None).is_none()) {
        ev::MEASURED_LOAD
    } else if steps[e].duration_s.is_some()
        && others().all(|(_, x)| costs.pair(&load_only, x, None).is_none())
    {
        ev::DURATION
    } else {
        ev::ORDER
    }
}

/// The alignment of a campaign's segments with its plan.
pub(crate) struct Alignment {
    /// Per segment (in the order given).
    pub assigned: Vec<Assigned>,
    /// Per segment: another alignment within `ambiguity_margin` of the best places it
    /// elsewhere.
    pub ambiguous: Vec<bool>,
    /// Files, as indices, in the order they were aligned (plan order).
    pub file_order: Vec<usize>,
}

/// Align every file's segments with the plan (see the module documentation). `segs` are in
/// campaign order, grouped by file.
pub(crate) fn align(
    segs: &[Candidate],
    steps: &[ExpectedStep],
    cfg: &IdentifyConfig,
) -> std::result::Result<Alignment, String> {
    let cells = (segs.len() + 1).saturating_mul(steps.len() + 1);
    if cells > MAX_ALIGNMENT_CELLS {
        return Err(format!(
            "{} segments against {} planned steps need an alignment table of {cells} cells, more than the cap of {MAX_ALIGNMENT_CELLS}: identify the pins in separate runs",
            segs.len(),
            steps.len()
        ));
    }
    let costs = Costs { cfg };
    let mut files: Vec<usize> = segs.iter().map(|s| s.file).collect();
    files.dedup();
    // where each file fits in the plan: its first paired step
    let mut placed: Vec<(usize, usize)> = files
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            let own: Vec<Candidate> = segs.iter().copied().filter(|s| s.file == f).collect();
            let (_, a) = align_sequence(&own, steps, &costs, true);
            let first = a
                .iter()
                .find_map(|x| match x {
                    Assigned::Step(e) => Some(*e),
                    Assigned::Merged { earlier, .. } => Some(*earlier),
                    Assigned::Extra => None,
                })
                .unwrap_or(usize::MAX);
            (first, k)
        })
        .collect();
    placed.sort();
    let file_order: Vec<usize> = placed.iter().map(|(_, k)| files[*k]).collect();
    let mut order: Vec<usize> = Vec::with_capacity(segs.len());
    for f in &file_order {
        order.extend((0..segs.len()).filter(|i| segs[*i].file == *f));
    }
    let sorted: Vec<Candidate> = order.iter().map(|i| segs[*i]).collect();
    let (_, a) = align_sequence(&sorted, steps, &costs, false);
    let near = ambiguous(&sorted, steps, &costs, &a, cfg.ambiguity_margin);
    let mut assigned = vec![Assigned::Extra; segs.len()];
    let mut ambiguous_seg = vec![false; segs.len()];
    for (k, i) in order.iter().enumerate() {
        assigned[*i] = a[k];
        ambiguous_seg[*i] = near[k];
    }
    pair_reordered(segs, steps, &costs, &mut assigned);
    Ok(Alignment {
        assigned,
        ambiguous: ambiguous_seg,
        file_order,
    })
}

/// Steps run out of the plan's order: segments left over by the alignment that have a
/// measured speed are paired with steps left over, nearest first (load and speed both within
/// tolerance; without a speed, load alone is too weak to reorder on).
fn pair_reordered(
    segs: &[Candidate],
    steps: &[ExpectedStep],
    costs: &Costs,
    assigned: &mut [Assigned],
) {
    let mut used = vec![false; steps.len()];
    for a in assigned.iter() {
        match a {
            Assigned::Step(e) => used[*e] = true,
            Assigned::Merged { earlier, later } => {
                used[*earlier] = true;
                used[*later] = true;
            }
            Assigned::Extra => {}
        }
    }
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (si, s) in segs.iter().enumerate() {
        if assigned[si] != Assigned::Extra || s.velocity_m_s.is_none() {
            continue;
        }
        for (ei, e) in steps.iter().enumerate().filter(|(ei, _)| !used[*ei]) {
            if let Some(c) = costs.pair(s, e, None) {
                pairs.push((c, si, ei));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    for (_, si, ei) in pairs {
        if assigned[si] == Assigned::Extra && !used[ei] {
            assigned[si] = Assigned::Step(ei);
            used[ei] = true;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(pin: u32, step: u32, f: f64, v: f64, d: Option<f64>) -> ExpectedStep {
        ExpectedStep {
            pin,
            step,
            normal_force_n: f,
            sliding_velocity_m_s: v,
            duration_s: d,
        }
    }

    fn seg(file: usize, f: f64, v: Option<f64>, d: f64, first: bool) -> Candidate {
        Candidate {
            file,
            load_n: f,
            velocity_m_s: v,
            duration_s: d,
            first_in_file: first,
            running_in: false,
            step_column: false,
            plan_timed: false,
        }
    }

    #[test]
    fn an_unplanned_run_in_is_skipped_not_shifted() {
        // plan: 3 steps at 100 N, 1/2/3 m/s; recording: a run-in at 2 m/s, then the steps
        let plan: Vec<_> = (1..=3).map(|k| step(1, k, 100.0, k as f64, None)).collect();
        let mut segs = vec![seg(0, 100.0, Some(2.0), 60.0, true)];
        segs.extend((1..=3).map(|k| seg(0, 100.0, Some(k as f64), 10.0, false)));
        let a = align(&segs, &plan, &IdentifyConfig::default()).unwrap();
        assert_eq!(
            a.assigned,
            vec![
                Assigned::Extra,
                Assigned::Step(0),
                Assigned::Step(1),
                Assigned::Step(2)
            ]
        );
    }

    #[test]
    fn without_speeds_durations_place_the_run_in_and_a_missing_step() {
        // no speed channel: loads alike, durations tell; the second step was never run
        let plan: Vec<_> = (1..=4)
            .map(|k| step(1, k, 100.0, k as f64, Some(10.0)))
            .collect();
        let segs = vec![
            seg(0, 100.0, None, 40.0, true),
            seg(0, 100.0, None, 9.5, false),
            seg(0, 100.0, None, 9.6, false),
            seg(0, 100.0, None, 9.4, false),
        ];
        let a = align(&segs, &plan, &IdentifyConfig::default()).unwrap();
        assert_eq!(a.assigned[0], Assigned::Extra);
        assert_eq!(
            a.assigned
                .iter()
                .filter(|x| matches!(x, Assigned::Step(_)))
                .count(),
            3
        );
    }

    #[test]
    fn a_segment_spanning_two_steps_is_a_merge() {
        let plan: Vec<_> = (1..=3)
            .map(|k| step(1, k, 100.0, 1.0, Some(10.0)))
            .collect();
        let segs = vec![
            seg(0, 100.0, None, 10.0, true),
            seg(0, 100.0, None, 19.5, false),
        ];
        let a = align(&segs, &plan, &IdentifyConfig::default()).unwrap();
        assert_eq!(
            a.assigned,
            vec![
                Assigned::Step(0),
                Assigned::Merged {
                    earlier: 1,
                    later: 2
                }
            ]
        );
    }

    #[test]
    fn files_out_of_plan_order_are_placed_by_their_loads() {
        let plan = vec![
            step(1, 1, 100.0, 1.0, None),
            step(1, 2, 100.0, 2.0, None),
            step(2, 1, 300.0, 1.0, None),
            step(2, 2, 300.0, 2.0, None),
        ];
        let segs = vec![
            seg(0, 300.0, None, 5.0, true),
            seg(0, 300.0, None, 5.0, false),
            seg(1, 100.0, None, 5.0, true),
            seg(1, 100.0, None, 5.0, false),
        ];
        let a = align(&segs, &plan, &IdentifyConfig::default()).unwrap();
        assert_eq!(a.file_order, vec![1, 0]);
        assert_eq!(
            a.assigned,
            vec![
                Assigned::Step(2),
                Assigned::Step(3),
                Assigned::Step(0),
                Assigned::Step(1)
            ]
        );
    }
}
