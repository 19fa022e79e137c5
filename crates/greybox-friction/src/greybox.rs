//! The grey-box law: a learned law inside its training domain, a physics law (or a white-box
//! form fitted to the learned law) outside it, blended smoothly across a border band, with an
//! optional Zorev shear cap τ ≤ k and optional clamping of μ.
//!
//! Blend: for each contact variable with a domain range [lo, hi], the distance outside the
//! range is measured in units of the band width b = `blend_fraction` · (hi − lo); d is the
//! largest of these. The weight of the learned law is w = 1 − (3d² − 2d³) for 0 ≤ d ≤ 1
//! (smoothstep, C¹), 0 beyond. The learned law is always evaluated at the state projected
//! onto its domain, so a tree ensemble is never extrapolated.

use greybox_core::law::{Range, ValidityDomain};
use greybox_core::linalg::solve3;
use greybox_core::{units, Breaks, ContactState, Error, FrictionLaw, Result};
use serde::{Deserialize, Serialize};

/// The blend band's width as a share of each feature's range (b = 0.1 · (hi − lo)).
pub const DEFAULT_BLEND_FRACTION: f64 = 0.1;
/// The widest band: half the range (wider, the two sides' bands would overlap).
pub const MAX_BLEND_FRACTION: f64 = 0.5;

pub struct GreyBoxLaw {
    pub inner: Box<dyn FrictionLaw>,
    pub outside: Box<dyn FrictionLaw>,
    pub blend_fraction: f64,
    /// Zorev cap: τ ≤ k (Pa).
    pub shear_cap_k_pa: Option<f64>,
    pub clamp: Option<(f64, f64)>,
    domain: ValidityDomain,
}

/// The least plausible shear cap k, MPa: the shear flow stress of the softest metals cut
/// (pure aluminium, lead alloys aside) is above it; a smaller value is a unit slip (GPa for MPa)
/// that caps every window's shear stress and makes μ the clamp's lower bound everywhere.
pub const MIN_SHEAR_CAP_MPA: f64 = 50.0;

impl GreyBoxLaw {
    pub fn new(
        inner: Box<dyn FrictionLaw>,
        outside: Box<dyn FrictionLaw>,
        blend_fraction: f64,
        shear_cap_k_pa: Option<f64>,
        clamp: Option<(f64, f64)>,
    ) -> Result<Self> {
        use greybox_core::physics::Quantity;
        let mut rules = greybox_core::rules::Rules::new("grey-box law");
        // a fraction of the domain's width: 5 (a percentage typed) would blend far outside
        rules
            .above_up_to("blend_fraction", blend_fraction, 0.0, MAX_BLEND_FRACTION)
            .physics("blend_fraction", Quantity::Share, blend_fraction);
        if let Some(k) = shear_cap_k_pa {
            // a cap ≤ 0 made every window slide at the clamp's lower bound (μ = 0.05 everywhere);
            // so did a cap in GPa typed where MPa is meant (0.6 or 1 for 600 MPa)
            let k_mpa = k / units::PA_PER_MPA;
            rules.positive("shear_cap_k_MPa", k_mpa).relation(
                !(k_mpa > 0.0) || k_mpa >= MIN_SHEAR_CAP_MPA,
                format!(
                    "shear_cap_k_MPa is {k_mpa} MPa, below any metal's shear flow stress ({MIN_SHEAR_CAP_MPA} MPa is the least accepted; steels and titanium alloys are 300-900 MPa): is the value in GPa? give it in MPa"
                ),
            );
        }
        if let Some((lo, hi)) = clamp {
            rules
                .physics("clamp[0]", Quantity::Mu, lo)
                .physics("clamp[1]", Quantity::Mu, hi)
                .relation(lo <= hi, format!("clamp needs min ≤ max, got [{lo}, {hi}]"));
        }
        rules.finish()?;
        let domain = inner.domain().ok_or_else(|| {
            Error::invalid("grey-box law", "the inner law has no validity domain")
        })?;

        Ok(GreyBoxLaw {
            inner,
            outside,
            blend_fraction,
            shear_cap_k_pa,
            clamp,
            domain,
        })
    }

    /// Weight of the learned law at a state, and the state projected onto the domain.
    pub fn weight(&self, s: &ContactState) -> (f64, ContactState) {
        let mut d: f64 = 0.0;
        let mut proj = *s;
        let mut axis = |x: f64, r: Range| -> f64 {
            let band = self.blend_fraction * (r.max - r.min).max(f64::MIN_POSITIVE);
            let out = (r.min - x).max(x - r.max).max(0.0);
            d = d.max(out / band);
            x.clamp(r.min, r.max)
        };
        proj.pressure_pa = axis(s.pressure_pa, self.domain.pressure_pa);
        proj.sliding_velocity_m_s = axis(
            s.sliding_velocity_m_s.abs(),
            self.domain.sliding_velocity_m_s,
        );
        if let Some(t) = self.domain.temperature_k {
            proj.temperature_k = axis(s.temperature_k, t);
        }
        let w = if d >= 1.0 {
            0.0
        } else {
            1.0 - d * d * (3.0 - 2.0 * d)
        };
        (w, proj)
    }
}

impl FrictionLaw for GreyBoxLaw {
    fn name(&self) -> String {
        format!(
            "grey-box [{} inside, {} outside]",
            self.inner.name(),
            self.outside.name()
        )
    }
    fn mu(&self, s: &ContactState) -> f64 {
        let (w, proj) = self.weight(s);
        let mut mu = if w >= 1.0 {
            self.inner.mu(&proj)
        } else if w <= 0.0 {
            self.outside.mu(s)
        } else {
            w * self.inner.mu(&proj) + (1.0 - w) * self.outside.mu(s)
        };
        if let Some(k) = self.shear_cap_k_pa {
            if mu * s.pressure_pa > k {
                mu = k / s.pressure_pa;
            }
        }
        if let Some((lo, hi)) = self.clamp {
            mu = mu.clamp(lo, hi);
        }
        mu
    }
    fn shear_stress(&self, s: &ContactState, k: f64) -> f64 {
        (self.mu(s) * s.pressure_pa).min(self.shear_cap_k_pa.unwrap_or(k).min(k))
    }
    fn domain(&self) -> Option<ValidityDomain> {
        None // defined everywhere
    }
    /// The inner law's jumps inside its domain (outside it the inner law is evaluated at the
    /// projected state, which stays on one side of a line b with min ≤ b < max only inside)
    /// and the outside law's jumps; the blend, the shear cap and the clamp are continuous.
    fn breaks(&self) -> Option<Breaks> {
        let inner = self.inner.breaks().map(|mut b| {
            let ranges = [
                Some(self.domain.pressure_pa),
                Some(self.domain.sliding_velocity_m_s),
                self.domain.temperature_k,
            ];
            for (a, r) in ranges.into_iter().enumerate() {
                if let Some(r) = r {
                    b.axis_mut(a).retain(|&x| x >= r.min && x < r.max);
                }
            }
            b
        });
        Breaks::union(inner, self.outside.breaks())
    }
}

/// A white-box power law μ = μ_ref (p/p_ref)^a (v/v_ref)^b, fitted by least squares in log space.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PowerLaw {
    pub mu_ref: f64,
    pub p_ref_pa: f64,
    pub v_ref_m_s: f64,
    pub a: f64,
    pub b: f64,
    /// Floor and ceiling of μ.
    pub mu_min: f64,
    pub mu_max: f64,
}

impl PowerLaw {
    /// Fit to a law over its domain (n × n log-spaced grid): the "fitted white-box form" used
    /// outside the training domain.
    pub fn fit_to(law: &dyn FrictionLaw, n: usize) -> Result<Self> {
        let d = law
            .domain()
            .ok_or_else(|| Error::invalid("power-law fit", "the law has no validity domain"))?;
        let (p0, p1) = (d.pressure_pa.min.max(1.0), d.pressure_pa.max.max(1.0));
        let (v0, v1) = (
            d.sliding_velocity_m_s.min.max(1e-6),
            d.sliding_velocity_m_s.max.max(1e-6),
        );
        let (p_ref, v_ref) = ((p0 * p1).sqrt(), (v0 * v1).sqrt());
        let t = d
            .temperature_k
            .map(|r| 0.5 * (r.min + r.max))
            .unwrap_or(ContactState::ROOM_TEMPERATURE_K);
        // normal equations for ln μ = c + a ln(p/p_ref) + b ln(v/v_ref)
        let mut ata = [[0.0f64; 3]; 3];
        let mut atb = [0.0f64; 3];
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let n = n.max(2);
        for i in 0..n {
            for j in 0..n {
                let p = p0 * (p1 / p0).powf(i as f64 / (n - 1) as f64);
                let v = v0 * (v1 / v0).powf(j as f64 / (n - 1) as f64);
                let mu = law.mu(&ContactState {
                    pressure_pa: p,
                    sliding_velocity_m_s: v,
                    temperature_k: t,
                });
                if !(mu > 0.0) {
                    return Err(Error::invalid(
                        "power-law fit",
                        format!("μ = {mu} ≤ 0 at p = {p} Pa, v = {v} m/s"),
                    ));
                }
                lo = lo.min(mu);
                hi = hi.max(mu);
                let row = [1.0, (p / p_ref).ln(), (v / v_ref).ln()];
                for r in 0..3 {
                    for c in 0..3 {
                        ata[r][c] += row[r] * row[c];
                    }
                    atb[r] += row[r] * mu.ln();
                }
            }
        }
        let x = solve3(ata, atb)
            .ok_or_else(|| Error::invalid("power-law fit", "singular fit (degenerate domain)"))?;
        Ok(PowerLaw {
            mu_ref: x[0].exp(),
            p_ref_pa: p_ref,
            v_ref_m_s: v_ref,
            a: x[1],
            b: x[2],
            mu_min: 0.5 * lo,
            mu_max: 1.5 * hi,
        })
    }
}

impl FrictionLaw for PowerLaw {
    fn name(&self) -> String {
        format!(
            "power law μ = {:.4} (p/p_ref)^{:.3} (v/v_ref)^{:.3}",
            self.mu_ref, self.a, self.b
        )
    }
    fn mu(&self, s: &ContactState) -> f64 {
        let p = s.pressure_pa.max(1.0) / self.p_ref_pa;
        let v = s.sliding_velocity_m_s.abs().max(1e-6) / self.v_ref_m_s;
        (self.mu_ref * p.powf(self.a) * v.powf(self.b)).clamp(self.mu_min, self.mu_max)
    }
}
