//! What the issue-58 tests share to run greybox on the generated traces of `support` (which
//! itself never uses greybox_tribo): a trace as a recording, the plan of its truth, one
//! identification call, and the coverage check of a 95 % interval over seeds.
#![allow(dead_code)]

use crate::support::sure::Trace;
use crate::support::PlannedStep;
use greybox_contact::hertz::PinContact;
use greybox_core::units;
use greybox_recording::Recording;
use greybox_tribo::campaign::{identify_recordings, Campaign, ExpectedStep, Identification};
use greybox_tribo::config::IdentifyConfig;

/// A generated trace as a recording (time, normal and friction force; no speed channel).
pub fn recording(t: &Trace) -> Recording {
    Recording::new(
        &t.name,
        t.time_s.clone(),
        t.normal_n.clone(),
        t.tangential_n.clone(),
    )
}

/// The plan of a generated truth (any generator's): its steps in run order, with or without
/// their durations.
pub fn plan_of<T: PlannedStep>(truth: &[T], with_durations: bool) -> Vec<ExpectedStep> {
    truth
        .iter()
        .map(|t| {
            let (pin, step, normal_force_n, velocity_m_per_min, duration_s) = t.planned();
            ExpectedStep {
                pin,
                step,
                normal_force_n,
                sliding_velocity_m_s: units::m_per_min_to_m_per_s(velocity_m_per_min),
                duration_s: duration_s.filter(|_| with_durations),
            }
        })
        .collect()
}

/// Identification of `recs` with the default contact, against `expected` where given.
pub fn identify(
    recs: &[Recording],
    expected: Option<&[ExpectedStep]>,
    cfg: &IdentifyConfig,
) -> Identification {
    identify_on(recs, expected, cfg, &[])
}

/// [`identify`] on tracks of the given radii, mm (one per pin, or one for all).
pub fn identify_on(
    recs: &[Recording],
    expected: Option<&[ExpectedStep]>,
    cfg: &IdentifyConfig,
    radii: &[f64],
) -> Identification {
    let contact = PinContact::default();
    identify_recordings(
        recs,
        &Campaign {
            expected,
            plan: None,
            contact: &contact,
            cfg,
            track_radius_mm: radii,
        },
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// Share of `hits` over `n` (at least 40 intervals), and a check that it lies in 90–99 %.
pub fn coverage(what: &str, hits: usize, n: usize) -> f64 {
    let share = hits as f64 / n as f64;
    eprintln!(
        "{what}: the 95 % interval covers the truth in {hits} of {n} ({:.1} %)",
        100.0 * share
    );
    assert!(n >= 40, "{what}: only {n} intervals");
    assert!(
        (0.90..=0.99).contains(&share),
        "{what}: coverage {share:.3} outside 90–99 %"
    );
    share
}
