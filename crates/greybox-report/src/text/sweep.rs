//! The sweep's reports as terminal text (its functions are not re-exported in [`super`]:
//! `text::sweep::plan` is a sweep's plan, `text::plan` a campaign's).

use greybox_sweep::calibrate::Calibration;
use greybox_sweep::collect::Collected;
use greybox_sweep::{Plan, RunReport};
use std::fmt::Write as _;

/// Core-seconds of a sweep at the solver's typical speed, particle-steps per second per core.
const PARTICLE_STEPS_PER_CORE_S: f64 = 1.5e6;

/// The case table with each case's cost.
pub fn plan(p: &Plan) -> String {
    let mut t = format!("{} cases of {}\n", p.cases.len(), p.source);
    let _ = write!(t, "{:>4}  {:<12}", "case", "id");
    for f in &p.fields {
        let _ = write!(t, "  {f}");
    }
    let _ = writeln!(t, "  particles  steps  particle-steps");
    let mut total = 0.0;
    for c in &p.cases {
        let _ = write!(t, "{:>4}  {:<12}", c.index, c.id);
        for (_, v) in &c.values {
            let _ = write!(t, "  {v}");
        }
        let _ = writeln!(
            t,
            "  {}  {}  {:.3e}",
            c.cost.particles, c.cost.steps, c.cost.particle_steps
        );
        total += c.cost.particle_steps;
    }
    let _ = writeln!(
        t,
        "total {total:.3e} particle-steps (≈ {:.0} core-s at {PARTICLE_STEPS_PER_CORE_S:.1e} particle-steps/s per core)",
        total / PARTICLE_STEPS_PER_CORE_S
    );
    t
}

/// What a run did; a Slurm dry run shows its array script.
pub fn run(r: &RunReport, dry_run: bool) -> String {
    if let (true, Some(s)) = (dry_run, &r.slurm_script) {
        return s.clone();
    }
    let mut t = String::new();
    if let Some(j) = &r.slurm_job {
        let _ = writeln!(t, "Slurm job {j}");
    }
    let _ = writeln!(
        t,
        "{} of {} cases done ({} already before this run), {} failed",
        r.done,
        r.cases,
        r.skipped,
        r.failed.len()
    );
    for f in &r.failed {
        let _ = writeln!(
            t,
            "case {} ({}) failed: {}\n{}",
            f.index, f.id, f.error, f.log_tail
        );
    }
    t
}

/// The collected results and what is missing.
pub fn collected(c: &Collected) -> String {
    let mut t = format!("{} of {} cases -> {}\n", c.done, c.cases, c.csv);
    for (i, id, s) in &c.missing {
        let _ = writeln!(t, "  no result: case {i} ({id}), {s:?}");
    }
    for p in &c.plots {
        let _ = writeln!(t, "  plot: {p}");
    }
    t
}

/// The calibrated fields (and μ scale) with the residual per condition.
pub fn calibration(r: &Calibration) -> String {
    let mut t = r
        .parameters
        .iter()
        .map(|(f, v)| format!("{f} = {v:.5}"))
        .collect::<Vec<_>>()
        .join(", ");
    if let Some(s) = r.friction_scale {
        if !t.is_empty() {
            t += ", ";
        }
        let _ = write!(t, "mu scale = {s:.4}");
    }
    let pm = |ci: Option<f64>| {
        ci.map(|h| format!(" ± {:.2}", 100.0 * h))
            .unwrap_or_default()
    };
    let _ = writeln!(
        t,
        "; mean relative error: training {:.2}{} %{}",
        100.0 * r.training_error,
        pm(r.training_error_ci95),
        r.held_out_error
            .map(|e| format!(", held out {:.2}{} %", 100.0 * e, pm(r.held_out_error_ci95)))
            .unwrap_or_default()
    );
    match &r.certainty {
        Some(c) => {
            let _ = writeln!(
                t,
                "how sure: {} of {} distinct evaluations cannot be told from the best, paired over the {} training conditions (95 %, corrected for the best's rivals):",
                c.as_good_as_best, c.evaluations, c.conditions
            );
            for f in &c.fields {
                let _ = writeln!(t, "  {} = {:.5}: {}", f.field, f.value, f.verdict);
            }
        }
        None => {
            let _ = writeln!(
                t,
                "how sure: cannot say (fewer than two training conditions with a finite error)"
            );
        }
    }
    for x in &r.residuals {
        let _ = write!(
            t,
            "  {:>3} {:<9} F'c measured {:.1} simulated {:.1} N/mm ({:+.1} %)",
            x.condition,
            if x.held_out { "held out" } else { "training" },
            x.measured_cutting_force_n_per_mm,
            x.simulated_cutting_force_n_per_mm,
            100.0 * x.cutting_force_error
        );
        if let (Some(m), Some(e)) = (x.measured_feed_force_n_per_mm, x.feed_force_error) {
            let _ = write!(
                t,
                "; F'f {m:.1} / {:.1} N/mm ({:+.1} %)",
                x.simulated_feed_force_n_per_mm,
                100.0 * e
            );
        }
        if let Some(m) = x.measured_chip_ratio {
            let _ = match (x.simulated_chip_ratio, x.chip_ratio_error) {
                (Some(s), Some(e)) => write!(t, "; h_c/h {m:.3} / {s:.3} ({:+.1} %)", 100.0 * e),
                _ => write!(t, "; h_c/h {m:.3} / none (no chip measured)"),
            };
        }
        t.push('\n');
    }
    t
}
