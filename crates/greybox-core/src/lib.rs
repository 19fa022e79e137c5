#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-core: the types every other greybox crate meets at.
//!
//! * [`units`] — SI conversion helpers for the edges (CLI flags, file columns).
//! * [`contact`] — [`ContactState`], what a friction law sees.
//! * [`law`] — the [`FrictionLaw`] seam (μ for a contact state).
//! * [`dataset`] — the friction dataset and its strict CSV schema.
//! * [`error`] — one error type whose input errors name file, line/byte and field.
//! * [`atomic`] — write-to-temp-then-rename output that only ever replaces regular files.
//! * [`outputs`] — outputs that cannot destroy inputs; output directories replaced whole.
//! * [`provenance`] — what produced an output: command, version, inputs with SHA-256, seed.
//! * [`cleanup`] — temporary paths an interrupt handler removes.
//! * [`csvutil`] — strict numeric field parsing shared by every CSV reader.
//! * [`plot`] — small self-contained SVG plots.
//! * [`progress`] — progress of long work, shown by whatever display the process installed.
//! * [`interrupt`] — cooperative cancellation: long loops stop at their next step on request.
//! * [`physics`] — the plausible ranges of every physical quantity and the likely unit mistake.
//! * [`notes`] — what a run must say without failing: values outside their usual range.
//! * [`rules`] — field-by-field configuration checks whose errors name the field and the rule.
//! * [`boundary`] — exact boundaries of monotone floating-point predicates (split thresholds).
//! * [`roots`] — bracketing root finding for expensive functions.
//! * [`linalg`] — small least-squares helpers.
//! * [`stats`] — the mean of a correlated series with its batch-means confidence interval.
//! * [`shell`] — quoting of every value a generated shell script receives.
//! * [`escape`] — free text escaped (or refused) for the format it lands in: deck comments,
//!   CSV fields, shell words, XML/SVG/HTML; names checked to be words.
//! * [`input`] — the one safe open of every input file (regular files only, a size cap, no
//!   hang on a FIFO, a missing file "not found").
//! * [`budget`] — the named caps of readers and walkers (bytes, cells, array lengths, lines).
//! * [`choice`] — option enums with one spelling on the command line, in Python and in files.
//! * [`count`] — counts as bounded types: the cap part of the type, checked where the number enters.
//!
//! SI units everywhere inside: Pa, m/s, N, K, s.

pub mod atomic;
pub mod boundary;
pub mod budget;
pub mod call_scope;
pub mod choice;
pub mod cleanup;
pub mod contact;
pub mod count;
pub mod csvutil;
pub mod dataset;
pub mod error;
pub mod escape;
pub mod input;
pub mod interrupt;
pub mod json_head;
pub mod law;
pub mod linalg;
pub mod notes;
pub mod outputs;
pub mod physics;
pub mod plot;
pub mod progress;
pub mod progress_sink;
pub mod provenance;
pub mod roots;
pub mod rules;
pub mod setting;
pub mod shell;
pub mod stats;
pub mod text_serde;
pub mod units;

pub use contact::ContactState;
pub use error::{Error, Result, SourcePos};
pub use law::{Breaks, FrictionLaw};
