//! Measuring a segment: its steady window, μ statistics and speed, whether its uncertain boundaries
//! matter, and the notes on run-in and drift.

use super::prepare::Prepared;
use super::report::{FileReport, SegmentReport};
use super::span::{Cut, Span};
use crate::config::IdentifyConfig;
use crate::config::SteadyRule;
use crate::signal::{moving_average, quantum, running_median};
use crate::steady_window::{
    plateau_stats, rule_span, steady_span, steady_stretch, step_signals, windows, Settling,
    StepSignals,
};
use greybox_core::dataset::flags;
use greybox_core::stats::median;
use greybox_core::units;
use greybox_recording::SpeedTrace;

/// The steady part of a segment, window-relative `[a, b)`, and the run-in end (`auto` only).
///
/// Under `auto`: F_N and the speed must be within their bands ([`steady_span`], which drops
/// load and speed ramps), and μ must be in its final stationary stretch
/// ([`final_stationary`]); the settle time and end margin are then dropped. Under
/// `last:P%` / `from:Ts` the window is the user's, as given. With the window, how μ settled
/// in it ([`steady_stretch`]: a μ that never settles gives its mean after the warm-up, with
/// its trend, and says so).
pub(super) fn steady_window(
    sig: &StepSignals,
    others: &[(&[f64], f64)],
    t_rel: &[f64],
    cfg: &IdentifyConfig,
    fs: f64,
) -> std::result::Result<(usize, usize, Option<usize>, Settling), String> {
    if let Some((a, b)) = rule_span(cfg.steady, t_rel, cfg.min_plateau_samples, "samples")? {
        return Ok((a, b, None, Settling::Settled));
    }
    let (a0, b0) = steady_span(others, sig.w_smooth).ok_or_else(|| {
        "no steady part: F_N or the speed never holds its level inside the segment".to_string()
    })?;
    let (fin, settling) = steady_stretch(&sig.smooth[a0..b0], &t_rel[a0..b0], sig.w_smooth, 0.002);
    let (a, b) = (a0 + fin.a, a0 + fin.b);
    let settle = (cfg.settle_time_s * fs).round() as usize;
    let margin = (cfg.end_margin_s * fs).round() as usize;
    let run_in = (fin.run_in_end > 0).then_some(a0 + fin.run_in_end);
    Ok((
        (a + settle).min(b),
        b.saturating_sub(margin).max(a),
        run_in,
        settling,
    ))
}

/// Identify one segment: steady part, statistics, speed.
pub(super) fn measure(
    p: &Prepared,
    span: Span,
    index: usize,
    cfg: &IdentifyConfig,
) -> SegmentReport {
    let rec = p.rec;
    let (i, j) = (span.i, span.j);
    let unc = span.unc.0.max(span.unc.1);
    let mut rep = SegmentReport::bare(p, span, index);
    rep.boundary_uncertainty_s = (unc > 0.0).then_some(unc);
    let f_ref = rep.normal_force_n.abs().max(1e-9);
    let sig = match step_signals(&p.fn_c, &p.ft_c, i, j, cfg, p.fs, |k, f_n| {
        if f_n <= 0.1 * f_ref {
            Err(format!(
                "normal force {f_n:.3} N at t = {:.3} s: zero or negative inside a loaded segment",
                rec.time_s[k]
            ))
        } else {
            Ok(())
        }
    }) {
        Ok(s) => s,
        Err(m) => {
            rep.problem = Some(m);
            return rep;
        }
    };
    let (h_spike, w) = windows(cfg, p.fs);
    // the load's level through a running median first: a heavy-tailed spike of the load cell
    // is no change of the load
    let fn_s = moving_average(&running_median(&p.fn_c[i..j], h_spike), w);
    let speed: Option<Vec<f64>> = rec
        .speed
        .as_ref()
        .map(|s| moving_average(&s.values()[i..j], w));
    let mut others: Vec<(&[f64], f64)> = vec![(&fn_s, 0.02 * f_ref)];
    if let Some(v) = &speed {
        // a quantised channel (a 1 Hz export stepping 0.147/0.150 m/s) wanders by its LSB
        let lsb = rec
            .speed
            .as_ref()
            .map_or(0.0, |s| quantum(&s.values()[i..j]));
        others.push((v, 0.01 * median(v).abs() + 1.5 * lsb + 1e-9));
    }
    let t_rel: Vec<f64> = rec.time_s[i..j].iter().map(|t| t - rec.time_s[i]).collect();
    let (pa, pb, run_in, settling) = match steady_window(&sig, &others, &t_rel, cfg, p.fs) {
        Ok(w) => w,
        Err(m) => {
            rep.problem = Some(m);
            return rep;
        }
    };
    let Some(st) = plateau_stats(&rec.time_s, &p.fn_c, &sig, pa, pb, 0.0, cfg) else {
        rep.problem = Some(format!(
            "only {} samples in the steady part (min {}): the segment is too short or never settles",
            pb.saturating_sub(pa),
            cfg.min_plateau_samples
        ));
        return rep;
    };
    if let Some(s) = &rec.speed {
        let v = median(&s.values()[i + pa..i + pb]);
        match s {
            SpeedTrace::SpindleRpm(_) => rep.spindle_rpm = Some(v),
            SpeedTrace::SlidingMPerS(_) => {
                rep.sliding_velocity_m_per_min = Some(units::m_per_s_to_m_per_min(v))
            }
        }
    }
    if cfg.steady == SteadyRule::Auto {
        rep.run_in_s = Some(run_in.map_or(0.0, |k| t_rel[k]));
    }
    rep.drift_per_hour = Some(st.trend_per_s * 3600.0);
    rep.steady_start_s = Some(st.start_s);
    rep.steady_end_s = Some(st.end_s);
    rep.normal_force_n = st.normal_force_n;
    rep.cof = Some(st.mean);
    rep.cof_std = Some(st.std);
    rep.n_samples = st.n_samples;
    rep.flags = st.flags.clone();
    let mut st = st;
    rep.unsettled = settling.reason(pb - pa, "samples");
    if settling == Settling::NeverSettles {
        st.stationary = false;
        rep.never_settles = true;
    }
    interval(&mut rep, &mut st, (span, &sig, (pa, pb)), p, cfg);
    if matches!(span.cut, Cut::LevelChange | Cut::PlanTiming) {
        check_one_level(&mut rep, &sig, p, cfg);
    }
    rep.masked_samples = st.spikes;
    rep.stats = Some(st);
    rep
}

/// μ's 95 % interval of a measured segment (window `[pa, pb)` of `span`), into `rep` and
/// `st.ci95`: the window's own serial correlation, or the run's disturbance over the
/// window's length where larger (a window on the crest of a slow run-out looks flat on its
/// own); the baseline's error, which moves every sample's μ alike,
/// δμ = (δF_t − μ·δF_N)/F_N; μ's change when the window's first half is left out, where it is
/// significant ([`settling_shift`]); and μ's change when the window's ends move in by the
/// boundaries' uncertainty (flag `uncertain-boundary` when that exceeds half
/// `mean_uncertainty_tolerance`).
fn interval(
    rep: &mut SegmentReport,
    st: &mut crate::steady_window::PlateauStats,
    (span, sig, window_idx): (Span, &StepSignals, (usize, usize)),
    p: &Prepared,
    cfg: &IdentifyConfig,
) {
    let mid = 0.5 * (st.start_s + st.end_s);
    let (se_n, se_t) = p.offset_se_at(mid);
    let f_n = st.normal_force_n.abs().max(1e-12);
    let se_base = se_t.hypot(st.mean * se_n) / f_n;
    let window = st
        .interval
        .with_sem_floor(span.run_sem / (st.end_s - st.start_s).max(1e-9).sqrt());
    let iv = window.with_common_error(se_base);
    let shift = boundary_shift(span, sig, window_idx, p.fs);
    if shift.is_some_and(|d| !(d <= 0.5 * cfg.mean_uncertainty_tolerance)) {
        rep.flags.push(flags::UNCERTAIN_BOUNDARY.to_string());
    }
    let widening = shift.map_or(0.0, |d| d.min(st.std.max(iv.half_width_95)))
        + settling_shift(sig, window_idx, iv.sem);
    st.ci95 = iv.half_width_95 + widening;
    let (se_n_at, (ta, te, lambda)) = p.offset_parts_at(mid);
    st.parts = Some(crate::steady_window::IntervalParts {
        window,
        normal_offset: st.mean.abs() * se_n_at / f_n,
        tangential_offset: (ta / f_n, te / f_n, lambda),
        shift: widening,
    });
    rep.cof_sem = Some(iv.sem);
    rep.cof_ci95 = Some(st.ci95);
    rep.cof_n_eff = Some(iv.n_eff);
}

/// How far μ over the window `[pa, pb)` moves when its first half is left out, where that
/// exceeds the window's standard error `sem` (0 otherwise): a run-in's tail still inside
/// the noise band, or a slow drift, biases a long window's mean by more than its own
/// statistics see; the interval is widened by it, as by an uncertain boundary.
fn settling_shift(sig: &StepSignals, (pa, pb): (usize, usize), sem: f64) -> f64 {
    let mean = |a: usize, b: usize| {
        let v: Vec<f64> = (a..b.min(sig.mu.len()))
            .filter(|k| sig.good[*k])
            .map(|k| sig.mu[k])
            .collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    match (mean(pa, pb), mean((pa + pb) / 2, pb)) {
        (Some(all), Some(late)) if (all - late).abs() > sem => (all - late).abs(),
        _ => 0.0,
    }
}

/// The segment's check against its own signal ([`super::self_check::two_levels`] over
/// μ's block means, blocks of [`Prepared::step_block`]): two levels inside it flag the row
/// `label-contradicted`, with a line saying where.
fn check_one_level(rep: &mut SegmentReport, sig: &StepSignals, p: &Prepared, cfg: &IdentifyConfig) {
    let b = p.step_block();
    let blocks: Vec<f64> = sig
        .mu
        .chunks(b)
        .zip(sig.good.chunks(b))
        .filter_map(|(m, g)| {
            let v: Vec<f64> = m
                .iter()
                .zip(g)
                .filter(|(_, g)| **g)
                .map(|(m, _)| *m)
                .collect();
            (!v.is_empty()).then(|| median(&v))
        })
        .collect();
    // the ramp into the step and a settling at its ends are transitions, not a second level
    let (ta, tb) = super::change_points::trim_transients(&blocks);
    let block_s = b as f64 / p.fs;
    if let Some((at, a, b_level)) =
        super::self_check::two_levels(&blocks[ta..tb], block_s, cfg.mean_uncertainty_tolerance)
    {
        let at = at + ta as f64 * block_s;
        rep.flags.push(flags::LABEL_CONTRADICTED.to_string());
        rep.contradiction = Some(format!(
            "μ holds two levels: {a:.4} until {:.3} s, then {b_level:.4} (a step boundary the cut missed?)",
            rep.start_s + at
        ));
    }
}

/// How far μ over the steady window `[pa, pb)` (segment-relative samples) moves when its ends
/// move in by the segment's boundary uncertainties (`None`: they do not reach into the
/// window). Where nothing of the window is left, the window's spread of μ (as much as μ could
/// move at all) — bounded in [`measure`] by the larger of the samples' standard deviation and
/// the interval.
pub(super) fn boundary_shift(
    span: Span,
    sig: &StepSignals,
    (pa, pb): (usize, usize),
    fs: f64,
) -> Option<f64> {
    let len = span.j - span.i;
    let a = pa.max((span.unc.0 * fs).ceil() as usize);
    let b = pb.min(len.saturating_sub((span.unc.1 * fs).ceil() as usize));
    if (a, b) == (pa, pb) {
        return None;
    }
    let mean = |a: usize, b: usize| {
        let v: Vec<f64> = (a..b).filter(|k| sig.good[*k]).map(|k| sig.mu[k]).collect();
        (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
    };
    match (mean(pa, pb), (a < b).then(|| mean(a, b)).flatten()) {
        (Some(all), Some(inner)) => Some((all - inner).abs()),
        _ => Some(f64::INFINITY),
    }
}

/// Drift per sliding distance (1/km) of every measured segment with a known speed, and a
/// note per segment with a run-in, a drift flagged `trend` or an uncertain boundary.
pub(super) fn steady_notes(files: &mut [FileReport]) {
    for f in files.iter_mut() {
        for s in f.segments.iter_mut() {
            let (Some(per_h), Some(v)) = (s.drift_per_hour, s.sliding_velocity_m_per_min) else {
                continue;
            };
            // μ/h ÷ (km/h) = μ/km, with v in m/min → 0.06 v km/h
            if v.abs() > 0.0 {
                s.drift_per_km = Some(per_h / (0.06 * v.abs()));
            }
        }
        let mut notes = Vec::new();
        for s in &f.segments {
            let mut parts = Vec::new();
            if let Some(r) = s.run_in_s.filter(|r| *r > 0.0) {
                parts.push(format!("run-in {r:.1} s"));
            }
            if s.flags.iter().any(|x| x == flags::TREND) {
                let km = s
                    .drift_per_km
                    .map_or(String::new(), |k| format!(", {k:+.2e} /km"));
                parts.push(format!(
                    "μ drifts {:+.4} /h{km} over the steady part",
                    s.drift_per_hour.unwrap_or(0.0)
                ));
            }
            if let Some(u) = &s.unsettled {
                parts.push(u.clone());
            }
            if let Some(u) = s.boundary_uncertainty_s {
                parts.push(format!("uncertain boundary (±{u:.3} s)"));
            }
            if !parts.is_empty() {
                notes.push(format!("segment {}: {}", s.index, parts.join("; ")));
            }
        }
        f.notes.extend(notes);
    }
}
