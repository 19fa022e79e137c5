#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-contact: contact mechanics that both the tribometer pipeline (`greybox-tribo`) and
//! the friction laws (`greybox-friction`, and through it the C ABI) need, so that neither
//! depends on the other.
//!
//! * [`hertz`] — Hertzian sphere-on-flat contact: contact radius, maximum and mean pressure,
//!   the seed article's eq.-7 convention, approach; [`PinContact`] maps a pin's normal force
//!   to a contact pressure and back.

pub mod hertz;

pub use hertz::PinContact;
