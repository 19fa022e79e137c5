//! Plain-text reports of each stage's results (what the command line prints), and the
//! table they are laid out in.

use crate::bench::{IngestResult, PredictLatency, SurrogateSpeed};
use crate::characterize::CharacterizeReport;
use crate::demo::{Demo, DEMO_SHEAR_CAP_MPA};
use crate::fit::FitOutputs;
use crate::hertz::HertzRow;
use crate::identify::{inspect_text, summary_table, IdentifySummary};
use crate::plan::PlanSummary;
use crate::predict::PredictedPoint;
use crate::simulate::{CutCase, CutSummary};
use crate::synth::SynthSummary;
use crate::table::Table;
use crate::wear::{WearResult, WearTestRow};
use anyhow::Result;
use greybox_core::dataset::PressureConvention;
use greybox_core::units::PA_PER_GPA;
use greybox_couple::engine::CouplingResult;
use greybox_learn::protocol::FitReport;
use greybox_material::fit::JcFit;
use greybox_model::modelfile::ModelFile;
use greybox_sim::cut_run::RateSensitivityFit;
use greybox_sim::pin::{PinResult, PinSetup};
use greybox_tribo::ploughing::Correction;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A plan: pins, velocities, forces, spindle speeds, durations.
pub fn plan(s: &PlanSummary) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "plan: {} pins x {} velocities = {} plateaus",
        s.pins,
        s.steps / s.pins.max(1),
        s.steps
    );
    let _ = writeln!(
        text,
        "  normal forces {} N",
        s.normal_forces_n
            .iter()
            .map(|f| format!("{f:.1}"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        text,
        "  velocities {:.1}..{:.1} m/min -> spindle {:.2}..{:.2} rpm",
        s.velocity_min_m_per_min, s.velocity_max_m_per_min, s.spindle_rpm_min, s.spindle_rpm_max
    );
    let _ = writeln!(
        text,
        "  recording per pin {:.2} s, campaign {:.1} s",
        s.pin_duration_s, s.campaign_recording_s
    );
    text
}

/// What the virtual rig recorded.
pub fn synth(s: &SynthSummary) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "synth: {} pins, {} samples (seed {}), true COF {:.3}..{:.3}",
        s.pins, s.samples, s.seed, s.cof_true_min, s.cof_true_max
    );
    text
}

/// One line on an identification, and its error against a ground truth.
pub fn identify_footer(s: &IdentifySummary) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "identify: {} plateaus ({} non-stationary), pressure convention {}, dataset {}",
        s.plateaus, s.non_stationary, s.pressure_convention, s.dataset
    );
    // values outside their usual range (greybox_core::physics), with the likely unit mistake
    for f in &s.identification.files {
        for u in &f.unusual {
            let _ = writeln!(text, "  unusual: {}: {u}", f.source);
        }
    }
    if let Some(c) = &s.cycles {
        let _ = writeln!(
            text,
            "  reciprocating: per-cycle μ (forward, backward, mean) in {c}"
        );
    }
    if let Some(t) = &s.truth {
        let _ = writeln!(text,
            "  against the ground truth: max |COF - COF_true| = {:.5}, mean = {:.5} over {} plateaus",
            t.max_abs_error, t.mean_abs_error, t.plateaus
        );
    }
    text
}

/// The ploughing correction per load.
pub fn correction(c: &Correction) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "ploughing correction ({}), pin radius {} mm",
        c.method, c.pin_tip_radius_mm
    );
    let _ = writeln!(
        text,
        "  w(F) = {:.2} um * F^{:.4}",
        c.width_law.a_um, c.width_law.b
    );
    let mut t = Table::new(&["F_N [N]", "track width [um]", "depth [um]", "mu_plough"]);
    for l in &c.per_load {
        t.row(vec![
            format!("{:.1}", l.normal_force_n),
            format!("{:.0}", l.width_um),
            format!("{:.2}", l.depth_um),
            format!("{:.4}", l.mu_plough),
        ]);
    }
    let _ = write!(text, "{}", t.render());
    let _ = writeln!(
        text,
        "  mean reduction of the COF: {:.2} % (article: 7.29 % at its highest loads)",
        c.mean_reduction_percent
    );
    text
}

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
        Some(c) => writeln!(text,
            "dynamics check: first resonance {:.1} Hz vs highest spindle excitation {:.2} Hz ({} harmonics): ratio {:.1} -> {}",
            c.first_resonance_hz,
            c.max_excitation_hz,
            c.harmonics,
            c.ratio,
            if c.pass { "PASS (at least an order of magnitude)" } else { "FAIL (less than an order of magnitude)" }
        ),
        None => writeln!(text, "dynamics check: no plan given (a study with a [plan], or a track radius)"),
    };
    text
}

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

/// A cut: speed of the run, friction windows, forces, chip measures.
pub fn cut(s: &CutSummary) -> String {
    let mut text = String::new();
    let _ = writeln!(text,
        "{} particles, {} steps ({} idle before first contact; dt {:.3e} s, mass scaling {}), {:.3} mm of cut in {:.1} s: {:.3e} particle-steps/s ({:.3e} per core, {} threads)",
        s.particles, s.steps, s.idle_steps, s.dt_s, s.mass_scaling, s.simulated_cut_length_mm, s.wall_s, s.particle_steps_per_s, s.particle_steps_per_s_per_core, s.threads
    );
    let _ = writeln!(
        text,
        "  friction: {}; {} windows, {} window updates",
        s.law, s.windows, s.window_updates
    );
    let c = &s.steady_criterion;
    let when = match s.steady_from_mm {
        Some(mm) if s.stopped_when_steady => format!(
            "steady from {mm:.3} mm of cut (blocks within ±{:.0} %), run stopped there",
            100.0 * c.tolerance
        ),
        Some(mm) => format!("steady from {mm:.3} mm of cut"),
        None => format!("not steady; mean from {:.3} mm of cut", s.averaged_from_mm),
    };
    let _ = writeln!(text,
        "  cutting force {:.1} N/mm, feed force {:.1} N/mm (F_f/F_c = {:.3}, k_c = {:.0} N/mm²), {when}",
        s.cutting_force_n_per_mm, s.feed_force_n_per_mm, s.force_ratio, s.specific_cutting_force_n_per_mm2
    );
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
    if let Some(melt) = s.melt_temperature_c.filter(|&t| s.peak_temperature_c > t) {
        let _ = writeln!(text,
            "  note: the hottest particle passed the melting point ({melt:.0} °C); the flow stress is zero there and the model has no liquid phase (an adiabatic tool at high speed does this; docs/validation.md, \"Melting\")"
        );
    }
    text
}

/// The demo stage by stage, with the paths of its outputs under `out` (where the demo's
/// directory is).
pub fn demo(demo: &Demo, out: &Path) -> Result<String> {
    let mut text = String::new();
    demo_campaign(&mut text, demo, out);
    demo_law(&mut text, demo, out);
    demo_wear_and_coupling(&mut text, demo, out)?;
    demo_material_and_cut(&mut text, demo, out);
    Ok(text)
}

/// `p` (relative to the demo's directory) under `out`.
fn under(out: &Path, p: impl AsRef<Path>) -> PathBuf {
    out.join(p)
}

/// Rig dynamics, plan, recordings and their identification (also of the foreign rig).
fn demo_campaign(text: &mut String, demo: &Demo, out: &Path) {
    let (s, p) = (&demo.summary, &demo.paths);
    let mut identify = s.identify.clone();
    identify.dataset = under(out, &identify.dataset).display().to_string();
    let _ = writeln!(
        text,
        "greybox demo — the seed article's tribometer campaign on a virtual rig\n"
    );
    let _ = writeln!(
        text,
        "[0/6] rig dynamics: virtual impact-hammer tests at 500, 1000, 2000 N -> {}",
        out.join("characterize").display()
    );
    text.push_str(&characterize(&s.dynamics));
    let _ = writeln!(text);
    let _ = writeln!(text, "[1/6] plan -> {}", out.join("plan").display());
    text.push_str(&plan(&s.plan));
    let _ = writeln!(
        text,
        "\n[2/6] synth -> {}",
        under(out, &p.recordings).display()
    );
    text.push_str(&synth(&s.synth));
    let _ = writeln!(
        text,
        "\n[3/6] identify (TDMS recordings) -> {}",
        under(out, &p.dataset).display()
    );
    let _ = write!(text, "{}", summary_table(&demo.dataset));
    text.push_str(&identify_footer(&identify));
    let _ = writeln!(
        text,
        "\n[3b] identify a foreign rig's export (rotary tribometer CSV, no plan) -> {}",
        under(out, p.foreign_rig.join("dataset.csv")).display()
    );
    let _ = write!(text, "{}", inspect_text(&demo.foreign_files));
    let _ = writeln!(
        text,
        "  against its ground truth: max |COF - COF_true| = {:.5} over {} steps",
        demo.foreign_error.max_abs_error, demo.foreign_error.plateaus
    );
}

/// Ploughing correction, the fit, the grey-box law and its exports.
fn demo_law(text: &mut String, demo: &Demo, out: &Path) {
    let (s, p) = (&demo.summary, &demo.paths);
    let shown = |v: &[String]| -> String {
        v.iter()
            .map(|m| under(out, m).display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(
        text,
        "\n[4/6] adhesive COF (Bowden-Tabor ploughing, the article's Table 3 track widths) -> {}",
        under(out, &p.dataset_adhesive).display()
    );
    text.push_str(&correction(&s.correction));
    let _ = writeln!(
        text,
        "\n[5/6] fit: the article's four model families and grids on cof_adhesive -> {}",
        out.join("fit").display()
    );
    let _ = writeln!(text, "{}", greybox_learn::protocol::markdown(&s.fit));
    let _ = writeln!(text, "models: {}", shown(&s.fit_outputs.models));
    let _ = writeln!(text, "plots:  {}", shown(&s.fit_outputs.plots));
    let _ = writeln!(
        text,
        "\n[6/6] grey-box law ({} inside its training domain, fitted power law outside, Zorev cap {DEMO_SHEAR_CAP_MPA} MPa) -> {}",
        demo.law_family,
        under(out, &p.law).display()
    );
    let _ = writeln!(text, "{}", demo.export_line);
    let _ = writeln!(
        text,
        "C ABI for user routines: {} and {} (library: cargo build --release -p greybox-ffi)",
        out.join("ffi/greybox.h").display(),
        out.join("ffi/greybox.f90").display()
    );
}

/// The article's wear tests re-derived, and the CalculiX restart loop (or how to run it).
fn demo_wear_and_coupling(text: &mut String, demo: &Demo, out: &Path) -> Result<()> {
    let (s, p) = (&demo.summary, &demo.paths);
    let _ = writeln!(
        text,
        "\nwear (the article's pin tests, {}): implied volumes V = k F s and k back from V",
        under(out, &p.wear_tests).display()
    );
    for w in &s.wear_tests {
        let r = crate::wear::wear_test_row(w)?;
        let _ = writeln!(
            text,
            "  {}: {} N, {} m/min, {} s -> s = {:.1} m, V = {:.3e} mm3, k = {:.2}e-7 mm3/(N m)",
            w.pin,
            w.normal_force_n,
            w.velocity_m_per_min,
            w.duration_s,
            r.sliding_distance_m,
            r.implied_volume_mm3,
            r.k_back_1e_7
        );
    }
    let couple_dir = under(out, &p.couple);
    match &s.coupling {
        Some(r) => {
            let _ = writeln!(
                text,
                "\ncoupling with CalculiX ({}): the restart loop {} after {} cycles; final μ per window:",
                couple_dir.display(),
                if r.converged { "converged" } else { "did not converge" },
                r.cycles
            );
            for (w, mu) in &r.final_mu {
                let _ = writeln!(text, "  {w}: {mu:.4}");
            }
        }
        None => {
            let d = couple_dir.display();
            let _ = writeln!(
                text,
                "\ncoupling: example deck written to {d} (install calculix-ccx to run it: greybox couple --deck {d}/model.inp --segment {d}/segment.inp --law {d}/law.json)"
            );
        }
    }
    Ok(())
}

/// The Johnson–Cook fit and the cut with the grey-box law.
fn demo_material_and_cut(text: &mut String, demo: &Demo, out: &Path) {
    let (s, p) = (&demo.summary, &demo.paths);
    let _ = writeln!(
        text,
        "\nmaterial: Johnson-Cook A, B, n, m from virtual compression curves at 25-1027 °C ({}; truth: the article's Table 4, 1 % noise, 12 % dynamic strain ageing at 359 °C)",
        under(out, &p.flow_curves).display()
    );
    text.push_str(&johnson_cook(&s.material));
    let cut_dir = under(out, &p.cutting);
    let _ = writeln!(
        text,
        "\ncutting: AISI 1045, 150 m/min, h = 0.1 mm, grey-box law in friction windows along the tool -> {}",
        cut_dir.display()
    );
    text.push_str(&cut(&s.cutting));
    let _ = writeln!(
        text,
        "  contact profile along the rake face (pressure, sliding velocity, temperature, mu, shear stress): {}",
        cut_dir.join("contact_profile.csv").display()
    );
    let _ = writeln!(
        text,
        "  the chip: {} and {}, {} frames in {}",
        cut_dir.join("chip_temperature.svg").display(),
        cut_dir.join("chip_plastic_strain.svg").display(),
        crate::demo::DEMO_CHIP_FRAMES,
        cut_dir.join("frames").display()
    );
    let r = &s.report;
    let _ = writeln!(
        text,
        "
report: {} ({:.0} kB, {} sections, {} figures) — open it in a browser",
        r.path,
        r.bytes as f64 / 1e3,
        r.sections.len(),
        r.figures
    );
    for w in &r.warnings {
        let _ = writeln!(text, "  warning: {w}");
    }
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
    // A run that stopped at a steady force is complete; otherwise extrapolate the fraction.
    let (full, how) = match s.steady_from_mm {
        Some(mm) if case.setup.steady.stop_when_steady => (
            s.wall_s,
            format!(", stopped at a steady force that set in at {mm:.3} mm"),
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

/// The article's wear tests re-derived.
pub fn wear_tests(rows: &[WearTestRow]) -> String {
    let mut text = String::new();
    let mut tab = Table::new(&[
        "pin",
        "s [m]",
        "V = k F s [mm3]",
        "k from V [1e-7 mm3/(N m)]",
        "k article",
    ]);
    for r in rows {
        tab.row(vec![
            r.pin.clone(),
            format!("{:.2}", r.sliding_distance_m),
            format!("{:.4e}", r.implied_volume_mm3),
            format!("{:.2}", r.k_back_1e_7),
            format!("{:.2}", r.k_article_1e_7),
        ]);
    }
    let _ = write!(text, "{}", tab.render());
    text
}

/// A specific wear rate with its volume and scar.
pub fn wear(r: &WearResult) -> String {
    let mut text = String::new();
    let k = r.k_mm3_per_nm;
    let _ = writeln!(
        text,
        "wear volume {:.4e} mm3 ({}), sliding distance {:.2} m",
        r.volume_mm3, r.volume_source, r.sliding_distance_m
    );
    let _ = writeln!(
        text,
        "Archard specific wear rate k = V/(F s) = {:.4e} mm3/(N m) = {:.3} x 1e-7 mm3/(N m)",
        k,
        k * 1e7
    );
    if let Some(kd) = r.k_dimensionless {
        let _ = writeln!(text, "dimensionless K = k H = {kd:.4e}");
    }
    if let Some(sc) = &r.scar {
        let _ = writeln!(text,
            "scar: mean depth {:.2} um, max depth {:.2} um, {:.3} x {:.3} mm, {} points, {} holes ({} filled), surface noise {:.3} um",
            sc.mean_depth_um, sc.max_depth_um, sc.length_mm, sc.width_mm, sc.scar_points, sc.holes, sc.holes_filled, sc.noise_um
        );
    }
    text
}

/// Hertzian contact per normal force.
pub fn hertz(e_star_pa: f64, rows: &[HertzRow], convention: PressureConvention) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "E* = {:.1} GPa", e_star_pa / PA_PER_GPA);
    let mut t = Table::new(&[
        "F [N]",
        "a or b [mm]",
        "p0 [MPa]",
        "p_mean [MPa]",
        "approach [um]",
        &format!("{} [MPa]", convention.name()),
    ]);
    for r in rows {
        t.row(vec![
            format!("{}", r.force_n),
            format!("{:.5}", r.contact_half_width_mm),
            format!("{:.1}", r.max_pressure_mpa),
            format!("{:.1}", r.mean_pressure_mpa),
            r.approach_um
                .map(|d| format!("{d:.3}"))
                .unwrap_or_else(|| "-".into()),
            format!("{:.1}", r.convention_pressure_mpa),
        ]);
    }
    let _ = write!(text, "{}", t.render());
    text
}

/// Predictions with their intervals, one row per point.
pub fn predictions(m: &ModelFile, rows: &[PredictedPoint]) -> String {
    let mut text = String::new();
    let names: Vec<String> = m.features.iter().map(|f| f.name.clone()).collect();
    let mut head: Vec<&str> = names.iter().map(|s| s.as_str()).collect();
    let target = format!("{} ({})", m.target.name, m.family.name());
    let low = format!("{:.0} % low", m.prediction_interval.coverage * 100.0);
    let high = format!("{:.0} % high", m.prediction_interval.coverage * 100.0);
    head.extend([target.as_str(), low.as_str(), high.as_str(), "in domain"]);
    let mut t = Table::new(&head);
    for r in rows {
        let mut cells: Vec<String> = r.features.iter().map(|v| format!("{v}")).collect();
        cells.push(format!("{:.5}", r.prediction.value));
        cells.push(format!("{:.5}", r.prediction.low));
        cells.push(format!("{:.5}", r.prediction.high));
        cells.push(r.prediction.in_domain.to_string());
        t.row(cells);
    }
    let _ = write!(text, "{}", t.render());
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

/// The fit report (markdown tables), time per family and the files written.
pub fn fit(report: &FitReport, outputs: &FitOutputs) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "{}", greybox_learn::protocol::markdown(report));
    for f in &report.families {
        let _ = writeln!(text, "{}: {:.1} s", f.family.name(), f.seconds);
    }
    let _ = writeln!(
        text,
        "wrote {}, {}, {} models, {} plots",
        outputs.report_json,
        outputs.report_md,
        outputs.models.len(),
        outputs.plots.len()
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
