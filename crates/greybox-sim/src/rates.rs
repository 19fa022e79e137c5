//! Per-particle rates: what the neighbour gather and the tool contact add up for each
//! particle in a step (accelerations, kinematics sums, heating), shared by the solver and the
//! contact model without either importing the other.

/// Per-particle rates from the neighbour gather.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Rates {
    pub ax: f64,
    pub ay: f64,
    /// Kinematics sums: ρ̇ (kg/(m³·s)), L_xx, L_xy, L_yx, L_yy (1/s) and the XSPH velocity
    /// correction before the factor ε (m/s).
    pub kin: [f64; 7],
    /// dT/dt, K/s (conduction, then friction heating). Between steps 3a and 3b it holds the
    /// raw conduction sum ρ c dT/dt, W/m³.
    pub dtemp: f64,
    /// Artificial-viscosity dissipation of the pairs whose first partner is this particle,
    /// W/m (only the total over all particles is meaningful).
    pub av_power: f64,
}
