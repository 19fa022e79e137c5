//! Chip breaking: free particles that rise above a height leave the model.
//!
//! A 2D cut with a continuous chip grows its chip by the cut length times the chip ratio, and
//! that chip stays attached: its length, stiffness and inertia (mass scaling included) act
//! back on the tool–chip contact. Measured on the Ti6Al4V template refined to 5 µm, the rake
//! contact lengthened from about 95 to 130–150 µm over 3 mm of cut while the flank load
//! halved, and F'f fell by 10–25 % although nothing else drifted (docs/validation.md, "The
//! chip that never breaks"). Real Ti6Al4V chips segment, curl and break long before that, so
//! a simulation of a measured cut, which is averaged over seconds of many broken chips, keeps
//! only the chip near the tool.
//!
//! A [`Sink`] removes every free particle whose centre lies above `y_above_m` at the start
//! of a step. What the removed particles carry away — kinetic energy ½ m v² and elastic
//! energy (deviatoric (m/ρ) s:s / 4G and the equation of state's) — is booked as
//! [`crate::solver::EnergyBook::removed`], so the energy balance stays closed; their mass and
//! momentum leave the model with them. Removal keeps the other particles in order, so the
//! same run removes the same particles and gives the same bytes.

use crate::particles::{Particles, FREE};
use serde::{Deserialize, Serialize};

/// A horizontal line in the model frame above which free particles leave the model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sink {
    /// Height of the line, m (model frame).
    pub y_above_m: f64,
}

impl Sink {
    /// Which particles stay (`None` when every particle does, the common case, without
    /// allocating).
    pub fn keep(&self, p: &Particles) -> Option<Vec<bool>> {
        let leaves = |i: usize| p.group[i] == FREE && p.y[i] > self.y_above_m;
        (0..p.len())
            .any(leaves)
            .then(|| (0..p.len()).map(|i| !leaves(i)).collect())
    }

    /// Checks the height.
    pub fn validate(&self) -> Result<(), String> {
        if self.y_above_m.is_finite() {
            Ok(())
        } else {
            Err(format!(
                "sink: y_above_m must be a finite height in m, got {}",
                self.y_above_m
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_free_particles_above_the_line_leave_and_the_rest_keep_their_order() {
        let mut p = Particles::block(0.0, 0.0, 3, 4, 1e-3, 1000.0, 300.0);
        // rows at y = 0.5, 1.5, 2.5, 3.5 mm; fix one particle of the top row
        p.group[10] = 1;
        let sink = Sink { y_above_m: 2.0e-3 };
        let keep = sink.keep(&p).expect("the top two rows rise above 2 mm");
        let kept: Vec<usize> = (0..p.len()).filter(|&i| keep[i]).collect();
        assert_eq!(kept, vec![0, 1, 2, 3, 4, 5, 10]);
        let ys: Vec<f64> = kept.iter().map(|&i| p.y[i]).collect();
        assert_eq!(p.retain(&keep), 5);
        assert_eq!(p.y, ys);
        assert!(p.check_lengths());
        assert_eq!(p.group, vec![0, 0, 0, 0, 0, 0, 1]);
        assert!(Sink { y_above_m: 1.0 }.keep(&p).is_none());
        assert!(Sink {
            y_above_m: f64::NAN
        }
        .validate()
        .is_err());
    }
}
