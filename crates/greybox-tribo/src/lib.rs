#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-tribo: from a tribometer campaign plan to a friction dataset.
//!
//! * [`plan`] — full-factorial plans with nominal timing; [`gcode`] — NC programs per pin.
//! * [`hertz`] — Hertzian contact pressure (textbook and the article's convention).
//! * [`recording`] — raw force recordings; [`csv_recording`] and [`tdms`] read and write them.
//! * [`synth`] — a virtual tribometer that writes realistic recordings from a ground-truth law.
//! * [`identify`] — plateau detection and apparent COF identification.

pub mod align;
mod bulk;
pub mod campaign;
pub mod coverage;
pub mod csv_recording;
pub mod decimal;
pub mod expected;
pub mod frf;
pub mod frf_synth;
pub mod gcode;
pub mod table;
pub mod text_table;
pub mod xlsx_table;
/// Hertzian contact, from `greybox-contact` (kept here under its old path).
pub use greybox_contact::hertz;
pub mod identify;
pub mod identify_config;
pub mod plan;
pub mod ploughing;
pub mod profiles;
pub mod readers;
pub mod reciprocating;
pub mod recording;
pub mod signal;
pub mod sliding;
pub mod steady;
pub mod synth;
pub mod synth_recip;
pub mod tdms;
pub mod uncertainty;
pub mod wear;
