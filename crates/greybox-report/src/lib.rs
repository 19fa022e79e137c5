//! How greybox's results are shown: the self-contained `report.html` of a study directory,
//! the plain-text tables each stage prints, the terminal progress display, and the demo that
//! runs every stage and shows it. The stages themselves are in `greybox_pipeline`; this
//! crate depends on it, never the other way round, so a stage can be called (from Rust,
//! Python or C) without the presentation.
//!
//! | module | shows | from → to |
//! |---|---|---|
//! | [`report`] | one page | a study directory → self-contained `report.html` |
//! | [`text`] | plain-text tables, one module per stage | a stage's result → what the command line prints |
//! | [`text::table`] | the right-aligned table those are laid out in | rows → text |
//! | `progress_display` (feature `cli`) | progress of long stages | `greybox_core::progress` events → bar or status lines on stderr |
//! | [`demo`] | everything | bundled study → every stage's outputs and the report |
//!
//! The demo lives here rather than in the pipeline because its last step writes the report:
//! it is the one workflow that both runs the stages and shows them.

pub mod demo;
#[cfg(feature = "cli")]
pub mod progress_display;
pub mod report;
pub mod text;

pub use report::{report, ReportOptions, ReportSummary};
