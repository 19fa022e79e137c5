#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-contact: contact mechanics that both the tribometer pipeline (`greybox-tribo`) and
//! the friction laws (`greybox-friction`, and through it the C ABI) need, so that neither
//! depends on the other.
//!
//! * [`hertz`] — Hertzian sphere-on-flat contact: contact radius, maximum and mean pressure,
//!   the seed article's eq.-7 convention, approach; [`PinContact`] maps a pin's normal force
//!   to a contact pressure and back.
//! * [`ploughing`] — the ploughing share of apparent friction (Bowden–Tabor's scratch
//!   geometry) and the adhesive coefficient that remains.
//! * [`wear`] — Archard specific wear rates from volumes, height maps of the worn pin and
//!   the scar geometry; the article's wear tests.

pub mod hertz;
pub mod ploughing;
pub mod wear;

pub use hertz::PinContact;
