//! The local contact state a friction law is evaluated at.

use serde::{Deserialize, Serialize};

/// Local tool–workpiece contact state, SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactState {
    /// Contact (normal) pressure, Pa.
    pub pressure_pa: f64,
    /// Sliding velocity, m/s.
    pub sliding_velocity_m_s: f64,
    /// Contact temperature, K.
    pub temperature_k: f64,
}

impl ContactState {
    /// Room temperature 293.15 K, used when a source has no temperature.
    pub const ROOM_TEMPERATURE_K: f64 = 293.15;

    pub fn new(pressure_pa: f64, sliding_velocity_m_s: f64) -> Self {
        ContactState {
            pressure_pa,
            sliding_velocity_m_s,
            temperature_k: Self::ROOM_TEMPERATURE_K,
        }
    }
}
