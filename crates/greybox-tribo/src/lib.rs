#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-tribo: from a tribometer campaign plan and its recordings to a friction dataset.
//!
//! Recordings are read by `greybox-recording`; this crate plans the campaign, identifies
//! the friction coefficient in what was recorded, and simulates a rig.
//!
//! * [`plan`] — full-factorial plans with nominal timing; [`gcode`] — NC programs per pin;
//!   [`expected`] — what a plan says each step should show.
//! * [`campaign`] — a campaign's recordings segmented into steps, matched to the plan,
//!   measured; [`plan_timing`] — μ per step of a pin by the plan's timing; [`config`] — the settings
//!   both paths share; [`align`] — plan timing against a recording; [`steady_window`] — the steady
//!   stretch of a step; [`sliding`] — sliding speed and distance; [`coverage`] — what each
//!   step could give; [`uncertainty`] — intervals of μ; [`reciprocating`] — strokes of a
//!   linear reciprocating test; [`signal`] — robust signal helpers.
//! * [`synth`], [`synth_recip`] — a virtual tribometer writing recordings from a known law;
//!   [`frf`], [`frf_synth`] — the rig's dynamics from impact-hammer tests.
//!
//! The ploughing share of apparent friction and wear (Archard rates, height maps) are
//! contact mechanics: `greybox_contact::{ploughing, wear}`.

pub mod align;
pub mod campaign;
pub mod config;
pub mod coverage;
pub mod expected;
pub mod frf;
pub mod frf_synth;
pub mod gcode;
pub mod plan;
pub mod plan_timing;
pub mod reciprocating;
pub mod signal;
pub mod sliding;
pub mod steady_window;
pub mod synth;
pub mod synth_recip;
pub mod uncertainty;
