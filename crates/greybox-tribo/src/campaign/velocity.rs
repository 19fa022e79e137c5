//! Sliding velocities of segments measured as a spindle speed, from the track radius.

use super::report::{Campaign, FileReport};
use greybox_core::physics::{self, Quantity};
use greybox_core::units;
use greybox_core::{Error, Result, SourcePos};

/// Sliding velocities of segments with a spindle speed: v = 2π R n / 60, R from the radius
/// column, the given radii, or the plan.
pub(super) fn resolve_velocities(files: &mut [FileReport], c: &Campaign) -> Result<()> {
    let total: usize = files
        .iter()
        .map(|f| {
            f.segments
                .iter()
                .filter(|s| s.spindle_rpm.is_some())
                .count()
        })
        .sum();
    let radii = c.track_radius_mm;
    let mut global = 0usize;
    for f in files.iter_mut() {
        let in_file = f
            .segments
            .iter()
            .filter(|s| s.spindle_rpm.is_some())
            .count();
        let mut local = 0usize;
        for s in f.segments.iter_mut() {
            let Some(rpm) = s.spindle_rpm else { continue };
            let r_mm = match radii.len() {
                1 => Some(radii[0]),
                n if n > 1 && n == in_file => Some(radii[local]),
                n if n > 1 && n == total => Some(radii[global]),
                0 => c.plan.and_then(|p| p.spec.track_radius_mm),
                n => {
                    return Err(Error::invalid(
                        "track radius",
                        format!(
                            "{n} track radii given, but {} has {in_file} segments with a spindle speed and the campaign {total}: give one radius, one per segment of each file, or one per segment of the campaign",
                            f.source
                        ),
                    ))
                }
            };
            local += 1;
            global += 1;
            if let Some(r) = r_mm {
                let what = format!("track radius for {} segment {}", f.source, s.index);
                match physics::check(Quantity::TrackRadius, r * units::M_PER_MM, &what) {
                    Err(e) => return Err(Error::invalid("track radius", e)),
                    Ok(Some(flag)) if !f.unusual.contains(&flag.text) => f.unusual.push(flag.text),
                    Ok(_) => {}
                }
            }
            match r_mm {
                Some(r) if r > 0.0 => {
                    s.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(
                        units::velocity_for_rpm(rpm, r * units::M_PER_MM),
                    ))
                }
                _ => {
                    return Err(Error::input(
                        SourcePos::file(&f.source),
                        "the speed channel is a spindle speed (rpm) but no track radius is known: give `track_radii_mm` (one value or one per segment) or map a radius column",
                    ))
                }
            }
        }
    }
    Ok(())
}
