//! Plain text of the benchmarks: ingestion, prediction latency, surrogate tables and SPH.

use greybox_pipeline::bench::{IngestResult, PredictLatency, SurrogateSpeed};
use greybox_pipeline::simulate::{CutCase, CutSummary};
use std::fmt::Write as _;
use std::path::Path;

/// Prediction latency per model file.
pub fn predict_latency(rows: &[PredictLatency]) -> String {
    let mut text = String::new();
    for r in rows {
        let _ = writeln!(
            text,
            "predict {:>18}: {:8.1} ns per point ({} calls, {})",
            r.family, r.ns_per_call, r.calls, r.model
        );
    }
    text
}

/// Read speed per recording format.
pub fn ingest(results: &[IngestResult]) -> String {
    let mut text = String::new();
    for r in results {
        let _ = writeln!(text,
            "ingest {:>4}: {:8.1} MB, {} samples x 5 channels: best {:.3} s (median {:.3} s) -> {:7.1} MB/s, {:.2} Msamples/s",
            r.format, r.file_mb, r.samples, r.best_s, r.median_s, r.best_mb_per_s, r.best_msamples_per_s
        );
    }
    text
}

/// Full run's wall time over a `fraction`'s: the working steps' ratio, since the idle steps
/// of the tool's approach (`idle_steps` of the run's `steps`; the same number in the full
/// run) cost next to nothing.
fn full_run_scale(steps: u64, idle_steps: u64, fraction: f64) -> f64 {
    let working = steps.saturating_sub(idle_steps) as f64;
    let full_working = steps as f64 / fraction - idle_steps as f64;
    if working > 0.0 {
        full_working / working
    } else {
        1.0 / fraction
    }
}

/// The SPH benchmark: speed per core and the full run's time.
pub fn sph_bench(config: &Path, fraction: f64, case: &CutCase, s: &CutSummary) -> String {
    let mut text = String::new();
    // A run that stopped once sure is complete; otherwise extrapolate the fraction.
    let (full, how) = match s.sure_at_mm {
        Some(mm) if case.setup.steady.stop_when_sure => (
            s.wall_s,
            format!(", stopped once its force intervals met their targets at {mm:.3} mm"),
        ),
        _ if fraction < 1.0 => (
            s.wall_s * full_run_scale(s.steps, s.idle_steps, fraction),
            ", extrapolated".to_string(),
        ),
        _ => (s.wall_s, String::new()),
    };
    let _ = writeln!(
        text,
        "SPH cutting benchmark ({}): {} particles, {} steps, dt {:.3e} s, mass scaling {}",
        config.display(),
        s.particles,
        s.steps,
        s.dt_s,
        s.mass_scaling
    );
    let _ = writeln!(text,
        "  {:.3e} particle-steps/s on {} threads ({} pair passes) = {:.3e} per core; {:.3} mm of cut in {:.1} s (full run: {:.1} s{how})",
        s.particle_steps_per_s,
        s.threads,
        s.simd,
        s.particle_steps_per_s_per_core,
        s.simulated_cut_length_mm,
        s.wall_s,
        full
    );
    if config.ends_with("iwf-ti64-cut.toml") {
        let _ = writeln!(text,
            "  reference: ETH IWF mfree_iwf-ul-cut-refine ~1.7e5 particle-steps/s/core, 59 min for the cut on one core"
        );
    }
    let _ = writeln!(
        text,
        "  cutting force {:.1} N/mm, feed force {:.1} N/mm",
        s.cutting_force_n_per_mm, s.feed_force_n_per_mm
    );
    text
}

/// Law and surrogate-table evaluation speed, the table's size and deviation.
pub fn surrogate_speed(s: &SurrogateSpeed) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "law:       {:8.1} ns per call, {:.3e} evaluations/s/core ({})",
        s.law_ns_per_call,
        1e9 / s.law_ns_per_call,
        s.law
    );
    let [np, nv, nt] = s.shape;
    let what = if s.table_kind == "exact" {
        "cells"
    } else {
        "nodes"
    };
    let _ = writeln!(
        text,
        "surrogate: {:8.1} ns per call, {:.3e} evaluations/s/core ({} table, {np} x {nv}{} {what} = {} values, {:.0} kB, built in {:.2} s)",
        s.table_ns_per_call,
        1e9 / s.table_ns_per_call,
        s.table_kind,
        if nt > 1 { format!(" x {nt}") } else { String::new() },
        s.values,
        s.values as f64 * 8.0 / 1e3,
        s.build_s
    );
    let _ = writeln!(
        text,
        "max deviation from the law: {:.2e} on {} fresh states{}",
        s.max_deviation,
        s.check_points,
        match s.tolerance {
            Some(t) => format!(" (tolerance {t:.0e})"),
            None if s.table_kind == "exact" => " (random, and every threshold ± 1 ulp)".into(),
            None => String::new(),
        }
    );
    text
}

#[cfg(test)]
mod tests {
    use super::full_run_scale;

    #[test]
    fn full_runs_scale_by_their_working_steps() {
        // 1 000 steps of a tenth, 400 of them idle: the full run has 10 000 steps, 9 600
        // of them working, 16 times the 600 timed.
        assert_eq!(full_run_scale(1_000, 400, 0.1), 16.0);
        // No idle steps: the fraction's inverse.
        assert!((full_run_scale(1_000, 0, 0.25) - 4.0).abs() < 1e-12);
        // Nothing but idle steps timed: no better guess than the fraction's inverse.
        assert_eq!(full_run_scale(500, 500, 0.5), 2.0);
    }
}
