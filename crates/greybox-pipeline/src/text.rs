//! Plain-text reports of each stage's results (what the command line prints), and the
//! table they are laid out in.

use crate::characterize::CharacterizeReport;
use crate::demo::{Demo, DemoSummary, DEMO_SHEAR_CAP_MPA};
use crate::identify::{inspect_text, summary_table, IdentifySummary};
use crate::plan::PlanSummary;
use crate::simulate::CutSummary;
use crate::synth::SynthSummary;
use anyhow::Result;
use greybox_material::fit::JcFit;
use greybox_tribo::ploughing::Correction;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A plain-text table with right-aligned columns.
///
/// ```
/// let mut t = greybox_pipeline::text::Table::new(&["pin", "COF"]);
/// t.row(vec!["1".into(), "0.3124".into()]);
/// assert_eq!(t.render(), "pin     COF\n---  ------\n  1  0.3124\n");
/// ```
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column headers.
    pub fn new(header: &[&str]) -> Self {
        Table {
            header: header.iter().map(|s| s.to_string()).collect(),
            rows: Vec::new(),
        }
    }
    /// Append a row (one cell per column).
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }
    /// The header, a rule and the rows, each line ending in `\n`.
    pub fn render(&self) -> String {
        let n = self.header.len();
        let mut width = vec![0; n];
        for r in std::iter::once(&self.header).chain(&self.rows) {
            for (w, c) in width.iter_mut().zip(r) {
                *w = (*w).max(c.chars().count());
            }
        }
        let line = |r: &Vec<String>| -> String {
            r.iter()
                .zip(&width)
                .map(|(c, w)| format!("{c:>w$}"))
                .collect::<Vec<_>>()
                .join("  ")
        };
        let mut s = line(&self.header);
        s.push('\n');
        s.push_str(
            &width
                .iter()
                .map(|w| "-".repeat(*w))
                .collect::<Vec<_>>()
                .join("  "),
        );
        s.push('\n');
        for r in &self.rows {
            s.push_str(&line(r));
            s.push('\n');
        }
        s
    }
}

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
        None => writeln!(text, "dynamics check: no plan given (--study or --track-radius-mm)"),
    };
    text
}

/// Prints a flow-curve fit.
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

/// Prints the summary of a cut.
/// A cut: speed of the run, friction windows, forces, chip measures.
pub fn cut(s: &CutSummary) -> String {
    let mut text = String::new();
    let _ = writeln!(text,
        "{} particles, {} steps (dt {:.3e} s, mass scaling {}), {:.3} mm of cut in {:.1} s: {:.3e} particle-steps/s ({:.3e} per core, {} threads)",
        s.particles, s.steps, s.dt_s, s.mass_scaling, s.simulated_cut_length_mm, s.wall_s, s.particle_steps_per_s, s.particle_steps_per_s_per_core, s.threads
    );
    let _ = writeln!(
        text,
        "  friction: {}; {} windows, {} window updates",
        s.law, s.windows, s.window_updates
    );
    let when = match s.steady_from_mm {
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
        "  chip thickness {}, compression ratio {}, shear angle {}, contact length {}, max temperature {:.0} °C",
        opt(m.chip_thickness_mm, " mm"),
        opt(m.compression_ratio, ""),
        opt(m.shear_angle_deg, "°"),
        opt(m.contact_length_mm, " mm"),
        m.max_temperature_c
    );
    text
}

/// The demo stage by stage, with the paths of its outputs under `out` (where the demo's
/// directory is).
pub fn demo(demo: &Demo, out: &Path) -> Result<String> {
    let mut text = String::new();
    let shown = |p: &Path| -> PathBuf { out.join(p) };
    let p = &demo.paths;
    let (rec_dir, dataset, foreign_dir, law_path, wear_path, couple_dir, curves) = (
        shown(&p.recordings),
        shown(&p.dataset),
        shown(&p.foreign_rig),
        shown(&p.law),
        shown(&p.wear_tests),
        shown(&p.couple),
        shown(&p.flow_curves),
    );
    let adhesive_out = shown(&p.dataset_adhesive);
    let cut_dir = shown(&p.cutting);
    let DemoSummary {
        plan: plan_summary,
        synth: synth_,
        identify,
        correction: correction_,
        fit,
        fit_outputs,
        dynamics,
        wear_tests,
        coupling,
        material,
        cutting,
        ..
    } = &demo.summary;
    let mut identify = identify.clone();
    identify.dataset = shown(Path::new(&identify.dataset)).display().to_string();
    let models: Vec<String> = fit_outputs
        .models
        .iter()
        .map(|m| shown(Path::new(m)).display().to_string())
        .collect();
    let plots: Vec<String> = fit_outputs
        .plots
        .iter()
        .map(|m| shown(Path::new(m)).display().to_string())
        .collect();
    let _ = writeln!(
        text,
        "greybox demo — the seed article's tribometer campaign on a virtual rig\n"
    );
    let _ = writeln!(
        text,
        "[0/6] rig dynamics: virtual impact-hammer tests at 500, 1000, 2000 N -> {}",
        out.join("characterize").display()
    );
    text.push_str(&characterize(dynamics));
    let _ = writeln!(text);
    let _ = writeln!(text, "[1/6] plan -> {}", out.join("plan").display());
    text.push_str(&plan(plan_summary));
    let _ = writeln!(text, "\n[2/6] synth -> {}", rec_dir.display());
    text.push_str(&synth(synth_));
    let _ = writeln!(
        text,
        "\n[3/6] identify (TDMS recordings) -> {}",
        dataset.display()
    );
    let _ = write!(text, "{}", summary_table(&demo.dataset));
    text.push_str(&identify_footer(&identify));
    let _ = writeln!(
        text,
        "\n[3b] identify a foreign rig's export (rotary tribometer CSV, no plan) -> {}",
        foreign_dir.join("dataset.csv").display()
    );
    let _ = write!(text, "{}", inspect_text(&demo.foreign_files));
    let _ = writeln!(
        text,
        "  against its ground truth: max |COF - COF_true| = {:.5} over {} steps",
        demo.foreign_error.max_abs_error, demo.foreign_error.plateaus
    );
    let _ =
        writeln!(text,
        "\n[4/6] adhesive COF (Bowden-Tabor ploughing, the article's Table 3 track widths) -> {}",
        adhesive_out.display()
    );
    text.push_str(&correction(correction_));
    let _ = writeln!(
        text,
        "\n[5/6] fit: the article's four model families and grids on cof_adhesive -> {}",
        out.join("fit").display()
    );
    let _ = writeln!(text, "{}", greybox_learn::protocol::markdown(fit));
    let _ = writeln!(text, "models: {}", models.join(", "));
    let _ = writeln!(text, "plots:  {}", plots.join(", "));
    let _ = writeln!(text, "\n[6/6] grey-box law ({} inside its training domain, fitted power law outside, Zorev cap {DEMO_SHEAR_CAP_MPA} MPa) -> {}", demo.law_family, law_path.display());
    let _ = writeln!(text, "{}", demo.export_line);
    let _ = writeln!(
        text,
        "C ABI for user routines: {} and {} (library: cargo build --release -p greybox-ffi)",
        out.join("ffi/greybox.h").display(),
        out.join("ffi/greybox.f90").display()
    );
    let _ = writeln!(
        text,
        "\nwear (the article's pin tests, {}): implied volumes V = k F s and k back from V",
        wear_path.display()
    );
    for w in wear_tests {
        let v = w.implied_volume_mm3();
        let k_back = greybox_tribo::wear::archard_k(v, w.normal_force_n, w.distance_m())? * 1e7;
        let _ = writeln!(
            text,
            "  {}: {} N, {} m/min, {} s -> s = {:.1} m, V = {:.3e} mm3, k = {:.2}e-7 mm3/(N m)",
            w.pin,
            w.normal_force_n,
            w.velocity_m_per_min,
            w.duration_s,
            w.distance_m(),
            v,
            k_back
        );
    }
    match &coupling {
        Some(r) => {
            let _ = writeln!(text,
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
            let _ = writeln!(text,
            "\ncoupling: example deck written to {} (install calculix-ccx to run it: greybox couple --deck {}/model.inp --segment {}/segment.inp --law {}/law.json)",
            couple_dir.display(),
            couple_dir.display(),
            couple_dir.display(),
            couple_dir.display()
        );
        }
    }
    let _ = writeln!(text,
        "\nmaterial: Johnson-Cook A, B, n, m from virtual compression curves at 25-1027 °C ({}; truth: the article's Table 4, 1 % noise, 12 % dynamic strain ageing at 359 °C)",
        curves.display()
    );
    text.push_str(&johnson_cook(material));
    let _ = writeln!(text,
        "\ncutting: AISI 1045, 150 m/min, h = 0.1 mm, grey-box law in friction windows along the tool -> {}",
        cut_dir.display()
    );
    text.push_str(&cut(cutting));
    let _ = writeln!(text,
        "  contact profile along the rake face (pressure, sliding velocity, temperature, mu, shear stress): {}",
        cut_dir.join("contact_profile.csv").display()
    );
    Ok(text)
}
