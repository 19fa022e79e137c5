//! Plausibility checks of an identified campaign: μ, load, speed and pressure against the physics
//! table, and each pin's μ level against the others'.

use super::report::FileReport;
use greybox_core::dataset::FrictionDataset;
use greybox_core::physics::{self, Quantity};
use greybox_core::{Error, Result, SourcePos};

/// How far (as a factor) one pin's median μ may lie from the other pins' before its channels
/// are called implausible: friction coefficients of one campaign stay within a factor of a few
/// of each other, a channel read in the wrong unit (kN as N, mN as N) moves them by 1000.
pub const IMPLAUSIBLE_LEVEL_FACTOR: f64 = 20.0;

/// The fastest sliding a measured speed may give a row, m/s: the hard end of
/// [`Quantity::SlidingVelocity`] (12 000 m/min: above the cutting speeds of high-speed
/// machining and any pin-on-disc rig); a faster one is a unit mistake and is refused.
pub const MAX_SLIDING_VELOCITY_M_S: f64 = Quantity::SlidingVelocity.spec().hard.1;

/// Refuse a campaign whose median μ lies outside the possible range of
/// [`Quantity::CampaignMu`], with the numbers and the likely unit slip.
pub(super) fn check_campaign_level(
    median_mu: f64,
    rows: usize,
    files: &[FileReport],
) -> Result<()> {
    let what = format!("{rows} steps");
    let Err(e) = physics::check(Quantity::CampaignMu, median_mu, &what) else {
        return Ok(());
    };
    let hint = if median_mu < *Quantity::CampaignMu.hard().start() {
        "state the unit of the tangential channel: `map` tangential=NAME:kN"
    } else {
        "state the unit of the normal channel: `map` normal=NAME:kN"
    };
    let sources: Vec<&str> = files.iter().map(|f| f.source.as_str()).take(3).collect();
    Err(Error::input(
        SourcePos::file(sources.join(", ")).field("tangential / normal"),
        format!("{e}; {hint}"),
    ))
}

/// The file that holds (pin, step), for messages.
pub(super) fn source_of(files: &[FileReport], pin: u32, step: Option<u32>) -> Option<usize> {
    files.iter().position(|f| {
        f.segments.iter().any(|s| {
            s.matched
                .is_some_and(|(p, k)| p == pin && step.is_none_or(|st| st == k))
        }) || f
            .rows
            .iter()
            .any(|r| r.pin == pin && step.is_none_or(|st| st == r.step))
    })
}

/// Check every step's μ, load, sliding velocity and pressure against the physics table
/// ([`greybox_core::physics`]): outside the possible range refused, outside the usual range
/// flagged in the file's [`FileReport::unusual`] (one line per quantity and file: the first
/// step's number and hint, and how many more steps).
pub fn check_physics(ds: &FrictionDataset, files: &mut [FileReport]) -> Result<()> {
    // (file, quantity) → first flag and how many
    let mut flagged: Vec<(Option<usize>, Quantity, String, usize)> = Vec::new();
    for r in &ds.records {
        let file = source_of(files, r.pin, Some(r.step));
        let at = format!("pin {} step {}", r.pin, r.step);
        let mut values = vec![
            (Quantity::Mu, r.cof_apparent.abs(), "tangential / normal"),
            (Quantity::NormalForce, r.normal_force_n.abs(), "normal"),
            (
                Quantity::SlidingVelocity,
                r.sliding_velocity_m_s.abs(),
                "speed",
            ),
        ];
        if r.hertz_pressure_pa != 0.0 {
            values.push((Quantity::ContactPressure, r.hertz_pressure_pa, "pressure"));
        }
        for (q, v, field) in values {
            match physics::check(q, v, &at) {
                Ok(None) => {}
                Ok(Some(flag)) => match flagged.iter_mut().find(|e| e.0 == file && e.1 == q) {
                    Some(e) => e.3 += 1,
                    None => flagged.push((file, q, flag.text, 0)),
                },
                Err(e) => {
                    let source = file.map_or_else(|| at.clone(), |f| files[f].source.clone());
                    return Err(Error::input(SourcePos::file(source).field(field), e));
                }
            }
        }
    }
    for (file, _, text, more) in flagged {
        let line = match more {
            0 => text,
            1 => format!("{text} (and 1 more step)"),
            _ => format!("{text} (and {more} more steps)"),
        };
        match file {
            Some(f) => files[f].unusual.push(line),
            None => {
                if let Some(f) = files.first_mut() {
                    f.unusual.push(line)
                }
            }
        }
    }
    Ok(())
}

/// Refuse a pin whose μ level is implausible against its neighbours (at least three pins):
/// its median μ more than [`IMPLAUSIBLE_LEVEL_FACTOR`] from the median of the other pins'.
///
/// Before that, the campaign as a whole: its median μ must lie in the possible range of
/// [`Quantity::CampaignMu`] (a channel
/// in the wrong unit in every pin moves all of them together, where no pin stands out).
pub fn check_levels(ds: &FrictionDataset, files: &[FileReport]) -> Result<()> {
    let median_of = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    if ds.records.is_empty() {
        return Ok(());
    }
    check_campaign_level(
        median_of(ds.records.iter().map(|r| r.cof_apparent.abs()).collect()),
        ds.records.len(),
        files,
    )?;
    let mut pins: Vec<u32> = ds.records.iter().map(|r| r.pin).collect();
    pins.sort_unstable();
    pins.dedup();
    if pins.len() < 3 {
        return Ok(());
    }
    let levels: Vec<(u32, f64)> = pins
        .iter()
        .map(|&p| {
            (
                p,
                median_of(
                    ds.records
                        .iter()
                        .filter(|r| r.pin == p)
                        .map(|r| r.cof_apparent.abs())
                        .collect(),
                ),
            )
        })
        .collect();
    for &(pin, level) in &levels {
        let others = median_of(
            levels
                .iter()
                .filter(|(p, _)| *p != pin)
                .map(|(_, l)| *l)
                .collect(),
        );
        let factor = level.max(1e-12) / others.max(1e-12);
        if !(1.0 / IMPLAUSIBLE_LEVEL_FACTOR..=IMPLAUSIBLE_LEVEL_FACTOR).contains(&factor) {
            let source = files
                .iter()
                .find(|f| {
                    f.segments
                        .iter()
                        .any(|s| s.matched.is_some_and(|(p, _)| p == pin))
                        || f.rows.iter().any(|r| r.pin == pin)
                })
                .map_or_else(|| format!("pin {pin}"), |f| f.source.clone());
            let hint = if factor < 1.0 {
                "is the tangential channel in kN (or the normal one in mN) read as N? state its unit: `map` tangential=NAME:kN"
            } else {
                "is the normal channel in kN (or the tangential one in mN) read as N? state its unit: `map` normal=NAME:kN"
            };
            return Err(Error::input(
                SourcePos::file(source).field("tangential / normal"),
                format!(
                    "pin {pin}'s median μ {level:.4} is {:.0}× {} the other pins' {others:.4}: {hint}",
                    if factor < 1.0 { 1.0 / factor } else { factor },
                    if factor < 1.0 { "below" } else { "above" }
                ),
            ));
        }
    }
    Ok(())
}
