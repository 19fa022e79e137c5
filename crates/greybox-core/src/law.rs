//! The friction-law seam.
//!
//! It lives in `greybox-core` (not in the friction crate) so that every producer and
//! consumer of friction — the virtual tribometer, the simulator, the coupling loop,
//! the exporters — can share it without depending on the learning stack.

use crate::ContactState;

/// Closed interval of a contact variable in SI units.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Range {
    pub min: f64,
    pub max: f64,
}

impl Range {
    pub fn contains(&self, x: f64) -> bool {
        x >= self.min && x <= self.max
    }
}

/// The contact states a law is valid for (fitted or calibrated on).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ValidityDomain {
    /// Pressure, Pa.
    pub pressure_pa: Range,
    /// Sliding velocity, m/s.
    pub sliding_velocity_m_s: Range,
    /// Temperature, K (`None`: the law does not depend on temperature).
    pub temperature_k: Option<Range>,
}

impl ValidityDomain {
    pub fn contains(&self, s: &ContactState) -> bool {
        self.pressure_pa.contains(s.pressure_pa)
            && self.sliding_velocity_m_s.contains(s.sliding_velocity_m_s)
            && self
                .temperature_k
                .is_none_or(|t| t.contains(s.temperature_k))
    }
}

/// Axis lines across which a law's μ may jump, per SI contact variable: ascending, finite and
/// distinct. A line `b` splits its axis into `x <= b` and `x > b` (the side a tree split
/// `feature <= threshold` sends left, restated in SI by [`crate::boundary::last_true`]).
///
/// Velocity lines are on the sliding speed |v| (m/s, ≥ 0): laws see velocity through |v|.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Breaks {
    /// Pressure, Pa.
    pub pressure_pa: Vec<f64>,
    /// Sliding speed |v|, m/s.
    pub sliding_velocity_m_s: Vec<f64>,
    /// Temperature, K.
    pub temperature_k: Vec<f64>,
    /// `true`: μ is constant on every cell these lines cut (p, |v|, T) space into — along each
    /// axis the cells are x ≤ b₀, b₀ < x ≤ b₁, …, x > bₙ₋₁ — as for a tree ensemble (no lines
    /// on an axis: μ does not depend on that variable). `false`: μ is continuous apart from
    /// jumps across the lines.
    pub constant_between: bool,
}

impl Breaks {
    /// The lines of axis 0 (pressure), 1 (velocity) or 2 (temperature).
    pub fn axis(&self, a: usize) -> &[f64] {
        match a {
            0 => &self.pressure_pa,
            1 => &self.sliding_velocity_m_s,
            _ => &self.temperature_k,
        }
    }
    /// Mutable lines of axis `a`, as [`Breaks::axis`].
    pub fn axis_mut(&mut self, a: usize) -> &mut Vec<f64> {
        match a {
            0 => &mut self.pressure_pa,
            1 => &mut self.sliding_velocity_m_s,
            _ => &mut self.temperature_k,
        }
    }
    /// Sort every axis, drop non-finite values, duplicates and negative speeds.
    pub fn normalize(mut self) -> Self {
        for a in 0..3 {
            let v = self.axis_mut(a);
            v.retain(|x| x.is_finite() && (a != 1 || *x >= 0.0));
            v.sort_by(f64::total_cmp);
            v.dedup(); // by ==, so −0 and +0 are one line
        }
        self
    }
    /// Lines of either (jumps of a combination of two laws); never `constant_between`.
    pub fn union(a: Option<Breaks>, b: Option<Breaks>) -> Option<Breaks> {
        let mut out = match (a, b) {
            (None, None) => return None,
            (Some(x), None) | (None, Some(x)) => x,
            (Some(mut x), Some(y)) => {
                for k in 0..3 {
                    x.axis_mut(k).extend_from_slice(y.axis(k));
                }
                x
            }
        };
        out.constant_between = false;
        Some(out.normalize())
    }
    /// Number of cells of a piecewise-constant law: Π (lines + 1), `None` on overflow.
    pub fn cells(&self) -> Option<usize> {
        (0..3).try_fold(1usize, |n, a| n.checked_mul(self.axis(a).len() + 1))
    }
}

/// A friction law: Coulomb coefficient μ as a function of the local contact state.
///
/// The extension seam for your own law: implement `name` and `mu` (SI state in, μ out), and
/// the law works everywhere a law file does — the simulator's friction windows, engine
/// exports, surrogate tables, the C ABI. A law falling with sliding speed, capped by
/// sticking at the shear flow stress k:
///
/// ```
/// use greybox_core::{ContactState, FrictionLaw};
/// struct SpeedSoftening { mu0: f64, v_ref_m_s: f64 }
/// impl FrictionLaw for SpeedSoftening {
///     fn name(&self) -> String { "speed-softening".into() }
///     fn mu(&self, s: &ContactState) -> f64 {
///         self.mu0 / (1.0 + s.sliding_velocity_m_s / self.v_ref_m_s)
///     }
/// }
/// let law = SpeedSoftening { mu0: 0.6, v_ref_m_s: 2.0 };
/// let s = ContactState::new(800e6, 2.0); // 800 MPa, 2 m/s
/// assert_eq!(law.mu(&s), 0.3);
/// // default shear stress: τ = μ p = 240 MPa, below k = 500 MPa; capped at k = 200 MPa
/// assert_eq!(law.shear_stress(&s, 500e6), 240e6);
/// assert_eq!(law.shear_stress(&s, 200e6), 200e6);
/// ```
pub trait FrictionLaw: Send + Sync {
    /// Short human-readable name (for reports and file headers).
    fn name(&self) -> String;

    /// Friction coefficient μ (dimensionless) at a contact state.
    fn mu(&self, state: &ContactState) -> f64;

    /// Batch form: writes μ for every state into `out` (same length).
    fn mu_batch(&self, states: &[ContactState], out: &mut [f64]) {
        for (s, o) in states.iter().zip(out.iter_mut()) {
            *o = self.mu(s);
        }
    }

    /// Frictional shear stress τ (Pa) for a workpiece shear flow stress `k_pa`.
    /// Default: Coulomb τ = μ p capped by sticking, τ ≤ k (Zorev).
    fn shear_stress(&self, state: &ContactState, k_pa: f64) -> f64 {
        (self.mu(state) * state.pressure_pa).min(k_pa)
    }

    /// The domain the law was fitted/calibrated on, if it has one.
    fn domain(&self) -> Option<ValidityDomain> {
        None
    }

    /// Where μ may jump ([`Breaks`]): the split thresholds of a tree ensemble restated in SI,
    /// and the laws built on one. `None`: μ is continuous as far as the law knows. Tables use
    /// the lines to be exact at steps (a cell per step, or two nodes one ulp apart).
    fn breaks(&self) -> Option<Breaks> {
        None
    }
}
