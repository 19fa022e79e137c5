//! A recording in SI units, its speed trace, and the reader's report of how it was read.

use greybox_core::choice::Choice;
use greybox_core::physics::Quantity;
use greybox_core::{Error, Result, SourcePos};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One pin's raw recording, SI units (s, N, V).
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// File (or other source) it was read from.
    pub source: String,
    /// Sample times, s (strictly increasing).
    pub time_s: Vec<f64>,
    /// Normal force F_N, N.
    pub normal_n: Vec<f64>,
    /// Tangential (friction) force F_t, N.
    pub tangential_n: Vec<f64>,
    /// Radial force, N (not used for μ; kept for checks).
    pub radial_n: Option<Vec<f64>>,
    /// Recording-trigger channel, V.
    pub trigger_v: Option<Vec<f64>>,
    /// Step (segment) number the rig software wrote per sample.
    pub step: Option<Vec<f64>>,
    /// Recorded spindle speed (rpm) or sliding velocity (m/s).
    pub speed: Option<SpeedTrace>,
    /// Recorded track radius per sample, m.
    pub track_radius_m: Option<Vec<f64>>,
    /// The friction coefficient the rig computed itself (`cof` role), dimensionless. Kept
    /// beside the forces: where the file has no friction force, `tangential_n` is μ·F_N.
    pub cof: Option<Vec<f64>>,
    /// Position along the stroke of a linear reciprocating rig (ASTM G133), m.
    pub position_m: Option<Vec<f64>>,
    /// How the file was read: its layout and which column became which role.
    pub provenance: Option<ReadReport>,
}

/// A recorded speed channel in SI-like base units.
#[derive(Debug, Clone, PartialEq)]
pub enum SpeedTrace {
    /// Spindle speed, rpm (needs the track radius to give a sliding velocity).
    SpindleRpm(Vec<f64>),
    /// Sliding velocity, m/s.
    SlidingMPerS(Vec<f64>),
}

impl SpeedTrace {
    pub fn values(&self) -> &[f64] {
        match self {
            SpeedTrace::SpindleRpm(v) | SpeedTrace::SlidingMPerS(v) => v,
        }
    }
}

/// What a reader found in a file, for `identify --inspect`.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct ReadReport {
    /// Dialect and layout, e.g. `semicolon-delimited, decimal comma, header on line 1`.
    pub layout: String,
    /// Role → column, unit and how it was found.
    pub columns: Vec<MappedColumn>,
    /// Footer lines after the data (reported, not an error): (line, text).
    pub footer: Vec<(u64, String)>,
    /// Preamble lines above the header.
    pub preamble: Vec<String>,
    /// Anything the reader repaired, e.g. a time that restarts per step.
    pub notes: Vec<String>,
    /// What was read but not used, or contradicts what was used (a long footer, a rig's own μ
    /// far from F_t/F_N): lines of the identification's summary, not only of `--inspect`
    /// (carried into `greybox_tribo::campaign::FileReport::warnings`).
    pub warnings: Vec<String>,
    /// How the rig profile says the rig runs its tests (`None`: no profile).
    pub test_mode: Option<TestMode>,
}

/// One role's column.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MappedColumn {
    pub role: super::roles::Role,
    pub column: String,
    pub unit: String,
    pub scale: f64,
    pub how: FoundBy,
}

/// How a role's column was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FoundBy {
    /// Named by the user (`map`).
    Mapped,
    /// Found by its usual name.
    Auto,
}

greybox_core::choice!(FoundBy, "how", [Mapped => "mapped", Auto => "auto"]);

/// The largest |value| of a channel whose samples are known finite: a parallel branch-free
/// screen (the sample itself is looked for only when a message needs it).
pub(crate) fn largest_magnitude(ch: &[f64]) -> f64 {
    ch.par_chunks(1 << 14)
        .map(|b| b.iter().fold(0.0f64, |m, v| m.max(v.abs())))
        .reduce(|| 0.0, f64::max)
}

impl Recording {
    /// A recording of time and the two forces only.
    pub fn new(source: &str, time_s: Vec<f64>, normal_n: Vec<f64>, tangential_n: Vec<f64>) -> Self {
        Recording {
            source: source.to_string(),
            time_s,
            normal_n,
            tangential_n,
            radial_n: None,
            trigger_v: None,
            step: None,
            speed: None,
            track_radius_m: None,
            cof: None,
            position_m: None,
            provenance: None,
        }
    }
    pub fn len(&self) -> usize {
        self.time_s.len()
    }
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }
    /// Duration from first to last sample, s.
    pub fn duration_s(&self) -> f64 {
        match (self.time_s.first(), self.time_s.last()) {
            (Some(a), Some(b)) => b - a,
            _ => 0.0,
        }
    }
    /// Sample rate from the median sample interval, Hz.
    pub fn sample_rate_hz(&self) -> f64 {
        let mut dt: Vec<f64> = self.time_s.windows(2).map(|w| w[1] - w[0]).collect();
        if dt.is_empty() {
            return f64::NAN;
        }
        let mid = dt.len() / 2;
        let (_, m, _) = dt.select_nth_unstable_by(mid, f64::total_cmp);
        1.0 / *m
    }

    /// Check lengths, finiteness and strictly increasing time.
    pub fn validate(&self) -> Result<()> {
        let n = self.time_s.len();
        let pos = || SourcePos::file(&self.source);
        if n < 2 {
            return Err(Error::input(
                pos(),
                format!("a recording needs at least 2 samples, found {n}"),
            ));
        }
        let speed = self.speed.as_ref().map(SpeedTrace::values);
        let channels: [(&str, Option<&[f64]>); 8] = [
            ("normal", Some(&self.normal_n)),
            ("tangential", Some(&self.tangential_n)),
            ("radial", self.radial_n.as_deref()),
            ("trigger", self.trigger_v.as_deref()),
            ("step", self.step.as_deref()),
            ("speed", speed),
            ("radius", self.track_radius_m.as_deref()),
            ("position", self.position_m.as_deref()),
        ];
        for (name, ch) in channels {
            if let Some(ch) = ch {
                if ch.len() != n {
                    return Err(Error::input(
                        pos().field(name),
                        format!("channel has {} samples, time has {n}", ch.len()),
                    ));
                }
                if let Some(i) = first_non_finite(ch) {
                    return Err(Error::input(
                        pos().field(name),
                        format!("sample {i} is not finite ({})", ch[i]),
                    ));
                }
            }
        }
        // A force no tribometer can apply (a channel in the wrong unit, an overflowed
        // value): refused at its largest sample against the physics table's possible range,
        // before any statistic of the file can turn it into another message.
        for (name, q, ch) in [
            ("normal", Quantity::NormalForce, &self.normal_n),
            ("tangential", Quantity::TangentialForce, &self.tangential_n),
        ] {
            let largest = largest_magnitude(ch);
            if !q.hard().contains(&largest) {
                let i = ch.iter().position(|v| v.abs() == largest).unwrap_or(0);
                let what = format!("sample {i}");
                let text = greybox_core::physics::check(q, largest, &what)
                    .err()
                    .unwrap_or_default();
                return Err(Error::input(pos().field(name), text));
            }
        }
        if let Some(i) = first_non_increasing(&self.time_s) {
            return Err(Error::input(
                pos().field("time"),
                format!(
                    "time must increase strictly: sample {} ({} s) follows {} s",
                    i + 1,
                    self.time_s[i + 1],
                    self.time_s[i]
                ),
            ));
        }
        Ok(())
    }
}

/// Index of the first NaN or infinity. Blocks are screened in parallel with a branch-free OR
/// that vectorises; only a failing block is searched.
pub(super) fn first_non_finite(values: &[f64]) -> Option<usize> {
    const BLOCK: usize = 1 << 14;
    values
        .par_chunks(BLOCK)
        .position_first(|b| b.iter().fold(false, |bad, v| bad | !v.is_finite()))
        .and_then(|k| {
            let start = k * BLOCK;
            values[start..]
                .iter()
                .position(|v| !v.is_finite())
                .map(|i| start + i)
        })
}

/// Index `i` of the first pair with `t[i+1] ≤ t[i]` (or a NaN), screened in parallel blocks
/// like [`first_non_finite`].
pub(super) fn first_non_increasing(t: &[f64]) -> Option<usize> {
    const BLOCK: usize = 1 << 14;
    let bad = |s: &[f64]| s.windows(2).fold(false, |bad, w| bad | !(w[1] > w[0]));
    let blocks = t.len().div_ceil(BLOCK);
    (0..blocks)
        .into_par_iter()
        .position_first(|k| bad(&t[k * BLOCK..((k + 1) * BLOCK + 1).min(t.len())]))
        .and_then(|k| {
            t[k * BLOCK..]
                .windows(2)
                .position(|w| !(w[1] > w[0]))
                .map(|i| k * BLOCK + i)
        })
}

greybox_core::choice!(
    TestMode,
    "test_mode",
    [
        Continuous => "continuous",
        Stepped => "stepped",
        Reciprocating => "reciprocating",
    ],
    text
);

/// How a rig runs its tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TestMode {
    /// Rotating pin-on-disc: one load and speed for the whole test.
    Continuous,
    /// Several loads or speeds one after another (step column or blocks).
    Stepped,
    /// Linear reciprocating (ASTM G133): the friction force changes sign with the stroke.
    Reciprocating,
}

impl TestMode {
    /// The mode's name (`continuous`, `stepped`, `reciprocating`), as its [`Choice`] spells it.
    pub fn name(self) -> &'static str {
        Choice::name(self)
    }
    /// The mode called `s` (`continuous`, `stepped`, `reciprocating`).
    pub fn parse(s: &str) -> Option<TestMode> {
        Self::parse_choice(s.trim()).ok()
    }
}
