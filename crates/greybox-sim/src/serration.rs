//! The serration of a chip at one instant: its thickness along its length, the segments'
//! peaks and valleys, their pitch and the degree of segmentation.
//!
//! The chip particles in front of the rake face and clear of the primary shear zone (more
//! than h above the uncut surface) are binned along the rake face (bins of twice the finest
//! spacing among them); in each bin the thickness is the extent of the particles' distances
//! from the rake face plus one spacing. A serrated chip's thickness rises and falls along
//! it: a *peak* is a local maximum that stands more than one particle spacing above the
//! valleys on both sides of it (a smaller ripple is the particle lattice, not a segment),
//! and a *valley* the least thickness between two peaks. Where the chip holds particles of
//! several spacings (a refined cut whose chip is coarsened, or whose chip began before the
//! refinement), "one spacing" is the coarser of the two bins compared, each bin's being the
//! coarser of its two extreme particles': a coarse lattice's ripple is no segment either.
//! Then
//!
//! * the **segment pitch** p_c is the mean distance between neighbouring peaks along the
//!   chip, m;
//! * the **degree of segmentation** G_s = (h_max − h_min)/h_max, with h_max and h_min the
//!   mean peak and valley thickness (Schulz, Abele & Sahm 2001, CIRP Annals 50(1):45; the
//!   measure used for Ti6Al4V chips, e.g. Sima & Özel 2010).
//!
//! A chip with fewer than two peaks at an instant has no serration there (`None`).

use crate::cutting::CuttingSetup;
use crate::particles::FREE;
use crate::solver::Solver;
use serde::{Deserialize, Serialize};

/// A chip's serration at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Serration {
    /// Mean distance between neighbouring peaks along the chip, m.
    pub pitch_m: f64,
    /// G_s = (h_max − h_min)/h_max.
    pub degree: f64,
    /// Mean peak and valley thickness, m.
    pub peak_m: f64,
    pub valley_m: f64,
    pub peaks: usize,
}

/// The chip's shape at one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct ChipShape {
    /// The thickness per bin along the rake face holding at least three particles, in order
    /// along the chip.
    pub profile: Vec<ProfileBin>,
    /// The finest particle spacing in the chip, m.
    pub fine: f64,
    /// The farthest chip particle along the rake face within one spacing of it, m: the
    /// tool–chip contact length as the chip's particles show it.
    pub contact_length_m: Option<f64>,
}

/// One bin of a chip's thickness profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfileBin {
    /// Distance along the rake face from the edge point, m.
    pub along_m: f64,
    /// Chip thickness, m.
    pub thickness_m: f64,
    /// The coarser spacing of the bin's two extreme particles, m: thickness ripples smaller
    /// than it are the particle lattice.
    pub spacing_m: f64,
}

/// The chip's thickness profile along the rake face and its contact with it (`None`: no
/// chip yet).
pub fn chip_shape(sim: &Solver, setup: &CuttingSetup, tool: usize) -> Option<ChipShape> {
    let t = sim.tools.get(tool)?;
    let p = &sim.particles;
    let h = setup.uncut_chip_thickness_m;
    let g = setup.insert.rake_deg.to_radians();
    // rake-face normal into the chip, and the tangent up the rake face
    let n = [-g.cos(), g.sin()];
    let up = [g.sin(), g.cos()];
    let top = -0.5 * setup.surface_spacing();
    let mut chip: Vec<(f64, f64, f64)> = Vec::new();
    let mut contact: Option<f64> = None;
    for i in 0..p.len() {
        if p.group[i] != FREE || p.y[i] < top {
            continue;
        }
        let (dx, dy) = (p.x[i] - t.position[0], p.y[i] - t.position[1]);
        let d = dx * n[0] + dy * n[1];
        let s = dx * up[0] + dy * up[1];
        let own = p.spacing_of(i);
        if d > -own && d < own && s > 0.0 {
            contact = Some(contact.map_or(s, |c: f64| c.max(s)));
        }
        if p.y[i] >= top + h && d > -p.spacing && d < 10.0 * h {
            chip.push((s, d, own));
        }
    }
    let fine = chip.iter().map(|c| c.2).fold(f64::INFINITY, f64::min);
    if chip.len() < 6 || !fine.is_finite() {
        return None;
    }
    let width = 2.0 * fine;
    let s0 = chip.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
    let bins = chip
        .iter()
        .map(|c| ((c.0 - s0) / width) as usize)
        .max()
        .unwrap_or(0)
        + 1;
    // per bin: count, least and greatest distance with their particles' spacings
    let mut acc = vec![(0usize, f64::INFINITY, 0.0, f64::NEG_INFINITY, 0.0); bins];
    for &(s, d, dx) in &chip {
        let b = &mut acc[((s - s0) / width) as usize];
        b.0 += 1;
        if d < b.1 {
            (b.1, b.2) = (d, dx);
        }
        if d > b.3 {
            (b.3, b.4) = (d, dx);
        }
    }
    let profile = acc
        .iter()
        .enumerate()
        .filter(|(_, b)| b.0 >= 3)
        .map(|(k, b)| ProfileBin {
            along_m: s0 + (k as f64 + 0.5) * width,
            thickness_m: b.3 - b.1 + 0.5 * (b.2 + b.4),
            spacing_m: b.2.max(b.4),
        })
        .collect();
    Some(ChipShape {
        profile,
        fine,
        contact_length_m: contact,
    })
}

/// The serration of a thickness `profile` (in order along the chip) whose ripples smaller
/// than the bins' spacing are no segments.
pub fn serration_of(profile: &[ProfileBin]) -> Option<Serration> {
    let (peaks, valleys) = turning_points(profile);
    if peaks.len() < 2 || valleys.is_empty() {
        return None;
    }
    let mean = |v: &[ProfileBin]| v.iter().map(|p| p.thickness_m).sum::<f64>() / v.len() as f64;
    let (hi, lo) = (mean(&peaks), mean(&valleys));
    let pitch = (peaks[peaks.len() - 1].along_m - peaks[0].along_m) / (peaks.len() - 1) as f64;
    Some(Serration {
        pitch_m: pitch,
        degree: (hi - lo) / hi,
        peak_m: hi,
        valley_m: lo,
        peaks: peaks.len(),
    })
}

impl ChipShape {
    /// The chip's serration (`None`: no two segments).
    pub fn serration(&self) -> Option<Serration> {
        serration_of(&self.profile)
    }
}

/// Bins of a thickness profile.
type Points = Vec<ProfileBin>;

/// The lattice's ripple between bins `a` and `b`: the coarser of their spacings, m.
fn ripple(a: ProfileBin, b: ProfileBin) -> f64 {
    a.spacing_m.max(b.spacing_m)
}

/// The peaks of `profile` that stand more than a spacing above the valleys on both sides,
/// and the valleys between neighbouring peaks (a zigzag with a spacing's hysteresis).
fn turning_points(profile: &[ProfileBin]) -> (Points, Points) {
    let mut extremes: Vec<(ProfileBin, bool)> = Vec::new(); // (bin, is a peak)
    let Some(&first) = profile.first() else {
        return (Vec::new(), Vec::new());
    };
    // candidates since the last confirmed extreme
    let (mut hi, mut lo) = (first, first);
    let mut rising: Option<bool> = None;
    for &p in &profile[1..] {
        if p.thickness_m > hi.thickness_m {
            hi = p;
        }
        if p.thickness_m < lo.thickness_m {
            lo = p;
        }
        match rising {
            Some(true) | None if p.thickness_m < hi.thickness_m - ripple(p, hi) => {
                if rising.is_some() || hi.thickness_m - lo.thickness_m > ripple(hi, lo) {
                    extremes.push((hi, true));
                }
                rising = Some(false);
                lo = p;
            }
            Some(false) | None if p.thickness_m > lo.thickness_m + ripple(p, lo) => {
                if rising.is_some() {
                    extremes.push((lo, false));
                }
                rising = Some(true);
                hi = p;
            }
            _ => {}
        }
    }
    // a peak counts only with a valley on both sides: drop the edges' unconfirmed ones
    let first_valley = extremes.iter().position(|e| !e.1);
    let last_valley = extremes.iter().rposition(|e| !e.1);
    let (Some(a), Some(b)) = (first_valley, last_valley) else {
        return (Vec::new(), Vec::new());
    };
    let inner = &extremes[a..=b];
    let peaks: Points = inner.iter().filter(|e| e.1).map(|e| e.0).collect();
    let valleys: Points = inner.iter().filter(|e| !e.1).map(|e| e.0).collect();
    (peaks, valleys)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sawtooth chip: thickness 100 µm rising to 140 µm over each 50 µm segment, binned
    /// every 5 µm, with a 2 µm lattice ripple on top.
    fn sawtooth() -> Vec<ProfileBin> {
        (0..80)
            .map(|k| {
                let s = 5e-6 * k as f64;
                let frac = (s / 50e-6).fract();
                let ripple = if k % 2 == 0 { 2e-6 } else { 0.0 };
                bin(s, 100e-6 + 40e-6 * frac + ripple, 5e-6)
            })
            .collect()
    }

    fn bin(along_m: f64, thickness_m: f64, spacing_m: f64) -> ProfileBin {
        ProfileBin {
            along_m,
            thickness_m,
            spacing_m,
        }
    }

    #[test]
    fn a_sawtooth_chip_has_its_pitch_and_degree() {
        let s = serration_of(&sawtooth()).expect("serrated");
        assert!((s.pitch_m - 50e-6).abs() < 1e-9, "{s:?}");
        // peaks ≈ 135 + 2 (last bin before the drop, with the ripple), valleys 100 µm
        assert!((s.degree - (s.peak_m - s.valley_m) / s.peak_m).abs() < 1e-12);
        assert!((0.2..0.3).contains(&s.degree), "{s:?}");
        assert!(s.peaks >= 5);
    }

    #[test]
    fn a_ripple_below_the_resolution_is_no_serration() {
        let flat: Vec<ProfileBin> = (0..80)
            .map(|k| {
                let t = 100e-6 + if k % 3 == 0 { 3e-6 } else { 0.0 };
                bin(5e-6 * k as f64, t, 5e-6)
            })
            .collect();
        assert_eq!(serration_of(&flat), None);
    }

    /// A chip fine (5 µm) near the edge and coarsened (10 µm) beyond: the coarse part's
    /// lattice ripple of 8 µm is more than a fine spacing but less than its own, so it is no
    /// segment; the same ripple taken at the fine spacing would be, and a real 40 µm
    /// sawtooth in the coarse part still is.
    #[test]
    fn a_coarse_lattice_ripple_is_no_serration() {
        let chip = |coarse_spacing: f64, sawtooth: bool| -> Vec<ProfileBin> {
            (0..120)
                .map(|k| {
                    let s = 5e-6 * k as f64;
                    if k < 40 {
                        return bin(s, 100e-6, 5e-6);
                    }
                    let t = if sawtooth {
                        100e-6 + 40e-6 * (s / 50e-6).fract()
                    } else {
                        100e-6 + if (k / 2) % 2 == 0 { 8e-6 } else { 0.0 }
                    };
                    bin(s, t, coarse_spacing)
                })
                .collect()
        };
        assert_eq!(serration_of(&chip(10e-6, false)), None);
        assert!(serration_of(&chip(5e-6, false)).is_some());
        let s = serration_of(&chip(10e-6, true)).expect("serrated");
        assert!((s.pitch_m - 50e-6).abs() < 1e-9, "{s:?}");
    }
}
