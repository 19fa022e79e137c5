//! `greybox demo`: the whole pipeline on the bundled example study
//! ([`greybox_pipeline::demo`]), printed stage by stage.

use crate::output::print_json;
use crate::{
    cmd_adhesive, cmd_characterize, cmd_identify, cmd_material, cmd_plan, cmd_simulate, cmd_synth,
};
use anyhow::Result;
use greybox_pipeline::demo::{DemoSummary, DEMO_SHEAR_CAP_MPA};
use greybox_pipeline::identify::{inspect_text, summary_table};
use std::path::{Path, PathBuf};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Output directory.
    #[arg(long, default_value = "demo-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once the demo is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
    /// Print the result as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: Args) -> Result<()> {
    let demo = greybox_pipeline::demo::run(&a.out, a.force)?;
    let shown = |p: &Path| -> PathBuf { a.out.join(p) };
    if a.json {
        return print_json(&serde_json::to_value(&demo.summary)?);
    }
    let out = a.out.as_path();
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
        synth,
        identify,
        correction,
        fit,
        fit_outputs,
        dynamics,
        wear_tests,
        coupling,
        material,
        cutting,
        ..
    } = demo.summary;
    let mut identify = identify;
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
    println!("greybox demo — the seed article's tribometer campaign on a virtual rig\n");
    println!(
        "[0/6] rig dynamics: virtual impact-hammer tests at 500, 1000, 2000 N -> {}",
        out.join("characterize").display()
    );
    cmd_characterize::print_report(&dynamics);
    println!();
    println!("[1/6] plan -> {}", out.join("plan").display());
    cmd_plan::print_summary(&plan_summary);
    println!("\n[2/6] synth -> {}", rec_dir.display());
    cmd_synth::print_summary(&synth);
    println!(
        "\n[3/6] identify (TDMS recordings) -> {}",
        dataset.display()
    );
    print!("{}", summary_table(&demo.dataset));
    cmd_identify::print_identify_footer(&identify);
    println!(
        "\n[3b] identify a foreign rig's export (rotary tribometer CSV, no plan) -> {}",
        foreign_dir.join("dataset.csv").display()
    );
    print!("{}", inspect_text(&demo.foreign_files));
    println!(
        "  against its ground truth: max |COF - COF_true| = {:.5} over {} steps",
        demo.foreign_error.max_abs_error, demo.foreign_error.plateaus
    );
    println!(
        "\n[4/6] adhesive COF (Bowden-Tabor ploughing, the article's Table 3 track widths) -> {}",
        adhesive_out.display()
    );
    cmd_adhesive::print_correction(&correction);
    println!(
        "\n[5/6] fit: the article's four model families and grids on cof_adhesive -> {}",
        out.join("fit").display()
    );
    println!("{}", greybox_learn::protocol::markdown(&fit));
    println!("models: {}", models.join(", "));
    println!("plots:  {}", plots.join(", "));
    println!("\n[6/6] grey-box law ({} inside its training domain, fitted power law outside, Zorev cap {DEMO_SHEAR_CAP_MPA} MPa) -> {}", demo.law_family, law_path.display());
    println!("{}", demo.export_line);
    println!(
        "C ABI for user routines: {} and {} (library: cargo build --release -p greybox-ffi)",
        out.join("ffi/greybox.h").display(),
        out.join("ffi/greybox.f90").display()
    );
    println!(
        "\nwear (the article's pin tests, {}): implied volumes V = k F s and k back from V",
        wear_path.display()
    );
    for w in &wear_tests {
        let v = w.implied_volume_mm3();
        let k_back = greybox_tribo::wear::archard_k(v, w.normal_force_n, w.distance_m())? * 1e7;
        println!(
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
            println!(
                "\ncoupling with CalculiX ({}): the restart loop {} after {} cycles; final μ per window:",
                couple_dir.display(),
                if r.converged { "converged" } else { "did not converge" },
                r.cycles
            );
            for (w, mu) in &r.final_mu {
                println!("  {w}: {mu:.4}");
            }
        }
        None => println!(
            "\ncoupling: example deck written to {} (install calculix-ccx to run it: greybox couple --deck {}/model.inp --segment {}/segment.inp --law {}/law.json)",
            couple_dir.display(),
            couple_dir.display(),
            couple_dir.display(),
            couple_dir.display()
        ),
    }
    println!(
        "\nmaterial: Johnson-Cook A, B, n, m from virtual compression curves at 25-1027 °C ({}; truth: the article's Table 4, 1 % noise, 12 % dynamic strain ageing at 359 °C)",
        curves.display()
    );
    cmd_material::print_fit(&material);
    println!(
        "\ncutting: AISI 1045, 150 m/min, h = 0.1 mm, grey-box law in friction windows along the tool -> {}",
        cut_dir.display()
    );
    cmd_simulate::print_cut_summary(&cutting);
    println!(
        "  contact profile along the rake face (pressure, sliding velocity, temperature, mu, shear stress): {}",
        cut_dir.join("contact_profile.csv").display()
    );
    Ok(())
}
