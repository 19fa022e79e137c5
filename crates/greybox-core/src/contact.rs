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

/// The states a law may be asked about, the one check of every surface that takes them from
/// a caller (the C ABI, Python's `Law.mu`): each pressure finite and ≥ 0 Pa, each velocity
/// finite, each temperature (where given) finite and > 0 K. The error names the array and
/// the index: "pressure[3] = -1 Pa: must be finite and ≥ 0".
pub fn check_states(p: &[f64], v: &[f64], t: Option<&[f64]>) -> Result<(), String> {
    for i in 0..p.len().min(v.len()) {
        if !p[i].is_finite() || p[i] < 0.0 {
            return Err(format!(
                "pressure[{i}] = {} Pa: must be finite and ≥ 0",
                p[i]
            ));
        }
        if !v[i].is_finite() {
            return Err(format!("velocity[{i}] = {} m/s: must be finite", v[i]));
        }
        if let Some(t) = t.and_then(|t| t.get(i)) {
            if !t.is_finite() || *t <= 0.0 {
                return Err(format!("temperature[{i}] = {t} K: must be finite and > 0"));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn states_are_checked_naming_array_and_index() {
        use super::check_states;
        assert!(check_states(&[0.0, 1e9], &[-1.0, 2.0], Some(&[300.0, 900.0])).is_ok());
        let e = check_states(&[1e9, -1.0], &[1.0, 1.0], None).unwrap_err();
        assert!(e.starts_with("pressure[1] = -1 Pa"), "{e}");
        let e = check_states(&[1e9], &[f64::NAN], None).unwrap_err();
        assert!(e.starts_with("velocity[0]"), "{e}");
        let e = check_states(&[1e9], &[1.0], Some(&[0.0])).unwrap_err();
        assert!(e.starts_with("temperature[0] = 0 K"), "{e}");
    }
}
