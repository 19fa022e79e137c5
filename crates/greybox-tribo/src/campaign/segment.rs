//! Segmenting every recording: the segmentation each file gets, its spans split at gaps, the short
//! pieces dropped, and each kept segment measured.

use super::change_points::split_run;
use super::measure::{measure, steady_notes};
use super::passes::{pair_passes, trim_ends};
use super::plan_timed::plan_timed;
use super::prepare::{prepare, Prepared};
use super::reciprocating_segments::{reciprocating_reason, reciprocating_segments};
use super::report::{update_coverage, Campaign, FileReport, SegmentReport};
use super::span::Span;
use super::spans::{sliding_runs, spans_from_speed, spans_from_steps};
use super::velocity::resolve_velocities;
use crate::config::IdentifyConfig;
use crate::config::Segmentation;
use crate::coverage::Dropped;
use crate::expected::ExpectedStep;
use crate::plan::Plan;
use greybox_core::{Error, Result, SourcePos};
use greybox_recording::Recording;
use greybox_recording::TestMode;

/// Which segmentation a file gets under `Auto`.
pub(super) fn resolve(method: Segmentation, rec: &Recording, plan: Option<&Plan>) -> Segmentation {
    match method {
        Segmentation::Auto if rec.step.is_some() => Segmentation::StepColumn,
        Segmentation::Auto if rec.speed.is_some() => Segmentation::Speed,
        Segmentation::Auto if plan.is_some() && rec.trigger_v.is_some() => Segmentation::PlanTiming,
        Segmentation::Auto => Segmentation::Signals,
        m => m,
    }
}

/// Segment every recording and measure every segment (no plan matching yet). The plan-timed
/// path also fills the matched pin and step.
pub fn segment_recordings(recs: &[Recording], c: &Campaign) -> Result<Vec<FileReport>> {
    let cfg = c.cfg;
    let recip: Vec<Option<String>> = recs.iter().map(|r| reciprocating_reason(r, cfg)).collect();
    let methods: Vec<Segmentation> = recs
        .iter()
        .zip(&recip)
        .map(|(r, why)| match why {
            Some(_) => Segmentation::Signals,
            None => resolve(cfg.segmentation, r, c.plan),
        })
        .collect();
    if methods.contains(&Segmentation::PlanTiming) {
        return plan_timed_all(recs, &methods, c);
    }
    check_evidence(recs, &methods)?;
    let mut prepared: Vec<Prepared> = recs
        .iter()
        .zip(&methods)
        .zip(&recip)
        .map(|((r, m), why)| prepare(r, cfg, m.name(), why.is_some()))
        .collect::<Result<_>>()?;
    let spans = file_spans(&mut prepared, &methods, &recip, c)?;
    for ((p, s), why) in prepared.iter_mut().zip(&spans).zip(&recip) {
        match why {
            Some(why) => reciprocating_segments(p, why, cfg),
            None => measure_file(p, s, cfg),
        }
    }
    let mut files: Vec<FileReport> = prepared.into_iter().map(|p| p.report).collect();
    resolve_velocities(&mut files, c)?;
    steady_notes(&mut files);
    for f in files.iter_mut() {
        update_coverage(f, cfg, true);
    }
    Ok(files)
}

/// The plan-timing path, when every recording takes it (one that does not is an error).
fn plan_timed_all(
    recs: &[Recording],
    methods: &[Segmentation],
    c: &Campaign,
) -> Result<Vec<FileReport>> {
    if methods.iter().any(|m| *m != Segmentation::PlanTiming) {
        return Err(Error::invalid(
            "identify",
            "some recordings have a trigger for the plan's timing and others do not: choose one segmentation for all with `segment`",
        ));
    }
    let plan = c.plan.ok_or_else(|| {
        Error::invalid(
            "identify",
            "`segment` plan-timing needs a plan with timing (`study`)",
        )
    })?;
    plan_timed(recs, plan, c)
}

/// Refuse a segmentation whose evidence a recording lacks (a step column, a speed channel).
fn check_evidence(recs: &[Recording], methods: &[Segmentation]) -> Result<()> {
    for (rec, m) in recs.iter().zip(methods) {
        let missing = match m {
            Segmentation::StepColumn if rec.step.is_none() => {
                Some("a step column (`map` step=NAME)")
            }
            Segmentation::Speed if rec.speed.is_none() => {
                Some("a speed channel (`map` speed=NAME:UNIT)")
            }
            _ => None,
        };
        if let Some(what) = missing {
            return Err(Error::input(
                SourcePos::file(&rec.source),
                format!("`segment` {} needs {what}, and none was found", m.name()),
            ));
        }
    }
    Ok(())
}

/// Each file's spans: from its step column or speed channel, or its sliding runs split at
/// μ's level changes (into the plan's steps when the run count says which pin each is). A
/// reciprocating file (`recip`) gets none here.
fn file_spans(
    prepared: &mut [Prepared],
    methods: &[Segmentation],
    recip: &[Option<String>],
    c: &Campaign,
) -> Result<Vec<Vec<Span>>> {
    let cfg = c.cfg;
    let mut spans: Vec<Vec<Span>> = Vec::with_capacity(prepared.len());
    let mut signal_runs: Vec<(usize, Span)> = Vec::new();
    for (f, (p, m)) in prepared.iter().zip(methods).enumerate() {
        if recip[f].is_some() {
            spans.push(Vec::new());
            continue;
        }
        match m {
            Segmentation::StepColumn => {
                spans.push(spans_from_steps(p, p.rec.step.as_deref().expect("checked")))
            }
            Segmentation::Speed => spans.push(spans_from_speed(
                p,
                p.rec.speed.as_ref().expect("checked").values(),
                cfg,
                c.expected,
            )),
            _ => {
                spans.push(Vec::new());
                // a reversal ends a run: each pass is split on its own
                let runs = p.passes.split(&sliding_runs(p));
                signal_runs.extend(runs.into_iter().map(|s| (f, s)));
            }
        }
    }
    // signal runs: split into the plan's steps when the run count says which pin each is
    if !signal_runs.is_empty() {
        // pieces shorter than any step (noise over a load ramp) hold no planned step and do
        // not count as runs: they are dropped, with their reason, when measured
        let long: Vec<bool> = signal_runs
            .iter()
            .map(|(f, s)| {
                let p = &prepared[*f];
                (s.j - s.i) as f64 / p.fs >= p.min_step_s(cfg)
            })
            .collect();
        let mut long_steps =
            plan_steps_per_run(c.expected, long.iter().filter(|l| **l).count()).into_iter();
        let per_run: Vec<Option<&[ExpectedStep]>> = long
            .iter()
            .map(|l| {
                if *l {
                    long_steps.next().flatten()
                } else {
                    None
                }
            })
            .collect();
        if c.expected.is_some() && per_run.iter().all(Option::is_none) {
            let pins = c.expected.map_or(0, |e| pin_groups(e).len());
            for p in prepared.iter_mut() {
                p.report.notes.push(format!(
                    "{} loaded sliding runs in all files, the plan has {pins} pins and {} steps: runs split by the signal alone, then aligned with the plan",
                    long.iter().filter(|l| **l).count(),
                    c.expected.map_or(0, <[ExpectedStep]>::len)
                ));
            }
        }
        for ((f, run), steps) in signal_runs.iter().zip(per_run) {
            let parts = split_run(&prepared[*f], *run, steps, cfg)?;
            spans[*f].extend(parts);
        }
    }
    Ok(spans)
}

/// Measure a file's spans: split at gaps in time, the pieces shorter than a step dropped
/// (with reasons), each kept one measured; a note when none is left, a warning when a named
/// test mode is contradicted.
fn measure_file(p: &mut Prepared, spans: &[Span], cfg: &IdentifyConfig) {
    let min_len = (cfg.min_segment_s * p.fs) as usize;
    let at_gaps = split_at_gaps(p, spans);
    let s: Vec<Span> = p
        .passes
        .split(&at_gaps)
        .into_iter()
        .map(|sp| trim_ends(p, sp))
        .collect();
    let (kept, short): (Vec<Span>, Vec<Span>) = s.iter().partition(|s| s.j - s.i >= min_len.max(4));
    p.report.too_short = too_short(p, &short, cfg);
    let segs: Vec<SegmentReport> = kept
        .iter()
        .enumerate()
        .map(|(k, sp)| measure(p, *sp, k + 1, cfg))
        .collect();
    let pass_of: Vec<u32> = kept.iter().map(|s| s.pass).collect();
    p.report.segments = pair_passes(segs, &pass_of, cfg, &mut p.report.notes);
    if p.report.segments.is_empty() {
        let hint = no_segment_hint(p);
        p.report.notes.push(format!("no segment found: {hint}"));
    }
    if let Some(w) = forced_mode_contradicted(p, cfg) {
        p.report.warnings.push(w);
    }
}

/// Why a file gave no row under a test mode the user named (`--test-mode continuous` or
/// `stepped`) that its signals contradict: the separate sliding runs it holds, and whether its
/// friction force changes sign like a reciprocating test's. `None` when a row came out or the
/// mode was not named.
pub(super) fn forced_mode_contradicted(p: &Prepared, cfg: &IdentifyConfig) -> Option<String> {
    let mode = cfg.mode.filter(|m| *m != TestMode::Reciprocating)?;
    if p.report.segments.iter().any(|s| s.stats.is_some()) {
        return None;
    }
    let runs = p
        .sliding
        .iter()
        .zip(std::iter::once(&false).chain(&p.sliding))
        .filter(|(now, before)| **now && !**before)
        .count();
    let profile = p.rec.provenance.as_ref().and_then(|r| r.test_mode);
    let recip = crate::reciprocating::detect(
        &crate::reciprocating::Signals::of(p.rec),
        None,
        profile,
        cfg,
    );
    Some(format!(
        "`test_mode` {} was named, but the recording has {runs} separate sliding run(s) and none gave a steady window{}",
        mode.name(),
        recip.map_or(String::new(), |why| format!(
            "; its signals look like a reciprocating test ({why}): try `test_mode` reciprocating or leave the mode to the signals"
        ))
    ))
}

/// A pause in the recording longer than this many (median) sample intervals splits the
/// segment it falls in: no steady window spans it (an 11-day pause inside one test is two
/// tests), and the split is a line of the summary.
pub const GAP_SPLIT_INTERVALS: f64 = 100.0;

/// The spans split at every gap in time longer than [`GAP_SPLIT_INTERVALS`] sample intervals,
/// each split a warning of the file's report.
pub(super) fn split_at_gaps(p: &mut Prepared, spans: &[Span]) -> Vec<Span> {
    let t = &p.rec.time_s;
    let limit = GAP_SPLIT_INTERVALS / p.fs;
    let mut out = Vec::with_capacity(spans.len());
    for sp in spans {
        let mut start = sp.i;
        for k in sp.i + 1..sp.j {
            let gap = t[k] - t[k - 1];
            if gap > limit {
                p.report.warnings.push(format!(
                    "a gap of {} in time (t = {:.3} s to {:.3} s, {:.0} sample intervals, more than {GAP_SPLIT_INTERVALS}) splits a segment: no steady window spans it",
                    duration_text(gap),
                    t[k - 1],
                    t[k],
                    gap * p.fs
                ));
                out.push(Span {
                    i: start,
                    j: k,
                    unc: (if start == sp.i { sp.unc.0 } else { 0.0 }, 0.0),
                    ..*sp
                });
                start = k;
            }
        }
        out.push(Span {
            i: start,
            unc: (if start == sp.i { sp.unc.0 } else { 0.0 }, sp.unc.1),
            ..*sp
        });
    }
    out
}

/// A duration for messages: `42.0 s`, `3.5 h`, `11.0 days`.
pub(super) fn duration_text(s: f64) -> String {
    if s >= 86_400.0 {
        format!("{:.1} days", s / 86_400.0)
    } else if s >= 3600.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{s:.1} s")
    }
}

/// Sliding pieces shorter than a step, as dropped parts: pieces less than `min_segment_s`
/// apart are one entry, and three or more such pieces in a row are a ramp cut into short
/// levels: transitions, not dropped data.
pub(super) fn too_short(p: &Prepared, short: &[Span], cfg: &IdentifyConfig) -> Vec<Dropped> {
    let gap = (cfg.min_segment_s * p.fs) as usize;
    let mut groups: Vec<(usize, usize, usize, usize)> = Vec::new(); // first, last, samples, count
    for sp in short {
        match groups.last_mut() {
            Some(g) if sp.i <= g.1 + gap => {
                g.1 = sp.j;
                g.2 += sp.j - sp.i;
                g.3 += 1;
            }
            _ => groups.push((sp.i, sp.j, sp.j - sp.i, 1)),
        }
    }
    groups
        .into_iter()
        .filter(|g| g.3 < 3)
        .map(|(i, j, samples, count)| Dropped {
            what: format!(
                "{} {:.3}–{:.3} s",
                if count == 1 {
                    "a piece".to_string()
                } else {
                    format!("{count} pieces")
                },
                p.rec.time_s[i],
                p.rec.time_s[j - 1]
            ),
            reason: format!(
                "shorter than the shortest step (min_segment_s = {} s)",
                cfg.min_segment_s
            ),
            seconds: samples as f64 / p.fs,
        })
        .collect()
}

/// Why a file gave no segment, from what its signals showed.
pub(super) fn no_segment_hint(p: &Prepared) -> String {
    let loaded_s = p.loaded_s;
    let sliding_s = p.report.coverage.sliding_s;
    match p.report.segmentation.as_str() {
        "step-column" => "no step of the step column is loaded and sliding".into(),
        "speed" => {
            "the speed channel never holds a constant speed above rest while loaded".into()
        }
        _ if sliding_s == 0.0 => format!(
            "the normal force is above its loaded threshold for {loaded_s:.1} s, but |μ| never stands out of its noise there (sliding_rest_sigmas × the smoothed μ's noise, at least sliding_min_mu; sliding evidence: {}); a step column (`map` step=NAME) or a speed channel (`map` speed=NAME:UNIT) would segment it",
            p.report.sliding
        ),
        _ => format!(
            "{sliding_s:.1} s slide, but in pieces shorter than min_segment_s; a step column (`map` step=NAME) or a speed channel (`map` speed=NAME:UNIT) would segment it"
        ),
    }
}

/// The plan's steps grouped by pin, in run order (a pin's steps are contiguous).
pub(super) fn pin_groups(expected: &[ExpectedStep]) -> Vec<&[ExpectedStep]> {
    expected.chunk_by(|a, b| a.pin == b.pin).collect()
}

/// Which planned steps each of `runs` sliding runs holds: a pin's steps each when there are
/// as many runs as pins, one step each when there are as many runs as steps, else unknown
/// (`None`: the run is split by the signal alone and aligned afterwards).
pub(super) fn plan_steps_per_run(
    expected: Option<&[ExpectedStep]>,
    runs: usize,
) -> Vec<Option<&[ExpectedStep]>> {
    let Some(e) = expected else {
        return vec![None; runs];
    };
    let pins = pin_groups(e);
    if pins.len() == runs {
        pins.into_iter().map(Some).collect()
    } else if e.len() == runs {
        e.chunks(1).map(Some).collect()
    } else {
        vec![None; runs]
    }
}
