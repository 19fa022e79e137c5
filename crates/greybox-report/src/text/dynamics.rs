//! Plain text of the rig's dynamics (resonances per load, the excitation check) and of the
//! FE restart loop (final μ per window).

use super::table::Table;
use greybox_couple::engine::CouplingResult;
use greybox_pipeline::characterize::CharacterizeReport;
use std::fmt::Write as _;
use std::path::Path;

/// The rig's resonances per load and the excitation check.
pub fn characterize(r: &CharacterizeReport) -> String {
    let mut text = String::new();
    let mut t = Table::new(&[
        "load [N]",
        "impacts",
        "rejected",
        "f1 [Hz]",
        "zeta1",
        "|H1| at f1",
        "f2 [Hz]",
    ]);
    for l in &r.loads {
        let first = l
            .resonances
            .iter()
            .min_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        let second = l
            .resonances
            .iter()
            .map(|x| x.frequency_hz)
            .filter(|f| Some(*f) != first.map(|x| x.frequency_hz))
            .fold(f64::INFINITY, f64::min);
        t.row(vec![
            l.load_n
                .map(|x| format!("{x:.0}"))
                .unwrap_or_else(|| "-".into()),
            l.impacts_used.to_string(),
            l.rejected.len().to_string(),
            first
                .map(|x| format!("{:.1}", x.frequency_hz))
                .unwrap_or_else(|| "-".into()),
            first
                .map(|x| format!("{:.4}", x.damping))
                .unwrap_or_else(|| "-".into()),
            first
                .map(|x| format!("{:.3e}", x.magnitude))
                .unwrap_or_else(|| "-".into()),
            if second.is_finite() {
                format!("{second:.1}")
            } else {
                "-".into()
            },
        ]);
    }
    let _ = write!(text, "{}", t.render());
    let _ = match &r.excitation_check {
        Some(p) => {
            let c = &p.check;
            writeln!(text,
                "dynamics check: first resonance {:.1} Hz vs highest spindle excitation {:.2} Hz ({} harmonics of {:.1} rpm: {:.1} m/min on R = {} mm, velocities {}): ratio {:.1} -> {}",
                c.first_resonance_hz,
                c.max_excitation_hz,
                c.harmonics,
                c.max_spindle_rpm,
                p.velocity_max_m_per_min,
                p.track_radius_mm,
                p.velocities,
                c.ratio,
                if c.pass { "PASS (at least an order of magnitude)" } else { "FAIL (less than an order of magnitude)" }
            )
        }
        None => writeln!(
            text,
            "dynamics check: none (no track radius or velocities stated: give them as flags or in the study's [plan])"
        ),
    };
    text
}

/// The restart loop's outcome: convergence, the final μ per window, the files.
pub fn coupling(r: &CouplingResult, tol: f64, work: &Path) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "{} after {} cycles (tolerance {})",
        if r.converged {
            "converged"
        } else {
            "NOT converged"
        },
        r.cycles,
        tol
    );
    for ((name, mu), h) in r
        .final_mu
        .iter()
        .zip(r.history.iter().filter(|h| h.cycle == r.cycles))
    {
        let _ = writeln!(
            text,
            "  {name}: p = {:.2} MPa, v = {:.3} m/min, mu = {:.4} (engine applied {:.4})",
            h.pressure_mpa, h.velocity_m_per_min, mu, h.shear_ratio
        );
    }
    let _ = writeln!(
        text,
        "history: {}, plot: {}",
        work.join("history.csv").display(),
        work.join("mu_history.svg").display()
    );
    text
}
