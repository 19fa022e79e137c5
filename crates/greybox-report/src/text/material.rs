//! Plain text of the material stage: a Johnson–Cook fit and a rate sensitivity C found by
//! simulated cuts.

use greybox_material::fit::JcFit;
use greybox_sim::cut_run::RateSensitivityFit;
use std::fmt::Write as _;

/// A Johnson–Cook fit with its residuals per temperature.
pub fn johnson_cook(f: &JcFit) -> String {
    let mut text = String::new();
    let p = &f.params;
    let _ = writeln!(text,
        "Johnson-Cook: A = {:.1} MPa, B = {:.1} MPa, n = {:.4}, m = {:.4} (C = {} fixed, ε̇₀ = {:.3e} 1/s, T_room = {:.1} °C, T_m = {:.0} K)",
        p.a_pa * 1e-6,
        p.b_pa * 1e-6,
        p.n,
        p.m,
        p.c,
        p.ref_strain_rate,
        p.room_temperature_k - 273.15,
        p.melt_temperature_k
    );
    let _ = writeln!(
        text,
        "  residual RMS {:.2} MPa ({:.2} %), {} evaluations",
        f.rms_mpa,
        100.0 * f.relative_rms,
        f.evaluations
    );
    let _ = writeln!(text, "  temperature °C  points  RMS MPa  RMS %  bias %");
    for t in &f.by_temperature {
        let _ = writeln!(
            text,
            "  {:>14.0}  {:>6}  {:>7.2}  {:>5.2}  {:>+6.2}{}",
            t.temperature_c,
            t.points,
            t.rms_mpa,
            100.0 * t.relative_rms,
            100.0 * t.relative_bias,
            if t.flagged { "  <- misfit" } else { "" }
        );
    }
    for w in &f.warnings {
        let _ = writeln!(text, "warning: {w}");
    }
    text
}

/// The rate sensitivity C found, with every simulated run.
pub fn rate_sensitivity(r: &RateSensitivityFit) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "C = {:.5}: simulated cutting force within {:.2} N/mm of the measured {:.1} N/mm after {} runs",
        r.c,
        r.residual_n_per_m * 1e-3,
        r.measured_force_n_per_m * 1e-3,
        r.runs.len()
    );
    for (c, f) in &r.runs {
        let _ = writeln!(text, "  C = {c:.5}: F'c = {:.2} N/mm", f * 1e-3);
    }
    text
}
