//! Measures of an orthogonal cut: chip thickness, shear angle, tool–chip contact length and
//! the contact profiles along the tool (the article's Fig. 15, bottom).
//!
//! * The chip's *band*: the free particles whose centres lie between h and 2h above the
//!   original workpiece surface, in front of the rake face ([`MEASURING_BAND_H`]).
//! * Chip thickness h_c, by continuity: the band's mass-weighted mean velocity relative to
//!   the tool, v̄_chip, carries the volume the cut removes, h v_c = h_c |v̄_chip| (plane
//!   strain, the chip's density that of the workpiece), so h_c = h v_c / |v̄_chip|. It is the
//!   mean thickness of a continuous chip whatever its direction: a chip that has left the
//!   rake face inside the band, or whose free side is ragged, measures the same.
//! * Chip extent ([`chip_extent`]): the band projected on the rake-face normal,
//!   (max − min) + Δx (a particle occupies Δx; with refinement, half the spacing of each of
//!   the two outermost particles). The thickness measure until 2026-12-01: the outer size of
//!   the chip, which exceeds its mean thickness t by the free side's roughness and, where the
//!   chip's axis leaves the rake face at an angle θ inside the band, is
//!   (h sin θ + t cos γ)/cos(γ − θ) for a straight chip (γ the rake angle; docs/validation.md,
//!   "How thick is the chip?").
//! * Shear angle from the chip compression ratio r = h/h_c (Merchant's continuity relation):
//!   tan φ = r cos γ / (1 − r sin γ).
//! * Contact length: the farthest rake-face window (distance from the edge, outer end) that
//!   was in contact for at least `min_fraction` of its length on time average.

use crate::cutting::{CuttingSetup, EdgeLayout, Face, MEASURING_BAND_H};
use crate::particles::FREE;
use crate::solver::Solver;
use crate::tool::{Tool, WindowAccumulator, WindowStats};
use serde::{Deserialize, Serialize};

/// The fewest band particles a chip measure rests on.
const MIN_BAND_PARTICLES: usize = 3;

/// The chip's band (module docs): each particle's index and its distance along the
/// rake-face normal from the rake line, m (`None`: fewer than [`MIN_BAND_PARTICLES`], no
/// chip yet).
fn chip_band(sim: &Solver, setup: &CuttingSetup, tool: usize) -> Option<Vec<(usize, f64)>> {
    let t = sim.tools.get(tool)?;
    let p = &sim.particles;
    let dx = p.spacing;
    let h = setup.uncut_chip_thickness_m;
    let g = setup.insert.rake_deg.to_radians();
    // Rake-face normal pointing into the chip; the rake line passes through the sharp-edge
    // point, the tool's local origin.
    let n = [-g.cos(), g.sin()];
    let top = -0.5 * setup.surface_spacing();
    let band = MEASURING_BAND_H.map(|k| top + k * h);
    let inside: Vec<(usize, f64)> = (0..p.len())
        .filter(|&i| p.group[i] == FREE && p.y[i] >= band[0] && p.y[i] <= band[1])
        .map(|i| {
            let d = (p.x[i] - t.position[0]) * n[0] + (p.y[i] - t.position[1]) * n[1];
            (i, d)
        })
        .filter(|&(_, d)| d > -dx && d < 10.0 * h)
        .collect();
    (inside.len() >= MIN_BAND_PARTICLES).then_some(inside)
}

/// Chip thickness by continuity, m (module docs): h_c = h v_c / |v̄_chip|, v̄_chip the band's
/// mass-weighted mean velocity relative to the tool, v_c the tool's speed (`None` before a
/// chip has formed, or with the tool or the chip at rest).
pub fn chip_thickness(sim: &Solver, setup: &CuttingSetup, tool: usize) -> Option<f64> {
    thickness_of(sim, setup, tool, &chip_band(sim, setup, tool)?)
}

/// The chip's extent along the rake-face normal, m (module docs; `None` before a chip has
/// formed).
pub fn chip_extent(sim: &Solver, setup: &CuttingSetup, tool: usize) -> Option<f64> {
    extent_of(sim, &chip_band(sim, setup, tool)?)
}

/// Both chip measures of one instant, [`chip_thickness`] and [`chip_extent`], from one scan
/// of the particles.
pub fn chip_thickness_and_extent(
    sim: &Solver,
    setup: &CuttingSetup,
    tool: usize,
) -> (Option<f64>, Option<f64>) {
    chip_band(sim, setup, tool).map_or((None, None), |band| {
        (thickness_of(sim, setup, tool, &band), extent_of(sim, &band))
    })
}

/// [`chip_thickness`] of the band `band`.
fn thickness_of(
    sim: &Solver,
    setup: &CuttingSetup,
    tool: usize,
    band: &[(usize, f64)],
) -> Option<f64> {
    let p = &sim.particles;
    let v_tool = sim.tools[tool].motion.velocity(sim.time);
    let (mut m, mut mvx, mut mvy) = (0.0, 0.0, 0.0);
    for &(i, _) in band {
        let mi = p.mass_of(i);
        m += mi;
        mvx += mi * (p.vx[i] - v_tool[0]);
        mvy += mi * (p.vy[i] - v_tool[1]);
    }
    let chip_speed = mvx.hypot(mvy) / m;
    let cutting_speed = v_tool[0].hypot(v_tool[1]);
    let h_c = setup.uncut_chip_thickness_m * cutting_speed / chip_speed;
    (h_c.is_finite() && h_c > 0.0).then_some(h_c)
}

/// [`chip_extent`] of the band `band`: the two outermost particles' distances and half
/// their spacings (the first of equal ones).
fn extent_of(sim: &Solver, band: &[(usize, f64)]) -> Option<f64> {
    let p = &sim.particles;
    let &(i_lo, lo) = band.iter().reduce(|a, b| if b.1 < a.1 { b } else { a })?;
    let &(i_hi, hi) = band.iter().reduce(|a, b| if b.1 > a.1 { b } else { a })?;
    Some(hi - lo + 0.5 * (p.spacing_of(i_lo) + p.spacing_of(i_hi)))
}

/// Shear angle φ (degrees) from the uncut and cut chip thickness and the rake angle γ.
pub fn shear_angle_deg(h: f64, h_c: f64, rake_deg: f64) -> f64 {
    let r = h / h_c;
    let g = rake_deg.to_radians();
    (r * g.cos() / (1.0 - r * g.sin())).atan().to_degrees()
}

/// One window of a contact profile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ProfilePoint {
    pub window: usize,
    pub face: Face,
    /// Signed distance of the window centre from the edge along the surface, m (positive up
    /// the rake face, negative along the flank).
    pub distance_m: f64,
    /// The μ the window used at the end of the run.
    pub mu: f64,
    /// Time-averaged contact state (`None`: never in contact).
    pub stats: Option<WindowStats>,
}

/// The contact profile of the rake, edge and flank windows from interval sums (one
/// [`WindowAccumulator`] per window of `tool`), ordered from the top of the rake face to the
/// end of the flank face.
pub fn contact_profile(
    tool: &Tool,
    layout: &EdgeLayout,
    sums: &[WindowAccumulator],
    spacing: f64,
) -> Vec<ProfilePoint> {
    tool.windows
        .iter()
        .zip(sums)
        .enumerate()
        .filter_map(|(k, (w, acc))| {
            let (face, distance_m) = layout.locate(0.5 * (w.s_start + w.s_end));
            (face != Face::Back).then(|| ProfilePoint {
                window: k,
                face,
                distance_m,
                mu: w.mu,
                stats: acc.stats(spacing, w.length()),
            })
        })
        .collect()
}

/// Tool–chip contact length on the rake side, m: outer end of the farthest rake or edge
/// window in contact for at least `min_fraction` of its length.
pub fn contact_length(
    profile: &[ProfilePoint],
    window_length: f64,
    min_fraction: f64,
) -> Option<f64> {
    profile
        .iter()
        .filter(|p| p.distance_m >= 0.0 && p.face != Face::Back)
        .filter(|p| p.stats.is_some_and(|s| s.contact_fraction >= min_fraction))
        .map(|p| p.distance_m + 0.5 * window_length)
        .max_by(f64::total_cmp)
}

/// Windows in contact for less than this fraction of their length on time average count as
/// out of contact (for the contact length and the rake-face contact quantities).
pub const IN_CONTACT: f64 = 0.1;

/// The contact state along the rake face (edge included) over the windows in contact: where
/// friction laws differ, the μ applied and the pressures and sliding velocities it was
/// applied at.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct RakeContact {
    /// The μ the windows applied at the end of the run, averaged over the windows in contact
    /// (equal lengths: the contact-length average).
    pub mean_mu: Option<f64>,
    /// Least and greatest window contact pressure, MPa.
    pub pressure_mpa: Option<[f64; 2]>,
    /// Least and greatest window sliding velocity (force-weighted per window), m/min.
    pub sliding_velocity_m_per_min: Option<[f64; 2]>,
}

/// The rake-face contact quantities of `profile`: its rake and edge windows in contact for
/// at least `min_fraction` of their length (all `None` without one).
pub fn rake_contact(profile: &[ProfilePoint], min_fraction: f64) -> RakeContact {
    let rake: Vec<(f64, WindowStats)> = profile
        .iter()
        .filter(|p| matches!(p.face, Face::Rake | Face::Edge))
        .filter_map(|p| p.stats.map(|s| (p.mu, s)))
        .filter(|(_, s)| s.contact_fraction >= min_fraction)
        .collect();
    if rake.is_empty() {
        return RakeContact::default();
    }
    let range = |f: &dyn Fn(&WindowStats) -> f64| {
        let values = rake.iter().map(|(_, s)| f(s));
        let lo = values.clone().fold(f64::INFINITY, f64::min);
        let hi = values.fold(f64::NEG_INFINITY, f64::max);
        Some([lo, hi])
    };
    RakeContact {
        mean_mu: Some(rake.iter().map(|(mu, _)| mu).sum::<f64>() / rake.len() as f64),
        pressure_mpa: range(&|s| s.pressure_pa / greybox_core::units::PA_PER_MPA),
        sliding_velocity_m_per_min: range(&|s| {
            greybox_core::units::m_per_s_to_m_per_min(s.sliding_velocity_m_s)
        }),
    }
}

/// The summary measures of a cut.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CutMeasures {
    pub chip_thickness_mm: Option<f64>,
    pub compression_ratio: Option<f64>,
    pub shear_angle_deg: Option<f64>,
    pub contact_length_mm: Option<f64>,
    pub max_temperature_c: f64,
    /// μ, pressure and sliding velocity along the rake face.
    pub rake_contact: RakeContact,
}

/// Chip thickness, compression ratio, shear angle, contact length and the maximum particle
/// temperature: the chip thickness and contact length are `steady`'s (the steady state's
/// means, m) where the cut has them, else the chip at the end and the contact length of
/// `profile`.
pub fn measure(
    sim: &Solver,
    setup: &CuttingSetup,
    tool: usize,
    profile: &[ProfilePoint],
    steady: [Option<f64>; 2],
) -> CutMeasures {
    let h = setup.uncut_chip_thickness_m;
    let hc = steady[0].or_else(|| chip_thickness(sim, setup, tool));
    let contact =
        steady[1].or_else(|| contact_length(profile, setup.friction.window_length_m, IN_CONTACT));
    CutMeasures {
        chip_thickness_mm: hc.map(|v| v * 1e3),
        compression_ratio: hc.map(|v| v / h),
        shear_angle_deg: hc.map(|v| shear_angle_deg(h, v, setup.insert.rake_deg)),
        contact_length_mm: contact.map(|v| v * 1e3),
        max_temperature_c: sim.particles.temp.iter().copied().fold(f64::MIN, f64::max) - 273.15,
        rake_contact: rake_contact(profile, IN_CONTACT),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merchant_shear_angle() {
        // r = 0.5, γ = 0: tan φ = 0.5 → φ = 26.565°.
        assert!((shear_angle_deg(0.1, 0.2, 0.0) - 26.565051177).abs() < 1e-8);
        // Positive rake raises φ; r = 1 with γ = 0 gives 45°.
        assert!(shear_angle_deg(0.1, 0.25, 10.0) > shear_angle_deg(0.1, 0.25, 0.0));
        assert!((shear_angle_deg(0.1, 0.1, 0.0) - 45.0).abs() < 1e-12);
    }

    fn window(face: Face, mu: f64, contact: Option<(f64, f64, f64)>) -> ProfilePoint {
        ProfilePoint {
            window: 0,
            face,
            distance_m: 0.0,
            mu,
            stats: contact.map(|(fraction, p_mpa, v_m_s)| WindowStats {
                pressure_pa: p_mpa * 1e6,
                normal_stress_pa: p_mpa * 1e6 * fraction,
                sliding_velocity_m_s: v_m_s,
                temperature_k: 600.0,
                shear_stress_pa: mu * p_mpa * 1e6,
                mu_effective: mu,
                contact_fraction: fraction,
                slip_fraction: 1.0,
                tool_temperature_k: None,
            }),
        }
    }

    #[test]
    fn rake_contact_averages_the_rake_and_edge_windows_in_contact_only() {
        let profile = [
            window(Face::Rake, 0.9, Some((0.05, 100.0, 1.0))), // barely touched: out
            window(Face::Rake, 0.3, Some((0.5, 800.0, 0.5))),
            window(Face::Edge, 0.5, Some((1.0, 2000.0, 0.1))),
            window(Face::Rake, 0.7, None), // never in contact
            window(Face::Flank, 0.1, Some((1.0, 3000.0, 2.0))), // not the rake face
        ];
        let r = rake_contact(&profile, IN_CONTACT);
        assert!((r.mean_mu.unwrap() - 0.4).abs() < 1e-15);
        assert_eq!(r.pressure_mpa, Some([800.0, 2000.0]));
        let v = r.sliding_velocity_m_per_min.unwrap();
        assert!(
            (v[0] - 6.0).abs() < 1e-12 && (v[1] - 30.0).abs() < 1e-12,
            "{v:?}"
        );
        assert_eq!(
            rake_contact(&profile[3..], IN_CONTACT),
            RakeContact::default()
        );
    }
}
