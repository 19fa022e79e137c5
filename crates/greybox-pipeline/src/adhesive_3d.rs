//! The article's inverse pin route on a 3D model of the spherical pin (CalculiX,
//! `greybox_couple::pin3d`): per simulated load, μ_adh with simulated F_t/F_N = μ_app at the
//! track depth of the measured widths; the deformation share fitted against load as a power
//! law and subtracted at every load, as in the plane-strain route.
//!
//! The loads run in parallel (one CalculiX process per core). Each search starts from
//! μ_app − guess: the first two loads (the pilots) guess the Bowden–Tabor share of the
//! nominal track; the others scale it by the pilots' mean ratio of simulated to
//! Bowden–Tabor share, which saves about one run per load. The pilots are fixed, so the
//! result does not depend on the number of threads. Every run's deck, `.dat` and log stay
//! in `<out>.pin3d/load_<F>N/run_<k>/`, each load's force history of its returned run in
//! `<out>.pin3d/load_<F>N.csv`, and the searches in `<out>.pin3d/inverse.json`.

use crate::adhesive::{loads_to_simulate, track_widths, AdhesiveOptions, Simulation3dOptions};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::dataset::FrictionDataset;
use greybox_couple::pin3d::{find_adhesive_mu, Pin3dInverse, Pin3dSetup};
use greybox_sim::pin::ShareLaw;
use greybox_tribo::ploughing::{bowden_tabor_mu, correct_with, Correction, WidthLaw};
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Loads searched first, with the analytic guess.
const PILOTS: usize = 2;

/// The directory of the runs beside the corrected dataset `out`.
pub fn runs_dir(out: &Path) -> PathBuf {
    out.with_extension("pin3d")
}

/// One load's search, as written to `inverse.json`.
#[derive(Serialize)]
struct LoadRecord<'a> {
    #[serde(rename = "normal_force_N")]
    normal_force_n: f64,
    depth_um: f64,
    share_guess: f64,
    search: &'a Pin3dInverse,
}

fn check(sim: &Simulation3dOptions) -> Result<()> {
    if !(sim.tolerance > 0.0 && sim.tolerance.is_finite()) {
        bail!(
            "adhesive.sim_tolerance: expected a positive number, got {}",
            sim.tolerance
        );
    }
    if sim.load_stride == 0 {
        bail!("adhesive.sim3d_load_stride: must be at least 1");
    }
    if sim.max_runs == 0 {
        bail!("adhesive.sim_max_runs: must be at least 1");
    }
    Ok(())
}

fn write_history(path: &Path, inv: &Pin3dInverse) -> Result<()> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for s in &inv.result.history {
        w.serialize(s)?;
    }
    write_string_atomic(path, &String::from_utf8(w.into_inner()?)?)?;
    Ok(())
}

/// Fills `cof_adhesive` by the 3D inverse route and returns the correction record.
pub fn correct(
    ds: &mut FrictionDataset,
    a: &AdhesiveOptions,
    sim: &Simulation3dOptions,
) -> Result<Correction> {
    check(sim)?;
    let r = a.pin_radius_mm * 1e-3;
    let measured = track_widths(a)?;
    let law = WidthLaw::fit(&measured)?;
    let loads = loads_to_simulate(
        ds,
        r,
        &law,
        sim.loads,
        sim.load_stride,
        "adhesive.sim3d_loads",
    )?;
    let dir = runs_dir(&a.out);
    let base = |depth: f64| {
        let mut s = Pin3dSetup::article(depth, 0.0);
        s.pin_radius_m = r;
        s.elements_per_radius = sim.elements_per_radius;
        s.slide_per_radius = sim.slide_per_radius;
        s.increments = sim.increments;
        s.ccx = sim.ccx.clone();
        s
    };
    let nominal = |f: f64| bowden_tabor_mu(r, law.width_um(f) * 1e-6);
    let progress =
        greybox_core::progress::task(
            &format!(
            "ploughing share by 3D simulation (CalculiX): {} load(s) ({} N), up to {} runs each",
            loads.len(),
            loads.iter().map(|l| format!("{:.0}", l.0)).collect::<Vec<_>>().join(", "),
            sim.max_runs
        ),
            Some(loads.len() as u64),
            "loads",
        );
    let search = |&(f, depth, mu_app): &(f64, f64, f64),
                  factor: f64|
     -> Result<(f64, Pin3dInverse)> {
        let guess = factor * nominal(f)?;
        let d = dir.join(format!("load_{f:.0}N"));
        let inv = find_adhesive_mu(&base(depth), mu_app, guess, sim.tolerance, sim.max_runs, &d)
            .with_context(|| format!("3D pin at {f:.0} N"))?;
        progress.inc(1);
        Ok((guess, inv))
    };
    let split = PILOTS.min(loads.len());
    let pilots: Vec<(f64, Pin3dInverse)> = loads[..split]
        .par_iter()
        .map(|l| search(l, 1.0))
        .collect::<Result<_>>()?;
    let mut factor = 0.0;
    for (l, (_, inv)) in loads.iter().zip(&pilots) {
        factor += inv.deformation_share / nominal(l.0)? / split as f64;
    }
    let factor = if factor.is_finite() && factor > 0.0 {
        factor
    } else {
        1.0
    };
    let rest: Vec<(f64, Pin3dInverse)> = loads[split..]
        .par_iter()
        .map(|l| search(l, factor))
        .collect::<Result<_>>()?;
    progress.finish("done");
    let all: Vec<(f64, Pin3dInverse)> = pilots.into_iter().chain(rest).collect();
    let mut records = Vec::new();
    for (l, (guess, inv)) in loads.iter().zip(&all) {
        write_history(&dir.join(format!("load_{:.0}N.csv", l.0)), inv)?;
        records.push(LoadRecord {
            normal_force_n: l.0,
            depth_um: l.1 * 1e6,
            share_guess: *guess,
            search: inv,
        });
    }
    write_string_atomic(
        &dir.join("inverse.json"),
        &serde_json::to_string_pretty(&records)?,
    )?;
    let share = ShareLaw::fit(
        &loads
            .iter()
            .zip(&all)
            .map(|(l, (_, i))| (l.0, i.deformation_share))
            .collect::<Vec<_>>(),
    )?;
    let runs: Vec<String> = loads
        .iter()
        .zip(&all)
        .map(|(l, (_, i))| {
            format!(
                "{:.0} N: depth {:.1} um, mu_app {:.4} -> mu_adh {:.4} (residual {:.4}, {} runs)",
                l.0,
                l.1 * 1e6,
                i.mu_apparent,
                i.mu_adhesive,
                i.residual,
                i.runs.len()
            )
        })
        .collect();
    let method = format!(
        "simulation-3d: CalculiX half model of the spherical pin (r = {} mm, {} elements per contact radius, slide {} contact radii in {} increments), deformation share = {:.4e} F^{:.3}; {}",
        a.pin_radius_mm,
        sim.elements_per_radius,
        sim.slide_per_radius,
        sim.increments,
        share.a,
        share.b,
        runs.join("; ")
    );
    Ok(correct_with(ds, r, &measured, method, |f, _| {
        Ok(share.share(f))
    })?)
}
