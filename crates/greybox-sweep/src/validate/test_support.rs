//! Outcomes made by hand for the tests of the modules that combine them.

use super::{Outcome, Role, ToolModel};

/// A held-out outcome with chip-ratio error `e` and the two standard errors.
pub(crate) fn outcome(e: f64, cut_se: Option<f64>, measured_se: Option<f64>) -> Outcome {
    Outcome {
        id: "X".into(),
        material: "m".into(),
        tool: ToolModel::Thermal,
        friction: "f".into(),
        role: Role::HeldOut,
        mu: None,
        cutting_speed_m_per_min: 10.0,
        uncut_chip_thickness_mm: 0.06,
        measured_cutting_force_n_per_mm: 100.0,
        simulated_cutting_force_n_per_mm: 100.0,
        measured_feed_force_n_per_mm: 50.0,
        simulated_feed_force_n_per_mm: 50.0,
        measured_chip_ratio: Some(1.5),
        simulated_chip_ratio: Some(1.5 * (1.0 + e)),
        simulated_extent_ratio: None,
        measured_contact_length_mm: None,
        simulated_contact_length_mm: None,
        cutting_force_error: 0.0,
        feed_force_error: 0.0,
        chip_ratio_error: Some(e),
        simulated_ci95: [None; 3],
        error_se: [Some(0.01), Some(0.01), cut_se],
        measured_error_se: [None, None, measured_se],
        steady_length_mm: None,
        steady_from_mm: None,
        sure: true,
        short_stretch: false,
        local: Default::default(),
        max_temperature_c: 20.0,
        steady: true,
        simulated_cut_length_mm: 1.0,
        wall_s: 1.0,
    }
}
