//! `greybox adhesive`: the ploughing correction μ_adh = μ_app − μ_plough.

use crate::output::{print_json, Table};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::dataset::FrictionDataset;
use greybox_core::outputs::check_file_output;
use greybox_sim::pin::{inverse_over_loads, PinSetup, ShareLaw};
use greybox_tribo::ploughing::{
    article_table3, correct_analytic, correct_with, track_depth, Correction, TrackWidth, WidthLaw,
};
use std::path::{Path, PathBuf};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Bowden–Tabor sphere ploughing with measured track widths.
    Analytic,
    /// Inverse pin-sliding simulation with the built-in SPH solver (the article's method).
    Simulation,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Friction dataset CSV from `greybox identify`.
    #[arg(long)]
    pub data: PathBuf,
    #[arg(long, value_enum, default_value_t = Method::Analytic)]
    pub method: Method,
    /// Pin tip radius, mm.
    #[arg(long = "pin-radius-mm", default_value_t = 17.0)]
    pub pin_radius_mm: f64,
    /// Measured track width as FORCE_N:WIDTH_um (repeatable); default: the article's Table 3.
    #[arg(long = "track-width")]
    pub track_width: Vec<String>,
    /// CSV of measured track widths with columns normal_force_N, track_width_um.
    #[arg(long = "track-widths-csv")]
    pub track_widths_csv: Option<PathBuf>,
    /// Output dataset with the cof_adhesive column (the correction goes beside it as .correction.json).
    #[arg(long, default_value = "dataset_adhesive.csv")]
    pub out: PathBuf,
    #[arg(long)]
    pub json: bool,
    /// Simulation: number of highest distinct loads simulated (the share is fitted against load
    /// and applied to all loads, as in the article).
    #[arg(long = "sim-loads", default_value_t = 3)]
    pub sim_loads: usize,
    /// Simulation: particle spacing, µm.
    #[arg(long = "sim-spacing-um", default_value_t = 10.0)]
    pub sim_spacing_um: f64,
    /// Simulation: slide length, mm.
    #[arg(long = "sim-slide-mm", default_value_t = 1.5)]
    pub sim_slide_mm: f64,
    /// Simulation: workpiece height, mm (the article's FE model: 1 mm).
    #[arg(long = "sim-height-mm", default_value_t = 1.0)]
    pub sim_height_mm: f64,
    /// Simulation: stop when |simulated F_t/F_N − μ_app| ≤ this.
    #[arg(long = "sim-tolerance", default_value_t = 0.002)]
    pub sim_tolerance: f64,
    /// Simulation: maximum runs per load.
    #[arg(long = "sim-max-runs", default_value_t = 5)]
    pub sim_max_runs: usize,
}

fn widths(a: &Args) -> Result<Vec<TrackWidth>> {
    let mut w = Vec::new();
    for t in &a.track_width {
        let (f, x) = t
            .split_once(':')
            .with_context(|| format!("--track-width '{t}': expected FORCE_N:WIDTH_um"))?;
        let parse = |s: &str| {
            s.trim()
                .parse::<f64>()
                .with_context(|| format!("--track-width '{t}': '{s}' is not a number"))
        };
        w.push(TrackWidth {
            normal_force_n: parse(f)?,
            width_um: parse(x)?,
        });
    }
    if let Some(p) = &a.track_widths_csv {
        let mut rdr =
            csv::Reader::from_path(p).with_context(|| format!("cannot read {}", p.display()))?;
        for (k, r) in rdr.deserialize::<TrackWidth>().enumerate() {
            w.push(r.with_context(|| {
                format!(
                    "{}, line {}: expected normal_force_N,track_width_um",
                    p.display(),
                    k + 2
                )
            })?);
        }
    }
    if w.is_empty() {
        w = article_table3();
    }
    Ok(w)
}

/// Apply the correction and write the dataset and the correction record.
pub fn adhesive(a: &Args) -> Result<(FrictionDataset, Correction)> {
    let mut inputs = vec![("--data", a.data.as_path())];
    if let Some(w) = &a.track_widths_csv {
        inputs.push(("--track-widths-csv", w.as_path()));
    }
    check_file_output(&a.out, "--out", &inputs)?;
    check_file_output(
        &correction_path(&a.out),
        "the correction record beside --out",
        &inputs,
    )?;
    let mut ds = FrictionDataset::read_csv(&a.data)?;
    let corr = match a.method {
        Method::Analytic => correct_analytic(&mut ds, a.pin_radius_mm * 1e-3, &widths(a)?)?,
        Method::Simulation => correct_by_simulation(&mut ds, a)?,
    };
    ds.write_csv(&a.out)?;
    write_string_atomic(
        &correction_path(&a.out),
        &serde_json::to_string_pretty(&corr)?,
    )?;
    crate::output::provenance(&inputs)?.write_beside(&a.out)?;
    Ok((ds, corr))
}

/// The article's inverse step: simulate the highest loads, find μ_adh per load so that the
/// simulated F_t/F_N equals the mean measured μ_app, fit the deformation share against load
/// (power law) and subtract it at every load.
fn correct_by_simulation(ds: &mut FrictionDataset, a: &Args) -> Result<Correction> {
    let r = a.pin_radius_mm * 1e-3;
    let measured = widths(a)?;
    let law = WidthLaw::fit(&measured)?;
    let mut forces: Vec<f64> = ds.records.iter().map(|r| r.normal_force_n).collect();
    forces.sort_by(f64::total_cmp);
    forces.dedup();
    if a.sim_loads == 0 {
        bail!("--sim-loads must be at least 1");
    }
    if !(a.sim_tolerance > 0.0 && a.sim_tolerance.is_finite()) {
        bail!(
            "--sim-tolerance: expected a positive number, got {}",
            a.sim_tolerance
        );
    }
    let simulated: Vec<f64> = forces.iter().rev().take(a.sim_loads).copied().collect();
    let mut loads = Vec::new();
    for &f in &simulated {
        let rows: Vec<f64> = ds
            .records
            .iter()
            .filter(|x| x.normal_force_n == f)
            .map(|x| x.cof_apparent)
            .collect();
        let mu_app = rows.iter().sum::<f64>() / rows.len() as f64;
        let depth = track_depth(r, law.width_um(f) * 1e-6)?;
        loads.push((f, depth, mu_app));
    }
    let mut base = PinSetup::article(loads[0].1, loads[0].2, a.sim_spacing_um * 1e-6);
    base.pin_radius_m = r;
    base.slide_length_m = a.sim_slide_mm * 1e-3;
    base.workpiece_height_m = a.sim_height_mm * 1e-3;
    eprintln!(
        "simulating {} load(s) ({} N) with up to {} pin runs each ...",
        loads.len(),
        simulated
            .iter()
            .map(|f| format!("{f:.0}"))
            .collect::<Vec<_>>()
            .join(", "),
        a.sim_max_runs
    );
    let inv = inverse_over_loads(&base, &loads, a.sim_tolerance, a.sim_max_runs.max(2))?;
    let share = ShareLaw::fit(
        &inv.iter()
            .map(|l| (l.normal_force_n, l.result.deformation_share))
            .collect::<Vec<_>>(),
    )?;
    let runs: Vec<String> = inv
        .iter()
        .map(|l| {
            format!(
                "{:.0} N: depth {:.1} um, mu_app {:.4} -> mu_adh {:.4} (residual {:.4}, {} runs)",
                l.normal_force_n,
                l.result.depth_m * 1e6,
                l.result.mu_apparent,
                l.result.mu_adhesive,
                l.result.residual,
                l.result.runs.len()
            )
        })
        .collect();
    let method = format!(
        "simulation: plane-strain SPH pin (r = {} mm, spacing {} um, slide {} mm), deformation share = {:.4e} F^{:.3}; {}",
        a.pin_radius_mm,
        a.sim_spacing_um,
        a.sim_slide_mm,
        share.a,
        share.b,
        runs.join("; ")
    );
    Ok(correct_with(ds, r, &measured, method, |f, _| {
        Ok(share.share(f))
    })?)
}

pub fn correction_path(out: &Path) -> PathBuf {
    out.with_extension("correction.json")
}

pub fn print_correction(c: &Correction) {
    println!(
        "ploughing correction ({}), pin radius {} mm",
        c.method, c.pin_tip_radius_mm
    );
    println!(
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
    print!("{}", t.render());
    println!(
        "  mean reduction of the COF: {:.2} % (article: 7.29 % at its highest loads)",
        c.mean_reduction_percent
    );
}

pub fn run(a: Args) -> Result<()> {
    let (ds, c) = adhesive(&a)?;
    if a.json {
        return print_json(&c);
    }
    print_correction(&c);
    if a.method == Method::Simulation {
        // The analytic Bowden–Tabor correction beside it, for comparison.
        let mut twin = ds.clone();
        let bt = correct_analytic(&mut twin, a.pin_radius_mm * 1e-3, &widths(&a)?)?;
        println!(
            "  analytic Bowden-Tabor (sphere) for comparison: mean reduction {:.2} %",
            bt.mean_reduction_percent
        );
    }
    println!(
        "wrote {} and {}",
        a.out.display(),
        correction_path(&a.out).display()
    );
    Ok(())
}
