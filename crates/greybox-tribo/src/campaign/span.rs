//! A segment as sample ranges of a recording: where it lies, what cut its boundaries and the
//! pass it lies in.

/// What cut a segment's boundaries (the segment report's `boundaries`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Cut {
    /// The recording's step column or blocks.
    StepColumn,
    /// A speed channel's runs of one level.
    Speed,
    /// The plan's step durations laid over a sliding run.
    PlanTiming,
    /// μ's level changes inside a sliding run (least squares or penalised).
    LevelChange,
    /// A whole loaded-and-sliding run.
    Run,
}

impl Cut {
    pub(super) fn name(self) -> &'static str {
        match self {
            Cut::StepColumn => "step column",
            Cut::Speed => "speed channel",
            Cut::PlanTiming => "plan timing",
            Cut::LevelChange => "level change of μ",
            Cut::Run => "sliding run",
        }
    }
}

/// Sample ranges of a segment, `[i, j)`, with its step label and the uncertainty of its
/// start and end boundaries, s (0 where the boundary is sharp).
#[derive(Debug, Clone, Copy)]
pub(super) struct Span {
    pub(super) i: usize,
    pub(super) j: usize,
    pub(super) label: Option<f64>,
    pub(super) unc: (f64, f64),
    /// The run's standard error of a one-second mean of μ, √s (0: from the segment alone).
    pub(super) run_sem: f64,
    /// What cut the boundaries.
    pub(super) cut: Cut,
    /// The pass it lies in (0-based; odd: a reverse pass, see [`super::reversals`]).
    pub(super) pass: u32,
}

impl Span {
    pub(super) fn new(i: usize, j: usize, label: Option<f64>) -> Self {
        Span {
            i,
            j,
            label,
            unc: (0.0, 0.0),
            run_sem: 0.0,
            cut: Cut::Run,
            pass: 0,
        }
    }

    /// The span with its boundaries cut by `cut`.
    pub(super) fn by(self, cut: Cut) -> Self {
        Span { cut, ..self }
    }
}
