//! μ and its partial derivatives ∂μ/∂p, ∂μ/∂v, ∂μ/∂T for implicit solvers (Abaqus/Standard's
//! FRIC_COEF asks for them), by central differences with steps relative to the state.
//! For piecewise-constant laws (tree ensembles) the derivative is zero almost everywhere.

use greybox_core::{ContactState, FrictionLaw};

/// (μ, [∂μ/∂p (1/Pa), ∂μ/∂v (s/m), ∂μ/∂T (1/K)]).
pub fn mu_and_gradient(law: &dyn FrictionLaw, s: &ContactState) -> (f64, [f64; 3]) {
    let mu = law.mu(s);
    let steps = [
        1e-6 * s.pressure_pa.abs().max(1e6),
        1e-6 * s.sliding_velocity_m_s.abs().max(1e-2),
        1e-6 * s.temperature_k.abs().max(1.0),
    ];
    let shifted = |axis: usize, h: f64| {
        let mut x = *s;
        match axis {
            0 => x.pressure_pa += h,
            1 => x.sliding_velocity_m_s += h,
            _ => x.temperature_k += h,
        }
        x
    };
    let mut g = [0.0; 3];
    for (axis, (gi, h)) in g.iter_mut().zip(steps).enumerate() {
        *gi = (law.mu(&shifted(axis, h)) - law.mu(&shifted(axis, -h))) / (2.0 * h);
    }
    (mu, g)
}
