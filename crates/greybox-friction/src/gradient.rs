//! μ and its partial derivatives ∂μ/∂p, ∂μ/∂v, ∂μ/∂T for implicit solvers (Abaqus/Standard's
//! FRIC_COEF asks for them), by central differences with steps relative to the state.
//! For piecewise-constant laws (tree ensembles) the derivative is zero almost everywhere.

use greybox_core::{ContactState, FrictionLaw};

/// (μ, [∂μ/∂p (1/Pa), ∂μ/∂v (s/m), ∂μ/∂T (1/K)]).
pub fn mu_and_gradient(law: &dyn FrictionLaw, s: &ContactState) -> (f64, [f64; 3]) {
    let mu = law.mu(s);
    let hp = 1e-6 * s.pressure_pa.abs().max(1e6);
    let hv = 1e-6 * s.sliding_velocity_m_s.abs().max(1e-2);
    let ht = 1e-6 * s.temperature_k.abs().max(1.0);
    let d = |a: ContactState, b: ContactState, h: f64| (law.mu(&a) - law.mu(&b)) / (2.0 * h);
    let dp = d(
        ContactState {
            pressure_pa: s.pressure_pa + hp,
            ..*s
        },
        ContactState {
            pressure_pa: s.pressure_pa - hp,
            ..*s
        },
        hp,
    );
    let dv = d(
        ContactState {
            sliding_velocity_m_s: s.sliding_velocity_m_s + hv,
            ..*s
        },
        ContactState {
            sliding_velocity_m_s: s.sliding_velocity_m_s - hv,
            ..*s
        },
        hv,
    );
    let dt = d(
        ContactState {
            temperature_k: s.temperature_k + ht,
            ..*s
        },
        ContactState {
            temperature_k: s.temperature_k - ht,
            ..*s
        },
        ht,
    );
    (mu, [dp, dv, dt])
}
