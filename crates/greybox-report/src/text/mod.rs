//! Plain-text reports of each stage's results (what the command line prints), one module per
//! stage, and the [`table::Table`] they are laid out in. The functions are re-exported here,
//! so `text::cut`, `text::plan`, … name them whatever module holds them.

pub mod bench;
pub mod campaign;
pub mod contact;
pub mod demo;
pub mod dynamics;
pub mod friction;
pub mod identify;
pub mod material;
pub mod simulate;
pub mod sweep;
pub mod table;

pub use bench::{ingest, predict_latency, sph_bench, surrogate_speed};
pub use campaign::{plan, synth};
pub use contact::{hertz, wear, wear_tests};
pub use demo::demo;
pub use dynamics::{characterize, coupling};
pub use friction::{correction, fit, predictions};
pub use identify::{
    all_rows_table, coverage_lines, files_table, identify_footer, inspect_text, matching_text,
    reciprocating_lines, summary_table,
};
pub use material::{johnson_cook, rate_sensitivity};
pub use simulate::{cut, pin};
