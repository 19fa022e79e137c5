//! Plain text of the demo, stage by stage, with the paths of its outputs.

use super::campaign::{plan, synth};
use super::dynamics::characterize;
use super::friction::correction;
use super::identify::{identify_footer, inspect_text, summary_table};
use super::material::johnson_cook;
use super::simulate::cut;
use crate::demo::{Demo, DEMO_SHEAR_CAP_MPA};
use anyhow::Result;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

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
        demo.law_family.name(),
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
        let r = greybox_pipeline::wear::wear_test_row(w)?;
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
