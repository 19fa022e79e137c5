//! A reciprocating test's segments (ASTM G133): one per test or load/speed step, μ averaged over
//! the steady cycles.

use super::prepare::Prepared;
use super::report::SegmentReport;
use super::span::{Cut, Span};
use crate::config::IdentifyConfig;
use crate::reciprocating::Reciprocating;
use crate::uncertainty::WindowMean;
use greybox_core::dataset::flags;
use greybox_core::stats::median;
use greybox_core::units;
use greybox_recording::{Recording, SpeedTrace};

/// Why a recording is identified as a reciprocating test, or `None` (see
/// [`crate::reciprocating::detect`]): the mode named in `[identify] mode` / `--test-mode`,
/// else the rig profile's mode and the strokes the signals show.
pub(super) fn reciprocating_reason(rec: &Recording, cfg: &IdentifyConfig) -> Option<String> {
    let profile = rec.provenance.as_ref().and_then(|r| r.test_mode);
    crate::reciprocating::detect(
        &crate::reciprocating::Signals::of(rec),
        cfg.mode,
        profile,
        cfg,
    )
}

/// A reciprocating file's segments: one per test (or load/speed step), μ averaged over the
/// steady cycles with the strokes and cycles kept beside it (ASTM G133).
pub(super) fn reciprocating_segments(p: &mut Prepared, why: &str, cfg: &IdentifyConfig) {
    let s = crate::reciprocating::Signals::with_forces(p.rec, &p.fn_c, &p.ft_c);
    let parts = crate::reciprocating::parts(&s, cfg);
    let mut segs = Vec::with_capacity(parts.len());
    for (k, &(i, j, label)) in parts.iter().enumerate() {
        let mut rep = SegmentReport::bare(
            p,
            Span::new(i, j, label).by(if label.is_some() {
                Cut::StepColumn
            } else {
                Cut::Run
            }),
            k + 1,
        );
        match &p.rec.speed {
            Some(SpeedTrace::SpindleRpm(v)) => rep.spindle_rpm = Some(median(&v[i..j])),
            Some(SpeedTrace::SlidingMPerS(v)) => {
                let m = median(&v[i..j].iter().map(|x| x.abs()).collect::<Vec<_>>());
                rep.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(m));
            }
            None => {}
        }
        match crate::reciprocating::analyse(&s, i, j, cfg) {
            Ok(r) => reciprocating_stats(&mut rep, r, cfg),
            Err(m) => rep.problem = Some(m),
        }
        segs.push(rep);
    }
    p.report.segmentation = "reciprocating".into();
    p.report.notes.push(format!("reciprocating test (ASTM G133): {why}; μ per stroke over its middle 50 %, sign taken by direction"));
    if segs.is_empty() {
        p.report
            .notes
            .push("no loaded stretch: no stroke found".into());
    }
    p.report.segments = segs;
}

/// Fill a segment from a reciprocating result: the row's μ is the steady cycles' mean μ,
/// its spread the cycles' spread, its standard error that over the cycles.
pub(super) fn reciprocating_stats(rep: &mut SegmentReport, r: Reciprocating, cfg: &IdentifyConfig) {
    let n_cycles = r.steady_cycles.1 - r.steady_cycles.0;
    let duration = r.end_s - r.start_s;
    let trend = (r.trend_per_s * duration).abs() > cfg.trend_tolerance;
    let mut fl = vec![flags::RECIPROCATING.to_string()];
    if trend {
        fl.push(flags::TREND.to_string());
    }
    // the cycles' mean μ, one value a cycle, through the one interval estimator
    let mus: Vec<f64> = r.cycles[r.steady_cycles.0..r.steady_cycles.1]
        .iter()
        .map(|c| c.mu_mean)
        .collect();
    let interval = WindowMean::of(&mus).unwrap_or(WindowMean {
        mean: r.mu_mean,
        sem: r.mu_std,
        n_eff: n_cycles.max(1) as f64,
        // one cycle: its two directions' difference is all that says how sure it is
        half_width_95: 0.5 * (r.mu_forward - r.mu_backward).abs(),
    });
    if let Some(v) = r.velocity_m_s {
        rep.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(v));
        rep.spindle_rpm = None;
    }
    if r.run_in_cycles.is_some() {
        rep.run_in_s = Some(r.start_s - rep.start_s);
    }
    rep.unsettled = r.unsettled.clone();
    rep.steady_start_s = Some(r.start_s);
    rep.steady_end_s = Some(r.end_s);
    rep.normal_force_n = r.normal_n;
    rep.cof = Some(r.mu_mean);
    rep.cof_std = Some(r.mu_std);
    rep.cof_sem = Some(interval.sem);
    rep.cof_ci95 = Some(interval.half_width_95);
    rep.cof_n_eff = Some(interval.n_eff);
    rep.n_samples = r.samples;
    rep.drift_per_hour = Some(r.trend_per_s * 3600.0);
    rep.flags = fl.clone();
    rep.stats = Some(crate::steady_window::PlateauStats {
        mean: r.mu_mean,
        std: r.mu_std,
        n_samples: r.samples,
        start_s: r.start_s,
        end_s: r.end_s,
        trend_per_s: r.trend_per_s,
        stationary: !trend,
        flags: fl,
        spikes: 0,
        interval,
        ci95: interval.half_width_95,
        normal_force_n: r.normal_n,
        parts: None,
    });
    rep.reciprocating = Some(r);
}
