//! Linear reciprocating tests (ASTM G133-05, "Standard Test Method for Linearly Reciprocating
//! Ball-on-Flat Sliding Wear"): strokes and cycles instead of plateaus.
//!
//! In a reciprocating test the friction force changes sign with the sliding direction, so a
//! plateau average of F_t/F_N is meaningless (it tends to zero). ASTM G133 reports the
//! friction force per direction from the part of the stroke away from the reversals; greybox
//! does this:
//!
//! 1. **Strokes** (half-cycles), from the best evidence: the turning points of a recorded
//!    stroke position (hysteresis of a tenth of the stroke); else the rig's blocks or step
//!    column when each block is one half-stroke (CETR/Bruker UMT exports write one block per
//!    half-stroke; the blocks' friction force alternates in sign); else the sign changes of
//!    the smoothed friction force with a hysteresis deadband from its noise. Incomplete
//!    strokes (shorter than 70 % of the median stroke, or unloaded) are left out.
//! 2. **Mid-stroke part**: the middle 50 % of each stroke by position (where there is a
//!    position), else by time; the turnaround transients lie outside it.
//! 3. **μ per stroke** = mean(F_t·s)/mean(F_N) over the mid-stroke part, the sign s taken by
//!    the direction so that both directions give a positive μ. *Forward* is increasing
//!    position (or, without one, positive F_t as recorded).
//! 4. **Cycles** = a forward and a backward stroke following each other; per cycle μ forward,
//!    μ backward and their mean.
//! 5. **Steady cycles**: the final stationary stretch of the per-cycle mean μ after the
//!    run-in ([`crate::steady_window::final_stationary`], G133 §9 practice; all cycles below 16), or
//!    the user's [`SteadyRule`] applied to cycles (`last:50%` = the last half of the cycles,
//!    `from:Ts` = cycles starting T s or more after the first). μ per direction and averaged
//!    over those cycles is the test's result.

use crate::config::{IdentifyConfig, SteadyRule};
use crate::signal::{linear_fit, mad_sigma, mean_std, moving_average};
use crate::steady_window::{rule_span, steady_stretch, Settling};
use greybox_core::stats::median;
use greybox_recording::TestMode;
use greybox_recording::{Recording, SpeedTrace};
use serde::Serialize;

/// Where the strokes came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StrokeSource {
    /// Turning points of the position channel.
    Position,
    /// One block (or step-column run) per half-stroke.
    Blocks,
    /// Sign changes of the smoothed friction force.
    ForceSign,
}

impl StrokeSource {
    pub fn describe(self) -> &'static str {
        match self {
            StrokeSource::Position => "turning points of the position",
            StrokeSource::Blocks => "blocks (one per half-stroke)",
            StrokeSource::ForceSign => "sign changes of the friction force",
        }
    }
}

/// The channels strokes are found in (forces after baseline correction where the caller has
/// one).
#[derive(Debug, Clone, Copy)]
pub struct Signals<'a> {
    pub time_s: &'a [f64],
    pub normal_n: &'a [f64],
    pub tangential_n: &'a [f64],
    pub position_m: Option<&'a [f64]>,
    pub step: Option<&'a [f64]>,
    /// Sliding velocity, m/s (a speed channel in rpm is not used).
    pub speed_m_s: Option<&'a [f64]>,
}

impl<'a> Signals<'a> {
    /// A recording's channels as read.
    pub fn of(rec: &'a Recording) -> Self {
        Signals::with_forces(rec, &rec.normal_n, &rec.tangential_n)
    }
    /// A recording's channels with corrected forces.
    pub fn with_forces(rec: &'a Recording, normal_n: &'a [f64], tangential_n: &'a [f64]) -> Self {
        Signals {
            time_s: &rec.time_s,
            normal_n,
            tangential_n,
            position_m: rec.position_m.as_deref(),
            step: rec.step.as_deref(),
            speed_m_s: match &rec.speed {
                Some(SpeedTrace::SlidingMPerS(v)) => Some(v),
                _ => None,
            },
        }
    }
    fn len(&self) -> usize {
        self.time_s.len()
    }
    fn fs(&self) -> f64 {
        let n = self.len();
        if n < 2 {
            return 1.0;
        }
        (n - 1) as f64 / (self.time_s[n - 1] - self.time_s[0]).max(1e-12)
    }
}

/// One stroke (half-cycle).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stroke {
    /// Sample range `[i, j)`.
    pub i: usize,
    pub j: usize,
    /// +1 forward, −1 backward.
    pub direction: i8,
    /// The mid-stroke part used, `[a, b)`.
    pub a: usize,
    pub b: usize,
    pub start_s: f64,
    pub end_s: f64,
    /// μ over the mid-stroke part, sign taken by the direction.
    pub mu: f64,
    pub normal_n: f64,
    /// Mean sliding speed over the mid-stroke part, m/s (from the position or a speed channel).
    pub velocity_m_s: Option<f64>,
    /// Stroke length, m (with a position channel).
    pub length_m: Option<f64>,
}

/// One cycle: a forward and a backward stroke.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Cycle {
    /// 1-based within its test (or load/speed step).
    pub index: usize,
    /// Start of the cycle's first stroke, s.
    pub time_s: f64,
    /// End of its second stroke, s.
    pub end_s: f64,
    pub mu_forward: f64,
    pub mu_backward: f64,
    pub mu_mean: f64,
    pub normal_n: f64,
    pub samples: usize,
    pub velocity_m_s: Option<f64>,
}

/// A reciprocating test (or one load/speed step of one).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reciprocating {
    pub source: StrokeSource,
    pub strokes: usize,
    /// Per-cycle evolution (not in JSON reports: written beside the dataset).
    #[serde(skip)]
    pub cycles: Vec<Cycle>,
    /// Steady cycles `[first, last)` (0-based into `cycles`).
    pub steady_cycles: (usize, usize),
    /// Cycles before μ entered its final band (`auto` rule only).
    pub run_in_cycles: Option<usize>,
    pub mu_forward: f64,
    pub mu_backward: f64,
    pub mu_mean: f64,
    /// Standard deviation of the steady cycles' mean μ.
    pub mu_std: f64,
    /// Slope of the cycles' mean μ over the steady cycles, 1/s.
    pub trend_per_s: f64,
    pub normal_n: f64,
    pub velocity_m_s: Option<f64>,
    pub stroke_length_m: Option<f64>,
    /// Cycles per second over the steady cycles.
    pub frequency_hz: f64,
    /// Time span of the steady cycles, s.
    pub start_s: f64,
    pub end_s: f64,
    /// Mid-stroke samples averaged.
    pub samples: usize,
    /// The friction channel carries a magnitude only (never negative): μ = |F_t|/F_N.
    pub unsigned: bool,
    /// Why the steady cycles are not a settled steady state, where they are not (too few
    /// cycles to tell, or a μ that never settles; see [`crate::steady_window::steady_stretch`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsettled: Option<String>,
}

/// `q`-quantile (nearest rank) of `x`; NaN when empty.
fn quantile(x: &[f64], q: f64) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    let mut v = x.to_vec();
    let k = ((q * (v.len() - 1) as f64).round() as usize).min(v.len() - 1);
    *v.select_nth_unstable_by(k, f64::total_cmp).1
}

/// Loaded samples: F_N above a quarter of its 95th percentile.
fn loaded_mask(normal: &[f64]) -> Vec<bool> {
    let hi = quantile(normal, 0.95);
    normal.iter().map(|f| hi > 0.0 && *f > 0.25 * hi).collect()
}

/// Robust noise level of a channel: the spread of its first differences / √2.
fn noise_sigma(x: &[f64]) -> f64 {
    let d: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    mad_sigma(&d, 0.0) / std::f64::consts::SQRT_2
}

/// Stroke bounds from the position's turning points in `[i0, j0)`: a turn where the smoothed
/// position has come back from its extreme by more than a tenth of the travel. `None` when
/// the position does not move (range below 20 noise levels or 1 µm).
fn strokes_from_position(x: &[f64], i0: usize, j0: usize, w: usize) -> Option<Vec<(usize, usize)>> {
    let part = &x[i0..j0];
    let range = quantile(part, 0.99) - quantile(part, 0.01);
    if !(range > 20.0 * noise_sigma(part) && range > 1e-6) {
        return None;
    }
    let xs = moving_average(part, w);
    let h = 0.1 * range;
    let mut turns: Vec<usize> = Vec::new();
    let (mut dir, mut ext, mut hi, mut lo) = (0i8, 0usize, 0usize, 0usize);
    for k in 0..xs.len() {
        match dir {
            1 if xs[k] >= xs[ext] => ext = k,
            1 if xs[ext] - xs[k] > h => {
                turns.push(ext);
                (dir, ext) = (-1, k);
            }
            -1 if xs[k] <= xs[ext] => ext = k,
            -1 if xs[k] - xs[ext] > h => {
                turns.push(ext);
                (dir, ext) = (1, k);
            }
            0 => {
                hi = if xs[k] > xs[hi] { k } else { hi };
                lo = if xs[k] < xs[lo] { k } else { lo };
                if xs[hi] - xs[lo] > h {
                    (dir, ext) = if hi > lo { (1, hi) } else { (-1, lo) };
                    turns.push(hi.min(lo));
                }
            }
            _ => {}
        }
    }
    if dir != 0 {
        turns.push(ext);
    }
    Some(
        turns
            .windows(2)
            .map(|t| (i0 + t[0], i0 + t[1] + 1))
            .collect(),
    )
}

/// Runs of one step value in `[i0, j0)`.
fn step_runs(step: &[f64], i0: usize, j0: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut s = i0;
    for k in i0 + 1..=j0 {
        if k == j0 || step[k] != step[s] {
            out.push((s, k));
            s = k;
        }
    }
    out
}

/// Stroke bounds from blocks (step-column runs) when each is one half-stroke: at least two
/// runs, the smoothed friction force keeps one sign over the middle half of each (90 % of
/// its samples) and that sign alternates from run to run (80 % of the changes).
fn strokes_from_blocks(s: &Signals, i0: usize, j0: usize, w: usize) -> Option<Vec<(usize, usize)>> {
    let runs = step_runs(s.step?, i0, j0);
    if runs.len() < 2 {
        return None;
    }
    let fs = moving_average(&s.tangential_n[i0..j0], w);
    let mut signs = Vec::with_capacity(runs.len());
    for &(i, j) in &runs {
        let (a, b) = (i - i0 + (j - i) / 4, i - i0 + 3 * (j - i) / 4);
        if b <= a {
            return None;
        }
        let pos = fs[a..b].iter().filter(|v| **v > 0.0).count();
        let share = pos as f64 / (b - a) as f64;
        if share > 0.1 && share < 0.9 {
            return None;
        }
        signs.push(share >= 0.9);
    }
    let alternating = signs.windows(2).filter(|p| p[0] != p[1]).count();
    (alternating as f64 >= 0.8 * (signs.len() - 1) as f64).then_some(runs)
}

/// Stroke bounds from the sign changes of the smoothed friction force in `[i0, j0)`, with a
/// deadband of the larger of four noise levels and 15 % of the force's 90th-percentile
/// magnitude: a stroke starts at the last zero crossing before the force passes the deadband
/// on the other side. Unloaded samples end a stroke.
fn strokes_from_force(s: &Signals, i0: usize, j0: usize, w: usize) -> Vec<(usize, usize)> {
    let ft = &s.tangential_n[i0..j0];
    let fs = moving_average(ft, w);
    let mags: Vec<f64> = fs.iter().map(|v| v.abs()).collect();
    let h = (4.0 * noise_sigma(ft)).max(0.15 * quantile(&mags, 0.9));
    let mut bounds = vec![0usize];
    let (mut state, mut zc) = (0i8, 0usize);
    for k in 1..fs.len() {
        if fs[k].signum() != fs[k - 1].signum() {
            zc = k;
        }
        let now = if fs[k] > h {
            1
        } else if fs[k] < -h {
            -1
        } else {
            continue;
        };
        if state != 0 && now != state {
            bounds.push(zc);
        }
        state = now;
    }
    bounds.push(fs.len());
    bounds.windows(2).map(|b| (i0 + b[0], i0 + b[1])).collect()
}

/// The middle 50 % of a stroke `[i, j)`: by position (samples whose position lies in the
/// middle half of the travel) or by time.
fn mid_part(s: &Signals, i: usize, j: usize, by_position: bool) -> (usize, usize) {
    if let (true, Some(x)) = (by_position, s.position_m) {
        let (x0, x1) = (x[i], x[j - 1]);
        let (lo, hi) = (x0.min(x1), x0.max(x1));
        let (qa, qb) = (lo + 0.25 * (hi - lo), lo + 0.75 * (hi - lo));
        let inside = |k: &usize| x[*k] >= qa && x[*k] <= qb;
        if let (Some(a), Some(b)) = ((i..j).find(inside), (i..j).rfind(inside)) {
            return (a, b + 1);
        }
    }
    let n = j - i;
    (i + n / 4, i + (3 * n) / 4)
}

/// Measure a stroke: direction, mid-stroke part, μ. `sign` turns the position's direction
/// into the friction force's sign (+1 or −1; 0 for an unsigned channel); without a position
/// the direction is the force's sign. `None` for an unloaded or empty mid part.
fn measure_stroke(
    s: &Signals,
    (i, j): (usize, usize),
    loaded: &[bool],
    sign: f64,
) -> Option<Stroke> {
    let by_position = s.position_m.is_some();
    let (a, b) = mid_part(s, i, j, by_position);
    if b <= a + 1 || !loaded[a..b].iter().all(|l| *l) {
        return None;
    }
    let m = (b - a) as f64;
    let ft = s.tangential_n[a..b].iter().sum::<f64>() / m;
    let f_n = s.normal_n[a..b].iter().sum::<f64>() / m;
    let (direction, s_f) = match s.position_m {
        Some(x) => {
            let d = if x[j - 1] >= x[i] { 1i8 } else { -1 };
            (d, if sign == 0.0 { 1.0 } else { sign * d as f64 })
        }
        None => {
            let d = if ft >= 0.0 { 1i8 } else { -1 };
            (d, d as f64)
        }
    };
    let dt = s.time_s[b - 1] - s.time_s[a];
    let velocity_m_s = match (s.position_m, s.speed_m_s) {
        (Some(x), _) if dt > 0.0 => Some((x[b - 1] - x[a]).abs() / dt),
        (_, Some(v)) => Some(median(&v[a..b].iter().map(|v| v.abs()).collect::<Vec<_>>())),
        _ => None,
    };
    Some(Stroke {
        i,
        j,
        direction,
        a,
        b,
        start_s: s.time_s[i],
        end_s: s.time_s[j - 1],
        mu: s_f * ft / f_n,
        normal_n: f_n,
        velocity_m_s,
        length_m: s.position_m.map(|x| (x[j - 1] - x[i]).abs()),
    })
}

/// Stroke bounds in `[i0, j0)` and where they came from: position, blocks, force sign.
pub fn stroke_bounds(
    s: &Signals,
    i0: usize,
    j0: usize,
    cfg: &IdentifyConfig,
) -> (StrokeSource, Vec<(usize, usize)>) {
    let w = ((cfg.smoothing_s * s.fs()).round() as usize).max(3);
    if let Some(b) = s
        .position_m
        .and_then(|x| strokes_from_position(x, i0, j0, w))
    {
        return (StrokeSource::Position, b);
    }
    if let Some(b) = strokes_from_blocks(s, i0, j0, w) {
        return (StrokeSource::Blocks, b);
    }
    (StrokeSource::ForceSign, strokes_from_force(s, i0, j0, w))
}

/// The strokes of `[i0, j0)`: measured, without incomplete ones (shorter than 70 % of the
/// median stroke in time, or in travel with a position), with the unsigned flag.
pub fn strokes(
    s: &Signals,
    i0: usize,
    j0: usize,
    cfg: &IdentifyConfig,
) -> (StrokeSource, Vec<Stroke>, bool) {
    let (source, bounds) = stroke_bounds(s, i0, j0, cfg);
    // a position that does not reverse (a constant radius column) says nothing of direction
    let s = &Signals {
        position_m: s.position_m.filter(|_| source == StrokeSource::Position),
        ..*s
    };
    let loaded = loaded_mask(s.normal_n);
    let ft_loaded: Vec<f64> = (i0..j0)
        .filter(|k| loaded[*k])
        .map(|k| s.tangential_n[k])
        .collect();
    let negative = ft_loaded.iter().filter(|v| **v < 0.0).count() as f64;
    let unsigned = source == StrokeSource::Position && negative < 0.02 * ft_loaded.len() as f64;
    // the position's direction → the force's sign: positive μ on the majority of strokes
    let probe: Vec<f64> = bounds
        .iter()
        .filter_map(|b| measure_stroke(s, *b, &loaded, 1.0).map(|st| st.mu))
        .collect();
    let sign = if unsigned {
        0.0
    } else if median(&probe) < 0.0 {
        -1.0
    } else {
        1.0
    };
    let all: Vec<Stroke> = bounds
        .iter()
        .filter_map(|b| measure_stroke(s, *b, &loaded, sign))
        .collect();
    let dur = median(
        &all.iter()
            .map(|st| st.end_s - st.start_s)
            .collect::<Vec<_>>(),
    );
    let len = median(&all.iter().filter_map(|st| st.length_m).collect::<Vec<_>>());
    let kept = all
        .into_iter()
        .filter(|st| st.end_s - st.start_s >= 0.7 * dur)
        .filter(|st| st.length_m.is_none_or(|l| l >= 0.7 * len))
        .collect();
    (source, kept, unsigned)
}

/// Cycles: each forward stroke with the backward stroke that follows it directly (or the
/// other way round, whichever the test starts with); a stroke without its partner is left out.
pub fn cycles(strokes: &[Stroke]) -> Vec<Cycle> {
    let dur = median(
        &strokes
            .iter()
            .map(|s| s.end_s - s.start_s)
            .collect::<Vec<_>>(),
    );
    let mut out = Vec::new();
    let mut k = 0;
    while k + 1 < strokes.len() {
        let (p, q) = (&strokes[k], &strokes[k + 1]);
        if p.direction == q.direction || q.start_s - p.end_s > 0.5 * dur {
            k += 1;
            continue;
        }
        let (f, b) = if p.direction > 0 { (p, q) } else { (q, p) };
        let samples = (p.b - p.a) + (q.b - q.a);
        out.push(Cycle {
            index: out.len() + 1,
            time_s: p.start_s,
            end_s: q.end_s,
            mu_forward: f.mu,
            mu_backward: b.mu,
            mu_mean: 0.5 * (f.mu + b.mu),
            normal_n: 0.5 * (f.normal_n + b.normal_n),
            samples,
            velocity_m_s: match (f.velocity_m_s, b.velocity_m_s) {
                (Some(x), Some(y)) => Some(0.5 * (x + y)),
                (x, y) => x.or(y),
            },
        });
        k += 2;
    }
    out
}

/// Steady cycles `[a, b)` under `rule` and the run-in (cycles) found under `auto`, by the one
/// steady-state rule ([`steady_stretch`]: below 16 cycles all of them, a μ that never settles
/// after its warm-up), with how μ settled. An error says why a user's rule cannot be
/// honoured ([`rule_span`]) or that there is no cycle.
pub fn steady_cycles(
    cycles: &[Cycle],
    rule: SteadyRule,
) -> Result<(usize, usize, Option<usize>, Settling), String> {
    let n = cycles.len();
    if n == 0 {
        return Err("no complete cycle".into());
    }
    let t: Vec<f64> = cycles.iter().map(|c| c.time_s).collect();
    if let Some((a, b)) = rule_span(rule, &t, 1, "cycles")? {
        return Ok((a, b, None, Settling::Settled));
    }
    let mu: Vec<f64> = cycles.iter().map(|c| c.mu_mean).collect();
    let (fin, settling) = steady_stretch(&mu, &t, 3, 0.002);
    Ok((fin.a, fin.b, Some(fin.run_in_end), settling))
}

/// Identify a reciprocating test over samples `[i0, j0)`: strokes, cycles, steady cycles and
/// μ per direction. An error says why no result came out.
pub fn analyse(
    s: &Signals,
    i0: usize,
    j0: usize,
    cfg: &IdentifyConfig,
) -> Result<Reciprocating, String> {
    let (source, st, unsigned) = strokes(s, i0, j0, cfg);
    let cy = cycles(&st);
    if cy.is_empty() {
        return Err(format!(
            "reciprocating: {} stroke(s) found from the {}, no complete cycle (a forward and a backward stroke)",
            st.len(),
            source.describe()
        ));
    }
    let (a, b, run_in, settling) =
        steady_cycles(&cy, cfg.steady).map_err(|m| format!("reciprocating: {m}"))?;
    let used = &cy[a..b];
    let mean = |f: &dyn Fn(&Cycle) -> f64| used.iter().map(f).sum::<f64>() / used.len() as f64;
    let mus: Vec<f64> = used.iter().map(|c| c.mu_mean).collect();
    let times: Vec<f64> = used.iter().map(|c| c.time_s).collect();
    let (_, std) = mean_std(&mus);
    let trend = if used.len() > 2 {
        linear_fit(&times, &mus).1
    } else {
        0.0
    };
    let vel: Vec<f64> = used.iter().filter_map(|c| c.velocity_m_s).collect();
    let lens: Vec<f64> = st.iter().filter_map(|x| x.length_m).collect();
    let span = used[used.len() - 1].time_s - used[0].time_s;
    Ok(Reciprocating {
        source,
        strokes: st.len(),
        steady_cycles: (a, b),
        run_in_cycles: run_in,
        mu_forward: mean(&|c| c.mu_forward),
        mu_backward: mean(&|c| c.mu_backward),
        mu_mean: mean(&|c| c.mu_mean),
        mu_std: std,
        trend_per_s: trend,
        normal_n: mean(&|c| c.normal_n),
        velocity_m_s: (!vel.is_empty()).then(|| vel.iter().sum::<f64>() / vel.len() as f64),
        stroke_length_m: (!lens.is_empty()).then(|| median(&lens)),
        frequency_hz: if span > 0.0 {
            (used.len() - 1) as f64 / span
        } else {
            f64::NAN
        },
        start_s: used[0].time_s,
        end_s: used[used.len() - 1].end_s,
        samples: used.iter().map(|c| c.samples).sum(),
        unsigned,
        unsettled: settling.reason(cy.len(), "cycles"),
        cycles: cy,
    })
}

/// Whether a recording is a reciprocating test, and why: named so (`mode`), or strokes
/// found — from a moving position (4 strokes or more), from blocks that are half-strokes, or
/// from a friction force that changes sign regularly (6 strokes or more, stroke durations
/// within 30 % of each other, both signs on a quarter of the loaded samples at least). Where
/// the rig profile says the rig reciprocates, 2 strokes suffice. `None`: a continuous test.
pub fn detect(
    s: &Signals,
    mode: Option<TestMode>,
    profile: Option<TestMode>,
    cfg: &IdentifyConfig,
) -> Option<String> {
    match mode {
        Some(TestMode::Reciprocating) => return Some("named (mode = reciprocating)".into()),
        Some(_) => return None,
        None => {}
    }
    let loaded = loaded_mask(s.normal_n);
    let (i0, j0) = (
        loaded.iter().position(|l| *l)?,
        loaded.iter().rposition(|l| *l)? + 1,
    );
    let ft: Vec<f64> = (i0..j0)
        .filter(|k| loaded[*k])
        .map(|k| s.tangential_n[k])
        .collect();
    let neg = ft.iter().filter(|v| **v < 0.0).count() as f64 / ft.len().max(1) as f64;
    // without a position, both directions must be loaded a fair share of the time
    if s.position_m.is_none() && !(0.2..=0.8).contains(&neg) {
        return None;
    }
    let (source, st, _) = strokes(s, i0, j0, cfg);
    let by_profile = profile == Some(TestMode::Reciprocating);
    let min = if by_profile { 2 } else { 4 };
    let why = match source {
        StrokeSource::Position | StrokeSource::Blocks if st.len() >= min => source.describe(),
        StrokeSource::ForceSign if st.len() >= min.max(6) || (by_profile && st.len() >= 2) => {
            let d: Vec<f64> = st.iter().map(|x| x.end_s - x.start_s).collect();
            let (m, sd) = mean_std(&d);
            let regular = by_profile || sd <= 0.3 * m;
            if !(regular && (0.25..=0.75).contains(&neg)) {
                return None;
            }
            source.describe()
        }
        _ => return None,
    };
    Some(format!(
        "{} strokes from the {why}{}",
        st.len(),
        if by_profile {
            " (rig profile: reciprocating)"
        } else {
            ""
        }
    ))
}

/// The parts of a recording identified separately: one per run of the step column when the
/// steps are load/speed steps (each holding many strokes), else the whole loaded recording.
/// Each part is `[i, j)` over its loaded samples, with its step label.
pub fn parts(s: &Signals, cfg: &IdentifyConfig) -> Vec<(usize, usize, Option<f64>)> {
    let loaded = loaded_mask(s.normal_n);
    let (Some(i0), Some(j1)) = (
        loaded.iter().position(|l| *l),
        loaded.iter().rposition(|l| *l),
    ) else {
        return Vec::new();
    };
    let j0 = j1 + 1;
    let w = ((cfg.smoothing_s * s.fs()).round() as usize).max(3);
    let Some(step) = s.step else {
        return vec![(i0, j0, None)];
    };
    if strokes_from_blocks(s, i0, j0, w).is_some() {
        return vec![(i0, j0, None)];
    }
    step_runs(step, i0, j0)
        .into_iter()
        .filter_map(|(i, j)| {
            let a = (i..j).find(|k| loaded[*k])?;
            let b = (i..j).rfind(|k| loaded[*k])? + 1;
            Some((a, b, Some(step[i])))
        })
        .collect()
}
