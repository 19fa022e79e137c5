//! Matching segments with the plan's steps (or numbering them without a plan) into the dataset,
//! with a report of the missing, extra, merged and reordered steps.

use super::checks::{check_levels, check_physics};
use super::numbering::number_without_plan;
use super::report::{
    flag_low_coverage_after_matching, segment_record, update_coverage, Campaign, FileReport,
    MatchReport,
};
use super::span::Cut;
use crate::align::{Assigned, Candidate};
use crate::config::Segmentation;
use crate::expected::ExpectedStep;
use crate::sliding::SlidingEvidence;
use greybox_core::dataset::{flags, FrictionDataset};
use greybox_core::units;
use greybox_core::{Error, Result};

/// Match segments to the plan (or number them without one) and build the dataset.
pub fn match_segments(
    files: &mut [FileReport],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    let (ds, report) = match_segments_unchecked(files, c)?;
    check_levels(&ds, files)?;
    check_physics(&ds, files)?;
    Ok((ds, report))
}

pub(super) fn match_segments_unchecked(
    files: &mut [FileReport],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    if files
        .iter()
        .all(|f| f.segmentation == Segmentation::PlanTiming.name())
    {
        let records = files
            .iter_mut()
            .flat_map(|f| std::mem::take(&mut f.rows))
            .collect();
        return Ok((
            FrictionDataset { records },
            MatchReport {
                method: "plan timing".into(),
                ..Default::default()
            },
        ));
    }
    let segs = measured_segments(files);
    match c.expected {
        None => number_without_plan(files, c),
        Some(expected) => match_to_plan(files, &segs, expected, c),
    }
}

/// Every measured segment as (file, segment) indices, in campaign order.
pub(super) fn measured_segments(files: &[FileReport]) -> Vec<(usize, usize)> {
    files
        .iter()
        .enumerate()
        .flat_map(|(f, file)| {
            file.segments
                .iter()
                .enumerate()
                .filter(|(_, s)| s.stats.is_some())
                .map(move |(k, _)| (f, k))
        })
        .collect()
}

/// "pin P step S (F N, v m/min)" for reports.
pub(super) fn describe_step(e: &ExpectedStep) -> String {
    format!(
        "pin {} step {} ({:.1} N, {:.1} m/min)",
        e.pin,
        e.step,
        e.normal_force_n,
        units::m_per_s_to_m_per_min(e.sliding_velocity_m_s)
    )
}

/// With a plan: segments aligned with the planned steps ([`crate::align`]), then rows for
/// the matched ones and a report of the missing, extra, merged and reordered steps.
pub(super) fn match_to_plan(
    files: &mut [FileReport],
    segs: &[(usize, usize)],
    expected: &[ExpectedStep],
    c: &Campaign,
) -> Result<(FrictionDataset, MatchReport)> {
    let candidates = candidates(files, segs);
    let aligned = crate::align::align(&candidates, expected, c.cfg)
        .map_err(|m| Error::invalid("identify", m))?;
    let mut report = MatchReport {
        method: alignment_method(&candidates, expected),
        ..Default::default()
    };
    if let Some(line) = file_order_note(files, segs, &aligned.file_order) {
        report.reordered.push(line);
    }
    let mut records = Vec::new();
    let mut matched = vec![false; expected.len()];
    let mut last_ei: Option<usize> = None;
    for (si, &(f, k)) in segs.iter().enumerate() {
        let ei = match aligned.assigned[si] {
            Assigned::Step(ei) => ei,
            Assigned::Merged { earlier, later } => {
                matched[earlier] = true;
                let s = &files[f].segments[k];
                report.merged.push(format!(
                    "{} merged with the next step into {} segment {} ({:.3}–{:.3} s): the row is the later step's",
                    describe_step(&expected[earlier]),
                    files[f].source,
                    s.index,
                    s.start_s,
                    s.end_s
                ));
                later
            }
            Assigned::Extra => {
                let (file, s) = (&files[f], &files[f].segments[k]);
                let v = s
                    .sliding_velocity_m_per_min
                    .map_or(String::new(), |v| format!(", {v:.1} m/min"));
                report.extra.push(format!(
                    "{} segment {} ({:.3}–{:.3} s, {:.1} s) at {:.1} N{v}: no planned step fits (an unplanned run-in or repeat?)",
                    file.source,
                    s.index,
                    s.start_s,
                    s.end_s,
                    s.end_s - s.start_s,
                    s.normal_force_n
                ));
                continue;
            }
        };
        matched[ei] = true;
        let e = &expected[ei];
        label_with_evidence(
            &mut files[f].segments[k],
            &candidates[si],
            ei,
            aligned.ambiguous[si],
            (expected, c),
            &mut report,
        );
        if let Some(prev) = last_ei.filter(|p| ei < *p) {
            report.reordered.push(format!(
                "{} recorded after {}",
                describe_step(e),
                describe_step(&expected[prev])
            ));
        }
        last_ei = Some(last_ei.map_or(ei, |p| p.max(ei)));
        files[f].segments[k].matched = Some((e.pin, e.step));
        let s = &files[f].segments[k];
        records.push(segment_record(
            c,
            (e.pin, e.step),
            Some(e.normal_force_n),
            e.sliding_velocity_m_s,
            s,
        )?);
    }
    for (ei, e) in expected.iter().enumerate() {
        if !matched[ei] {
            report.missing.push(describe_step(e));
        }
    }
    for f in files.iter_mut() {
        update_coverage(f, c.cfg, false);
    }
    flag_low_coverage_after_matching(files, &mut records, c.cfg);
    records.sort_by_key(|r| (r.pin, r.step));
    Ok((FrictionDataset { records }, report))
}

/// State what placed segment `s` (the alignment's `cand`) on planned step `ei`: its
/// evidence ([`crate::align::evidence`]), the flag `label-by-order` where that is the order
/// alone (another planned step would have fitted the segment as well), `ambiguous-alignment`
/// where another alignment nearly as good places it elsewhere; both counted in the report.
fn label_with_evidence(
    s: &mut super::report::SegmentReport,
    cand: &Candidate,
    ei: usize,
    ambiguous: bool,
    (expected, c): (&[ExpectedStep], &Campaign),
    report: &mut MatchReport,
) {
    let ev = crate::align::evidence(cand, ei, expected, c.cfg);
    s.label_evidence = Some(ev.to_string());
    if ev == greybox_core::dataset::label_evidence::ORDER {
        s.flags.push(flags::LABEL_BY_ORDER.to_string());
        report.labels_by_order += 1;
    }
    if ambiguous {
        s.flags.push(flags::AMBIGUOUS_ALIGNMENT.to_string());
        report.ambiguous.push(format!(
            "segment {} ({:.3}–{:.3} s) as {}: another alignment nearly as good places it elsewhere",
            s.index,
            s.start_s,
            s.end_s,
            describe_step(&expected[ei])
        ));
    }
}

/// The alignment's view of each measured segment (`segs`: file and segment indices).
fn candidates(files: &[FileReport], segs: &[(usize, usize)]) -> Vec<Candidate> {
    segs.iter()
        .enumerate()
        .map(|(si, &(f, k))| {
            let s = &files[f].segments[k];
            Candidate {
                file: f,
                load_n: s.normal_force_n,
                // a stated constant speed is no evidence of which step a segment is
                velocity_m_s: s
                    .sliding_velocity_m_per_min
                    .filter(|_| files[f].sliding == SlidingEvidence::SpeedChannel.name())
                    .map(units::m_per_min_to_m_per_s),
                duration_s: s.end_s - s.start_s,
                first_in_file: si == 0 || segs[si - 1].0 != f,
                running_in: s.run_in_s.is_some_and(|r| r > 0.0)
                    || s.flags.iter().any(|x| x == flags::TREND),
                step_column: s.boundaries == Cut::StepColumn.name(),
                plan_timed: s.boundaries == Cut::PlanTiming.name(),
            }
        })
        .collect()
}

/// A line for the report when the alignment took the files in another order than given.
fn file_order_note(
    files: &[FileReport],
    segs: &[(usize, usize)],
    file_order: &[usize],
) -> Option<String> {
    let given: Vec<usize> = {
        let mut v: Vec<usize> = segs.iter().map(|s| s.0).collect();
        v.dedup();
        v
    };
    (file_order != given).then(|| {
        format!(
            "the files were aligned with the plan in the order {}",
            file_order
                .iter()
                .map(|f| files[*f].source.clone())
                .collect::<Vec<_>>()
                .join(", ")
        )
    })
}

/// `alignment by load, speed and duration`: the evidence the segments and the plan share.
pub(super) fn alignment_method(segs: &[Candidate], expected: &[ExpectedStep]) -> String {
    let mut by = vec!["load"];
    if !segs.is_empty() && segs.iter().all(|s| s.velocity_m_s.is_some()) {
        by.push("speed");
    }
    if expected.iter().all(|e| e.duration_s.is_some()) {
        by.push("duration");
    }
    let last = by.pop().expect("load");
    if by.is_empty() {
        format!("alignment by {last}")
    } else {
        format!("alignment by {} and {last}", by.join(", "))
    }
}
