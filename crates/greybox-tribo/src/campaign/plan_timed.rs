//! The greybox NC-program path: one recording per pin, segmented by the plan's timing from the
//! trigger.

use super::report::{read_warnings, update_coverage, Campaign, FileReport, SegmentReport};
use crate::config::Segmentation;
use crate::coverage::Coverage;
use crate::plan::Plan;
use crate::plan_timing::identify_pin;
use greybox_core::units;
use greybox_core::{Error, Result};
use greybox_recording::Recording;

/// The greybox NC-program path: one recording per pin, the plan's timing from the trigger.
pub(super) fn plan_timed(recs: &[Recording], plan: &Plan, c: &Campaign) -> Result<Vec<FileReport>> {
    if recs.len() != plan.pins.len() {
        return Err(Error::invalid(
            "identify",
            format!(
                "the plan has {} pins but {} recordings were given (plan-timing needs one recording per pin, in pin order)",
                plan.pins.len(),
                recs.len()
            ),
        ));
    }
    let mut files = Vec::with_capacity(recs.len());
    for (k, rec) in recs.iter().enumerate() {
        let (rows, d) = identify_pin(rec, plan, k as u32 + 1, c.contact, c.cfg)?;
        let ts = d.trigger_s + d.latency_s;
        let segments = rows
            .iter()
            .enumerate()
            .map(|(i, r)| SegmentReport {
                index: i + 1,
                start_s: ts + plan.pin_steps(r.pin)[i].step_start_s,
                end_s: ts + plan.pin_steps(r.pin)[i].plateau_end_s,
                steady_start_s: Some(ts + r.plateau_start_s),
                steady_end_s: Some(ts + r.plateau_end_s),
                normal_force_n: r.normal_force_n,
                spindle_rpm: None,
                sliding_velocity_m_per_min: Some(units::m_per_s_to_m_per_min(
                    r.sliding_velocity_m_s,
                )),
                step_label: None,
                boundaries: "plan timing",
                cof: Some(r.cof_apparent),
                cof_std: Some(r.cof_apparent_std),
                cof_sem: None,
                cof_ci95: r.cof_apparent_ci95,
                cof_n_eff: None,
                n_samples: r.n_samples as usize,
                masked_samples: 0,
                label_evidence: r.label_evidence.clone(),
                flags: r.flags.clone(),
                matched: Some((r.pin, r.step)),
                problem: None,
                run_in_s: None,
                unsettled: None,
                never_settles: false,
                drift_per_hour: Some(r.cof_trend_per_s * 3600.0),
                drift_per_km: None,
                boundary_uncertainty_s: None,
                contradiction: None,
                direction: None,
                passes: None,
                reciprocating: None,
                stats: None,
            })
            .collect();
        files.push(FileReport {
            source: rec.source.clone(),
            read: rec.provenance.clone(),
            warnings: read_warnings(rec),
            sample_rate_hz: rec.sample_rate_hz(),
            samples: rec.len(),
            duration_s: rec.duration_s(),
            segmentation: Segmentation::PlanTiming.name().into(),
            baseline: "start and end".into(),
            drift_normal_n: d.drift_normal_n,
            drift_tangential_n: d.drift_tangential_n,
            tangential_sign_flipped: false,
            normal_sign_flipped: false,
            sliding: "plan timing".into(),
            period_s: None,
            coverage: Coverage::default(),
            segments,
            notes: vec![format!(
                "trigger at {:.4} s, NC-to-spindle latency {:.4} s, {} spikes removed",
                d.trigger_s, d.latency_s, d.spikes_removed
            )],
            unusual: Vec::new(),
            rows,
            too_short: Vec::new(),
        });
    }
    for f in files.iter_mut() {
        // the plan's steps are the sliding time
        f.coverage.sliding_s = f.segments.iter().map(|s| s.end_s - s.start_s).sum();
        update_coverage(f, c.cfg, true);
    }
    Ok(files)
}
