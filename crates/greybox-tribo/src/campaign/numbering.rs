//! Pins and steps numbered from the recordings alone, when there is no plan.

use super::checks::MAX_SLIDING_VELOCITY_M_S;
use super::report::{segment_record, Campaign, FileReport, MatchReport, SegmentReport};
use greybox_core::dataset::{label_evidence, FrictionDataset};
use greybox_core::units;
use greybox_core::{Error, Result, SourcePos};

/// Without a plan: pins and steps numbered from the recordings (a new pin where the load
/// changes by more than 10 % or a new multi-step file starts); speeds must be measured.
pub(super) fn number_without_plan(
    files: &mut [FileReport],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    let mut records = Vec::new();
    let (mut pin, mut step) = (0u32, 0u32);
    let mut prev: Option<(usize, f64)> = None; // file, load
    let mut prev_label: Option<f64> = None; // the recording's own step number (step column, block)
    let mut pending: Vec<(usize, String)> = Vec::new(); // dropped steps whose number is kept
                                                        // a dropped segment keeps its place: the steps after it keep their numbers
    let all: Vec<(usize, usize)> = files
        .iter()
        .enumerate()
        .flat_map(|(f, file)| (0..file.segments.len()).map(move |k| (f, k)))
        .collect();
    for &(f, k) in &all {
        let s = &files[f].segments[k];
        if s.stats.is_none() {
            if s.problem.is_none() || !(s.normal_force_n > 0.0) {
                continue;
            }
            let same_pin = prev
                .is_some_and(|(pf, load)| pf == f && (s.normal_force_n / load - 1.0).abs() <= 0.1);
            if !same_pin {
                pin += 1;
                step = 0;
                // the dropped segments at the end of a pin shift no number: their dropped
                // notes say enough
                pending.clear();
            } else {
                step += labels_skipped(prev_label, s.step_label);
            }
            step += 1;
            prev = Some((f, s.normal_force_n));
            prev_label = s.step_label;
            let note = format!(
                "segment {} ({:.3}–{:.3} s) is pin {pin} step {step} but gave no row ({}): the step is left empty, the steps after it keep their numbers",
                s.index,
                s.start_s,
                s.end_s,
                s.problem.as_deref().unwrap_or_default()
            );
            pending.push((f, note));
            continue;
        }
        let v = measured_velocity(&files[f], s)?;
        let new_pin = prev.is_none_or(|(pf, load)| {
            let load_changed = (s.normal_force_n / load - 1.0).abs() > 0.1;
            load_changed || (pf != f && !(single_step(&files[pf]) && single_step(&files[f])))
        });
        let skipped = if new_pin {
            pin += 1;
            step = 0;
            pending.clear();
            0
        } else {
            labels_skipped(prev_label, s.step_label)
        };
        // a dropped step before this one in the pin: its number stays taken, and says so
        let kept = std::mem::take(&mut pending);
        step += 1 + skipped;
        prev = Some((f, s.normal_force_n));
        prev_label = s.step_label;
        if skipped > 0 {
            let note = labels_jump_note(pin, step, skipped, prev_label.unwrap_or_default());
            files[f].warnings.push(note);
        }
        for (pf, note) in kept {
            files[pf].warnings.push(note);
        }
        let s = &mut files[f].segments[k];
        s.matched = Some((pin, step));
        // without a plan a step is its place in the recording: numbered by its step column
        // or blocks, else by order (nothing to be placed on wrongly: no flag)
        s.label_evidence = Some(
            if s.boundaries == super::span::Cut::StepColumn.name() {
                label_evidence::STEP_COLUMN
            } else {
                label_evidence::ORDER
            }
            .to_string(),
        );
        let s = &files[f].segments[k];
        records.push(segment_record(
            c,
            (pin, step),
            None,
            units::m_per_min_to_m_per_s(v),
            s,
        )?);
    }
    let report = MatchReport {
        method: "none".into(),
        ..Default::default()
    };
    Ok((FrictionDataset { records }, report))
}

/// A measured segment's sliding velocity, m/min: refused beyond any tribometer or cut (a
/// unit mistake) or when the recording has none (no plan to take it from).
fn measured_velocity(file: &FileReport, s: &SegmentReport) -> Result<f64> {
    if let Some(v) = s
        .sliding_velocity_m_per_min
        .filter(|v| !(v.abs() <= units::m_per_s_to_m_per_min(MAX_SLIDING_VELOCITY_M_S)))
    {
        return Err(Error::input(
            SourcePos::file(&file.source).field("speed"),
            format!(
                "segment {} ({:.3}–{:.3} s): a sliding velocity of {v:.4e} m/min is beyond any tribometer or cut (at most {:.0} m/min): is the speed channel's unit right (rpm against m/s, mm/s against m/s)?",
                s.index,
                s.start_s,
                s.end_s,
                units::m_per_s_to_m_per_min(MAX_SLIDING_VELOCITY_M_S)
            ),
        ));
    }
    s.sliding_velocity_m_per_min.ok_or_else(|| {
        Error::input(
            SourcePos::file(&file.source),
            "without a plan the sliding velocity must come from the recording: map a speed channel (`map` speed=NAME:UNIT, with `track_radii_mm` for rpm), state a constant one (`constant_sliding_velocity_m_per_s`) or give a plan (`study` or `plan_steps`)",
        )
    })
}

/// Whether a file gave exactly one measured segment (files of one step each continue a pin).
fn single_step(file: &FileReport) -> bool {
    file.segments.iter().filter(|s| s.stats.is_some()).count() == 1
}

/// The warning for steps the recording's own numbering skips: `skipped` steps before `step`
/// of `pin`, the recording's label now `label`.
fn labels_jump_note(pin: u32, step: u32, skipped: u32, label: f64) -> String {
    format!(
        "the recording's steps jump from {} to {}: pin {pin} steps {}–{} have no segment and are left empty, the steps after them keep their numbers",
        label - skipped as f64 - 1.0,
        label,
        step - skipped,
        step - 1
    )
}

/// Steps the recording's own numbering (a step column, blocks) skips between two segments of
/// one pin: `prev` 2 and `label` 4 skip one. Only whole, increasing numbers count.
pub(super) fn labels_skipped(prev: Option<f64>, label: Option<f64>) -> u32 {
    match (prev, label) {
        (Some(a), Some(b))
            if a.fract() == 0.0 && b.fract() == 0.0 && b > a + 1.0 && b - a < 1e4 =>
        {
            (b - a - 1.0) as u32
        }
        _ => 0,
    }
}
