//! An export grid against the law's validity domain: how many of the table's points the law
//! was fitted or calibrated on, and — when none are — the likely unit slip. A grid given in Pa
//! where MPa was meant (Python's SI arguments invite it) is physically possible, so the physics
//! table lets it through; only the law's own domain can tell that every value written is an
//! extrapolation.

use super::Grid;
use greybox_core::law::{Range, ValidityDomain};
use greybox_core::FrictionLaw;
use serde::Serialize;

/// The grid's points against the law's domain (reported with every export of a law that has
/// one).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GridAgainstDomain {
    /// The law's validity domain, SI (pressure Pa, velocity m/s, temperature K).
    pub domain: ValidityDomain,
    /// Grid points (pressure × velocity × temperature).
    pub grid_points: usize,
    /// Of them, those outside the domain (their μ is the law's extrapolation).
    pub points_outside: usize,
}

/// The values of `axis` inside `range`; every value when the law has no range on it.
fn inside(axis: &[f64], range: Option<&Range>) -> usize {
    range.map_or(axis.len(), |r| {
        axis.iter().filter(|x| r.contains(**x)).count()
    })
}

/// The factor by which an axis given in another unit lands inside the domain, in words: a
/// grid in Pa where MPa was meant sits 10⁶ below the domain.
fn slip(axis: &[f64], range: &Range, what: &str, slips: &[(f64, &str)]) -> Option<String> {
    slips.iter().find_map(|(factor, words)| {
        axis.iter().any(|x| range.contains(x * factor)).then(|| {
            format!("the {what} grid meets the domain when multiplied by {factor} ({words}?)")
        })
    })
}

/// The grid against `law`'s domain; `None` for a law without one (a classical law). Says a
/// note (a `warning:` line on the command line, a `greybox.UnusualValueWarning` in Python)
/// when points lie outside: all of them, with the likely unit slip per axis, or their share.
pub fn check_grid(law: &dyn FrictionLaw, grid: &Grid) -> Option<GridAgainstDomain> {
    let domain = law.domain()?;
    let temperatures = grid.temperature_k.as_deref().unwrap_or(&[]);
    let inside_p = inside(&grid.pressure_pa, Some(&domain.pressure_pa));
    let inside_v = inside(&grid.velocity_m_s, Some(&domain.sliding_velocity_m_s));
    let inside_t = match &grid.temperature_k {
        Some(t) => inside(t, domain.temperature_k.as_ref()),
        None => 1,
    };
    let grid_points = grid.pressure_pa.len() * grid.velocity_m_s.len() * temperatures.len().max(1);
    let points_outside = grid_points - inside_p * inside_v * inside_t;
    let check = GridAgainstDomain {
        domain,
        grid_points,
        points_outside,
    };
    if points_outside == grid_points {
        let mut slips = Vec::new();
        if inside_p == 0 {
            slips.extend(slip(
                &grid.pressure_pa,
                &domain.pressure_pa,
                "pressure",
                &[
                    (1e6, "MPa numbers given where Pa are asked"),
                    (
                        1e3,
                        "GPa numbers given where MPa are asked, or kPa where Pa",
                    ),
                    (
                        1e-3,
                        "kPa numbers given where MPa are asked, or Pa where kPa",
                    ),
                    (1e-6, "Pa numbers given where MPa are asked"),
                ],
            ));
        }
        if inside_v == 0 {
            slips.extend(slip(
                &grid.velocity_m_s,
                &domain.sliding_velocity_m_s,
                "velocity",
                &[
                    (1.0 / 60.0, "m/min numbers given where m/s are asked"),
                    (60.0, "m/s numbers given where m/min are asked"),
                    (1e-3, "mm/s numbers given where m/s are asked"),
                ],
            ));
        }
        greybox_core::notes::note(format!(
            "export grid: all {grid_points} points lie outside the law's validity domain ({}): every value written is the law's extrapolation{}",
            describe(&domain),
            if slips.is_empty() {
                String::new()
            } else {
                format!("; {}", slips.join("; "))
            }
        ));
    } else if points_outside > 0 {
        greybox_core::notes::note(format!(
            "export grid: {points_outside} of {grid_points} points ({:.0} %) lie outside the law's validity domain ({}): their values are the law's extrapolation",
            100.0 * points_outside as f64 / grid_points as f64,
            describe(&domain)
        ));
    }
    Some(check)
}

/// The domain in the units a user reads: MPa, m/min, K.
fn describe(d: &ValidityDomain) -> String {
    let mut s = format!(
        "pressure {:.4}–{:.4} MPa, velocity {:.4}–{:.4} m/min",
        d.pressure_pa.min / 1e6,
        d.pressure_pa.max / 1e6,
        d.sliding_velocity_m_s.min * 60.0,
        d.sliding_velocity_m_s.max * 60.0
    );
    if let Some(t) = d.temperature_k {
        s.push_str(&format!(", temperature {:.1}–{:.1} K", t.min, t.max));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classical::Coulomb;
    use greybox_core::ContactState;

    /// A law with a domain of 200–1500 MPa and 1–5 m/s (μ constant).
    struct Fitted;
    impl FrictionLaw for Fitted {
        fn name(&self) -> String {
            "fitted".into()
        }
        fn mu(&self, _: &ContactState) -> f64 {
            0.3
        }
        fn domain(&self) -> Option<ValidityDomain> {
            Some(ValidityDomain {
                pressure_pa: Range {
                    min: 200e6,
                    max: 1500e6,
                },
                sliding_velocity_m_s: Range { min: 1.0, max: 5.0 },
                temperature_k: None,
            })
        }
    }

    fn grid(p: &[f64], v: &[f64]) -> Grid {
        Grid {
            pressure_pa: p.to_vec(),
            velocity_m_s: v.to_vec(),
            temperature_k: None,
        }
    }

    #[test]
    fn a_grid_outside_the_domain_is_counted_and_its_slip_named() {
        let ((), notes) = greybox_core::notes::collected(|| {
            // MPa numbers given as Pa, m/min numbers given as m/s
            let c = check_grid(&Fitted, &grid(&[500.0, 1000.0], &[60.0, 120.0, 240.0])).unwrap();
            assert_eq!((c.grid_points, c.points_outside), (6, 6));
            let c = check_grid(&Fitted, &grid(&[500e6, 2000e6], &[2.0, 4.0])).unwrap();
            assert_eq!((c.grid_points, c.points_outside), (4, 2));
            let c = check_grid(&Fitted, &grid(&[500e6, 1000e6], &[2.0, 4.0])).unwrap();
            assert_eq!(c.points_outside, 0);
        });
        assert_eq!(notes.len(), 2, "{notes:?}");
        assert!(
            notes[0].contains("all 6 points")
                && notes[0].contains("multiplied by 1000000 (MPa numbers given where Pa")
                && notes[0].contains("m/min numbers given where m/s"),
            "{}",
            notes[0]
        );
        assert!(notes[1].contains("2 of 4 points (50 %)"), "{}", notes[1]);
        assert!(check_grid(&Coulomb { mu: 0.3 }, &grid(&[1.0], &[1.0])).is_none());
    }
}
