//! The serration of a chip at one instant: its thickness along its length, the segments'
//! peaks and valleys, their pitch and the degree of segmentation.
//!
//! The chip particles in front of the rake face and clear of the primary shear zone (more
//! than h above the uncut surface) are binned along the rake face (bins of twice the finest
//! spacing among them); in each bin the thickness is the extent of the particles' distances
//! from the rake face plus one spacing. A serrated chip's thickness rises and falls along
//! it: a *peak* is a local maximum that stands more than one particle spacing above the
//! valleys on both sides of it (a smaller ripple is the particle lattice, not a segment),
//! and a *valley* the least thickness between two peaks. Then
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
    /// (distance along the rake face from the edge point, m; thickness, m) per bin holding at
    /// least three particles.
    pub profile: Vec<(f64, f64)>,
    /// The finest particle spacing in the chip, m.
    pub fine: f64,
    /// The farthest chip particle along the rake face within one spacing of it, m: the
    /// tool–chip contact length as the chip's particles show it.
    pub contact_length_m: Option<f64>,
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
        .map(|(k, b)| (s0 + (k as f64 + 0.5) * width, b.3 - b.1 + 0.5 * (b.2 + b.4)))
        .collect();
    Some(ChipShape {
        profile,
        fine,
        contact_length_m: contact,
    })
}

/// The serration of a thickness `profile` (distance, thickness; in order along the chip)
/// whose ripples smaller than `resolution` (one particle spacing) are no segments.
pub fn serration_of(profile: &[(f64, f64)], resolution: f64) -> Option<Serration> {
    let (peaks, valleys) = turning_points(profile, resolution);
    if peaks.len() < 2 || valleys.is_empty() {
        return None;
    }
    let mean = |v: &[(f64, f64)]| v.iter().map(|p| p.1).sum::<f64>() / v.len() as f64;
    let (hi, lo) = (mean(&peaks), mean(&valleys));
    let pitch = (peaks[peaks.len() - 1].0 - peaks[0].0) / (peaks.len() - 1) as f64;
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
        serration_of(&self.profile, self.fine)
    }
}

/// The peaks of `profile` that stand more than `resolution` above the valleys on both sides,
/// and the valleys between neighbouring peaks (a zigzag with hysteresis `resolution`).
fn turning_points(profile: &[(f64, f64)], resolution: f64) -> (Vec<(f64, f64)>, Vec<(f64, f64)>) {
    let mut extremes: Vec<((f64, f64), bool)> = Vec::new(); // (point, is a peak)
    let Some(&first) = profile.first() else {
        return (Vec::new(), Vec::new());
    };
    // candidates since the last confirmed extreme
    let (mut hi, mut lo) = (first, first);
    let mut rising: Option<bool> = None;
    for &p in &profile[1..] {
        if p.1 > hi.1 {
            hi = p;
        }
        if p.1 < lo.1 {
            lo = p;
        }
        match rising {
            Some(true) | None if p.1 < hi.1 - resolution => {
                if rising.is_some() || hi.1 - lo.1 > resolution {
                    extremes.push((hi, true));
                }
                rising = Some(false);
                lo = p;
            }
            Some(false) | None if p.1 > lo.1 + resolution => {
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
    let peaks: Vec<(f64, f64)> = inner.iter().filter(|e| e.1).map(|e| e.0).collect();
    let valleys: Vec<(f64, f64)> = inner.iter().filter(|e| !e.1).map(|e| e.0).collect();
    (peaks, valleys)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sawtooth chip: thickness 100 µm rising to 140 µm over each 50 µm segment, binned
    /// every 5 µm, with a 2 µm lattice ripple on top.
    fn sawtooth() -> Vec<(f64, f64)> {
        (0..80)
            .map(|k| {
                let s = 5e-6 * k as f64;
                let frac = (s / 50e-6).fract();
                let ripple = if k % 2 == 0 { 2e-6 } else { 0.0 };
                (s, 100e-6 + 40e-6 * frac + ripple)
            })
            .collect()
    }

    #[test]
    fn a_sawtooth_chip_has_its_pitch_and_degree() {
        let s = serration_of(&sawtooth(), 5e-6).expect("serrated");
        assert!((s.pitch_m - 50e-6).abs() < 1e-9, "{s:?}");
        // peaks ≈ 135 + 2 (last bin before the drop, with the ripple), valleys 100 µm
        assert!((s.degree - (s.peak_m - s.valley_m) / s.peak_m).abs() < 1e-12);
        assert!((0.2..0.3).contains(&s.degree), "{s:?}");
        assert!(s.peaks >= 5);
    }

    #[test]
    fn a_ripple_below_the_resolution_is_no_serration() {
        let flat: Vec<(f64, f64)> = (0..80)
            .map(|k| {
                (
                    5e-6 * k as f64,
                    100e-6 + if k % 3 == 0 { 3e-6 } else { 0.0 },
                )
            })
            .collect();
        assert_eq!(serration_of(&flat, 5e-6), None);
    }
}
