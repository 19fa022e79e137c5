//! A cut's steady state as it is reported: every quantity in the units of the cut summary
//! (N/mm, mm, °C) with its 95 % interval and what the interval rests on.

use crate::steady::{SteadyState, SteadyWindow};
use greybox_core::stats::MeanInterval;
use serde::{Deserialize, Serialize};

/// One steady quantity: mean, half-width of its 95 % interval (`None`: too few batches to
/// say), its standard error, and what it rests on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyQuantity {
    pub mean: f64,
    pub ci95: Option<f64>,
    /// Standard error of the mean, s_b/√b (the interval is t(0.975; b − 1) of it).
    pub se: Option<f64>,
    /// The half-width relative to the mean.
    pub rel_ci95: Option<f64>,
    /// Batches of whole units the interval rests on, and the units averaged.
    pub batches: usize,
    pub units: usize,
    /// The change of the batch means across the stretch along their least-squares line,
    /// and the half-width of its 95 % interval ([`greybox_core::stats::Drift`]); a change
    /// larger than its half-width: the quantity was still drifting.
    #[serde(default)]
    pub drift: Option<f64>,
    #[serde(default)]
    pub drift_ci95: Option<f64>,
}

impl SteadyQuantity {
    /// `m` scaled by `scale` and shifted by `offset` (°C from K), in report units.
    fn of(m: &MeanInterval, scale: f64, offset: f64) -> Self {
        SteadyQuantity {
            mean: m.mean * scale + offset,
            ci95: m.half_width.map(|h| h * scale.abs()),
            se: m.standard_error().map(|e| e * scale.abs()),
            rel_ci95: m.relative(),
            batches: m.batches,
            units: m.units,
            drift: m.drift.map(|d| d.change * scale),
            drift_ci95: m.drift.map(|d| d.half_width * scale.abs()),
        }
    }

    /// Whether the quantity drifted significantly across the stretch.
    pub fn drifting(&self) -> bool {
        match (self.drift, self.drift_ci95) {
            (Some(change), Some(half_width)) => {
                greybox_core::stats::Drift { change, half_width }.significant()
            }
            _ => false,
        }
    }
}

/// The steady state of a cut in report units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyReport {
    /// The averaged stretch, mm of cut.
    pub from_mm: f64,
    pub to_mm: f64,
    /// The force signal's period (the chip's segmentation), mm of cut, and the whole periods
    /// averaged; without a period the unit is one force bin.
    pub period_mm: Option<f64>,
    pub periods: Option<usize>,
    /// What the intervals rest on, in words.
    pub rests_on: String,
    pub cutting_force_n_per_mm: SteadyQuantity,
    pub feed_force_n_per_mm: SteadyQuantity,
    pub chip_thickness_mm: Option<SteadyQuantity>,
    pub compression_ratio: Option<SteadyQuantity>,
    /// The chip's extent along the rake-face normal, mm, and over h: its outer size, the
    /// thickness measure until 2026-12-01 ([`crate::chip::chip_extent`]).
    #[serde(default)]
    pub chip_extent_mm: Option<SteadyQuantity>,
    #[serde(default)]
    pub extent_ratio: Option<SteadyQuantity>,
    pub contact_length_mm: Option<SteadyQuantity>,
    pub rake_peak_temperature_c: Option<SteadyQuantity>,
    pub rake_mean_temperature_c: Option<SteadyQuantity>,
    /// Segment pitch along the chip, mm, and degree of segmentation (where the chip is
    /// serrated at most instants of the stretch; `serrated_share` of them it was).
    pub segment_pitch_mm: Option<SteadyQuantity>,
    pub segmentation_degree: Option<SteadyQuantity>,
    pub serrated_share: f64,
    /// The cut length over which the chip renews its contact with the rake face, mm, and
    /// the renewals the stretch spans ([`crate::steady`]).
    pub contact_renewal_mm: Option<f64>,
    pub renewals: Option<f64>,
}

impl SteadyReport {
    /// The report of `s`, a cut at `speed_m_s` with uncut chip thickness `h_m`.
    pub fn of(s: &SteadyState, speed_m_s: f64, h_m: f64) -> Self {
        let mm = |t: f64| t * speed_m_s * 1e3;
        let w: &SteadyWindow = &s.window;
        let q = |m: &Option<MeanInterval>, scale: f64, offset: f64| {
            m.as_ref().map(|m| SteadyQuantity::of(m, scale, offset))
        };
        let kelvin = -273.15;
        SteadyReport {
            from_mm: mm(w.from_s),
            to_mm: mm(w.to_s),
            period_mm: w.period_s.map(mm),
            periods: w.period_s.map(|_| w.units),
            rests_on: rests_on(w, &s.cutting_force, mm(w.unit_s), s.renewals),
            cutting_force_n_per_mm: SteadyQuantity::of(&s.cutting_force, 1e-3, 0.0),
            feed_force_n_per_mm: SteadyQuantity::of(&s.feed_force, 1e-3, 0.0),
            chip_thickness_mm: q(&s.chip_thickness, 1e3, 0.0),
            compression_ratio: q(&s.chip_thickness, 1.0 / h_m, 0.0),
            chip_extent_mm: q(&s.chip_extent, 1e3, 0.0),
            extent_ratio: q(&s.chip_extent, 1.0 / h_m, 0.0),
            contact_length_mm: q(&s.contact_length, 1e3, 0.0),
            rake_peak_temperature_c: q(&s.rake_peak_temperature, 1.0, kelvin),
            rake_mean_temperature_c: q(&s.rake_mean_temperature, 1.0, kelvin),
            segment_pitch_mm: q(&s.segment_pitch, 1e3, 0.0),
            segmentation_degree: q(&s.segmentation_degree, 1.0, 0.0),
            serrated_share: s.serrated_share,
            contact_renewal_mm: s.contact_renewal_m.map(|l| l * 1e3),
            renewals: s.renewals,
        }
    }
}

/// "12 periods of 0.071 mm (the force signal's), 6 batches of 2 for F'c" or "540 force bins
/// of 0.004 mm (no period in the forces), 10 batches of 54 for F'c".
fn rests_on(w: &SteadyWindow, fc: &MeanInterval, unit_mm: f64, renewals: Option<f64>) -> String {
    let span = renewals.map_or(String::new(), |r| format!(", {r:.1} contact renewals"));
    let units = match w.period_s {
        Some(_) => format!(
            "{} periods of {unit_mm:.4} mm (the force signal's)",
            w.units
        ),
        None => format!(
            "{} force bins of {unit_mm:.4} mm (no period in the forces)",
            w.units
        ),
    } + &span;
    match fc.half_width {
        Some(_) => format!("{units}, {} batches of {} for F'c", fc.batches, fc.units_per_batch),
        None => format!(
            "{units}: fewer than {} batches as long as F'c's correlation ({:.1} units), no interval",
            greybox_core::stats::MIN_BATCHES,
            fc.autocorrelation_time
        ),
    }
}
