//! Identification of recordings from any rig: segments found from what the recording
//! shows, matched to a plan when there is one.
//!
//! Per file:
//! 1. **Loaded samples**: block medians (10 ms) of F_N above the unloaded level plus
//!    `loaded_fraction` of the loaded range.
//! 2. **Baseline**: the unloaded windows at the start and end (where present) give a linear
//!    offset per channel; with one window the offset is constant; with none the file's
//!    warnings say so.
//! 3. **Sign**: a tangential channel whose loaded median is negative is flipped (reported).
//! 4. **Segments**, from the best evidence available: a step column (runs of one step
//!    number), a speed channel (runs of constant speed above rest), or the signals
//!    (loaded-and-sliding runs, split at the level changes of μ into as many steps as the
//!    plan expects, or by a penalised least-squares criterion without one).
//! 5. **Steady part** of each segment from the signal ([`steady_span`]: μ, F_N and the
//!    speed within their bands), then today's spike masking and statistics
//!    ([`plateau_stats`]).
//!
//! Across files, segments are matched to the plan's steps by measured load and speed when
//! every segment has a speed, else by order; missing, extra and reordered steps are reported
//! by name. Without a plan, loads and velocities are the measured ones.
//!
//! The stages live in submodules, in the order a recording passes them: [`prepare`]
//! (baseline, sign, sliding mask), [`spans`] (step column, speed channel, sliding runs),
//! [`change_points`] (μ's level changes inside a run), [`reciprocating_segments`],
//! [`measure`] (steady window and statistics), [`segment`] (all of the above per file),
//! [`self_check`] (one level per step), [`velocity`], then [`matching`] with the plan ([`numbering`] without one, [`plan_timed`]
//! for the NC-program path) and the plausibility [`checks`]; the reports are in [`report`].

mod change_points;
mod checks;
mod matching;
mod measure;
mod numbering;
mod passes;
mod plan_timed;
mod prepare;
mod reciprocating_segments;
mod report;
mod reversals;
mod segment;
mod self_check;
mod span;
mod spans;
mod velocity;

pub use crate::config::Segmentation;
pub use crate::expected::{expected_from_plan, read_expected_steps, ExpectedStep};
pub use checks::{check_levels, check_physics, IMPLAUSIBLE_LEVEL_FACTOR, MAX_SLIDING_VELOCITY_M_S};
pub use matching::match_segments;
pub use report::{
    Campaign, FileReport, Identification, MatchReport, PassMean, PassPair, SegmentReport,
};
pub use segment::{segment_recordings, GAP_SPLIT_INTERVALS};

use greybox_core::Result;
use greybox_recording::Recording;

/// Identify recordings (any layout: a file per step, per pin or for the whole campaign):
/// [`segment_recordings`], then [`match_segments`].
pub fn identify_recordings(recs: &[Recording], c: &Campaign) -> Result<Identification> {
    let mut files = segment_recordings(recs, c)?;
    let (dataset, matching) = match_segments(&mut files, c)?;
    Ok(Identification {
        dataset,
        files,
        matching,
    })
}
