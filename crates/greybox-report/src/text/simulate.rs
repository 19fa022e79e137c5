//! Plain text of the simulations: a cut (speed, forces, chip measures) and a pin run.

use greybox_pipeline::simulate::CutSummary;
use greybox_sim::pin::{PinResult, PinSetup};
use std::fmt::Write as _;

/// A cut: speed of the run, friction windows, forces, chip measures.
pub fn cut(s: &CutSummary) -> String {
    let mut text = String::new();
    let _ = writeln!(text,
        "{} particles, {} steps ({} idle before first contact; dt {:.3e} s, mass scaling {}), {:.3} mm of cut in {:.1} s: {:.3e} particle-steps/s ({:.3e} per core, {} threads)",
        s.particles, s.steps, s.idle_steps, s.dt_s, s.mass_scaling, s.simulated_cut_length_mm, s.wall_s, s.particle_steps_per_s, s.particle_steps_per_s_per_core, s.threads
    );
    if let Some(n) = s.chip_removed_particles {
        let _ = writeln!(
            text,
            "  chip break: {n} particles left the model above chip_break_height_m (their energy is in the balance)"
        );
    }
    if let Some(c) = &s.coarsened {
        let _ = writeln!(
            text,
            "  coarsening: {} refined particles merged away; the merges averaged out {:.3e} J/m, {:.3} % of the work (in the balance)",
            c.particles,
            c.energy_j_per_m,
            100.0 * c.share_of_work
        );
    }
    let _ = writeln!(
        text,
        "  friction: {}; {} windows, {} window updates",
        s.law, s.windows, s.window_updates
    );
    let c = &s.steady_criterion;
    let pm = |ci: Option<f64>| ci.map_or(String::new(), |h| format!(" ± {h:.1}"));
    let when = match (&s.steady_state, s.sure_at_mm) {
        (Some(st), Some(at)) if s.stopped_when_sure => format!(
            "steady from {:.3} mm of cut, sure at {at:.3} mm (F'c ±{:.1} %, F'f ±{:.1} % reached), run stopped there; {}",
            st.from_mm,
            100.0 * c.cutting_force_rel_ci95,
            100.0 * c.feed_force_rel_ci95,
            st.rests_on
        ),
        (Some(st), _) => format!("steady from {:.3} mm of cut; {}", st.from_mm, st.rests_on),
        (None, _) => format!("no steady stretch; mean from {:.3} mm of cut", s.averaged_from_mm),
    };
    // Says "95 % intervals" only where one is printed: a cut without a steady stretch (or
    // too short a one) has none, and its means say so.
    let intervals =
        if s.cutting_force_ci95_n_per_mm.is_some() || s.feed_force_ci95_n_per_mm.is_some() {
            "95 % intervals"
        } else {
            "no interval"
        };
    let _ = writeln!(text,
        "  cutting force {:.1}{} N/mm, feed force {:.1}{} N/mm ({intervals}; F_f/F_c = {:.3}, k_c = {:.0} N/mm²), {when}",
        s.cutting_force_n_per_mm, pm(s.cutting_force_ci95_n_per_mm), s.feed_force_n_per_mm, pm(s.feed_force_ci95_n_per_mm), s.force_ratio, s.specific_cutting_force_n_per_mm2
    );
    if let Some(st) = &s.steady_state {
        for (name, q) in [
            ("F'c", &st.cutting_force_n_per_mm),
            ("F'f", &st.feed_force_n_per_mm),
        ] {
            if let (true, Some(d), Some(h)) = (q.drifting(), q.drift, q.drift_ci95) {
                let _ = writeln!(text,
                    "  note: {name} drifts by {d:+.1} ± {h:.1} N/mm across the steady stretch (its batch means' line): the cut has not settled, the mean is that of the stretch; a longer cut_length_m"
                );
            }
        }
        if let Some((true, Some(d), Some(h))) = st
            .contact_length_mm
            .as_ref()
            .map(|q| (q.drifting(), q.drift, q.drift_ci95))
        {
            let _ = writeln!(text,
                "  note: the tool–chip contact length drifts by {:+.1} ± {:.1} µm across the steady stretch: the contact has not settled and the forces follow it; a longer cut_length_m",
                1e3 * d, 1e3 * h
            );
        }
    }
    if s.short_stretch && s.steady {
        let _ = writeln!(text,
            "  note: the steady stretch spans fewer than {} renewals of the tool–chip contact: its intervals may understate the scatter (a longer cut_length_m)",
            c.min_contact_renewals
        );
    }
    if s.limit_reached {
        let _ = writeln!(text,
            "  note: the cut reached its length limit ({:.3} mm) before its intervals met the targets (F'c ±{:.1} %, F'f ±{:.1} %): raise cut_length_m to be as sure",
            s.simulated_cut_length_mm, 100.0 * c.cutting_force_rel_ci95, 100.0 * c.feed_force_rel_ci95
        );
    }
    if let Some(st) = &s.steady_state {
        let _ = writeln!(text, "  {}", steady_line(st));
    }
    text.push_str(&measure_lines(s));
    text
}

/// The chip's measures at the end, and what the material did there: how far damage went
/// (with `[material.damage]`) and whether the hottest particle passed the melting point.
fn measure_lines(s: &CutSummary) -> String {
    let mut text = String::new();
    let opt = |v: Option<f64>, unit: &str| v.map_or("n/a".to_string(), |v| format!("{v:.3}{unit}"));
    let m = &s.measures;
    let _ = writeln!(text,
        "  chip thickness {}, compression ratio {}, shear angle {}, contact length {}, max temperature {:.0} °C (peak over the run {:.0} °C)",
        opt(m.chip_thickness_mm, " mm"),
        opt(m.compression_ratio, ""),
        opt(m.shear_angle_deg, "°"),
        opt(m.contact_length_mm, " mm"),
        m.max_temperature_c,
        s.peak_temperature_c
    );
    if let Some(d) = &s.damage_at_end {
        let _ = writeln!(text,
            "  damage: initiated in {} of {} particles at the end (mean degradation there {:.3}, largest {:.3})",
            d.initiated, d.particles, d.mean_degradation, d.max_degradation
        );
    }
    if let Some(melt) = s.melt_temperature_c.filter(|&t| s.peak_temperature_c > t) {
        let _ = writeln!(text,
            "  note: the hottest particle passed the melting point ({melt:.0} °C); the flow stress is zero there and the model has no liquid phase (an adiabatic tool at high speed does this; docs/validation.md, \"Melting\")"
        );
    }
    text
}

/// The steady quantities besides the forces, each with its 95 % interval.
fn steady_line(st: &greybox_sim::steady_report::SteadyReport) -> String {
    use greybox_sim::steady_report::SteadyQuantity;
    let q = |name: &str, v: &Option<SteadyQuantity>, unit: &str, digits: usize| {
        v.as_ref().map(|q| {
            let ci = q
                .ci95
                .map_or(" (no interval)".to_string(), |h| format!(" ± {h:.digits$}"));
            format!("{name} {:.digits$}{ci}{unit}", q.mean)
        })
    };
    let parts: Vec<String> = [
        q("chip ratio", &st.compression_ratio, "", 3),
        q("chip extent/h", &st.extent_ratio, "", 3),
        q("contact length", &st.contact_length_mm, " mm", 3),
        q("rake peak T", &st.rake_peak_temperature_c, " °C", 0),
        q("rake mean T", &st.rake_mean_temperature_c, " °C", 0),
        q("segment pitch", &st.segment_pitch_mm, " mm", 4),
        q("degree of segmentation", &st.segmentation_degree, "", 3),
    ]
    .into_iter()
    .flatten()
    .collect();
    format!("steady: {}", parts.join(", "))
}

/// A pin run: force ratio, deformation share, forces, speed.
pub fn pin(setup: &PinSetup, res: &PinResult, speed_m_per_min: f64) -> String {
    let mut text = String::new();
    let _ = writeln!(text,
        "pin r = {} mm, depth {:.2} µm, μ = {}: F_t/F_N = {:.4} (deformation share {:.4}; analytic cylinder tan(θ/2) = {:.4})",
        setup.pin_radius_m * 1e3,
        setup.depth_m * 1e6,
        setup.mu,
        res.force_ratio,
        res.deformation_share,
        res.analytic_share
    );
    let _ = writeln!(text,
        "  F_N = {:.1} N/mm, F_t = {:.1} N/mm; {} particles, {} steps, {:.1} s wall ({:.2e} particle-steps/s), energy residual {:.2} %",
        res.normal_force_n_per_mm, res.tangential_force_n_per_mm, res.particles, res.steps, res.wall_s, res.particle_steps_per_s, 100.0 * res.energy_error
    );
    let _ = writeln!(
        text,
        "  simulated slide speed {:.1} m/s (strain rate scaled to {} m/min), mass scaling {}",
        res.simulated_speed_m_s, speed_m_per_min, res.mass_scaling
    );
    for u in &res.unusual {
        let _ = writeln!(text, "  unusual: {u}");
    }
    text
}
