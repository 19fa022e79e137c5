//! The article's inverse pin route on a 3D model of the spherical pin (CalculiX,
//! `greybox_couple::pin3d`): per simulated load, μ_adh with simulated F_t/F_N = μ_app at the
//! track depth of the measured widths; the deformation share fitted against load as a power
//! law and subtracted at every load, as in the plane-strain route.
//!
//! A load whose CalculiX runs do not converge (contact chatter at low loads, as the article
//! reports for its own) is named in the correction's method and `inverse.json` and left out
//! of the fit; the correction fails only when no load converges.
//!
//! The loads run in parallel (one CalculiX process per core). Each search starts from
//! μ_app − guess: the first two loads (the pilots) guess the Bowden–Tabor share of the
//! nominal track; the others scale it by the pilots' mean ratio of simulated to
//! Bowden–Tabor share, which saves about one run per load. The pilots are fixed, so the
//! result does not depend on the number of threads. Every run's deck, `.dat` and log stay
//! in `<out>.pin3d/load_<F>N/run_<k>/`, each load's force history of its returned run in
//! `<out>.pin3d/load_<F>N.csv`, and the searches in `<out>.pin3d/inverse.json`.

use crate::adhesive_loads::loads_to_simulate;
use crate::adhesive_loads::{LoadStride, SimLoads, SimRuns};
use anyhow::{bail, Result};
use greybox_contact::ploughing::{bowden_tabor_mu, correct_with, Correction, TrackWidth, WidthLaw};
use greybox_core::atomic::write_string_atomic;
use greybox_core::dataset::FrictionDataset;
use greybox_couple::pin3d::{find_adhesive_mu, Increments, Pin3dInverse, Pin3dSetup};
use greybox_sim::pin::ShareLaw;
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Loads searched first, with the analytic guess.
const PILOTS: usize = 2;

/// The inverse route of `AdhesiveMethod::Simulation3d`.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation3dOptions {
    /// Number of loads simulated, taken every `load_stride`-th distinct load from the highest
    /// (the article: six, every second load).
    pub loads: SimLoads,
    pub load_stride: LoadStride,
    /// Elements per nominal contact radius.
    pub elements_per_radius: f64,
    /// Slide length in nominal contact radii.
    pub slide_per_radius: f64,
    /// Slide increments.
    pub increments: Increments,
    /// Stop when |simulated F_t/F_N − μ_app| ≤ this.
    pub tolerance: f64,
    /// Maximum runs per load.
    pub max_runs: SimRuns,
    /// The CalculiX executable.
    pub ccx: PathBuf,
}

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
    /// NaN where the search failed.
    share_guess: f64,
    search: Option<&'a Pin3dInverse>,
    /// Why the search failed (the load is then left out of the fit).
    error: Option<&'a String>,
}

/// A simulated load: (normal force N, track depth m, mean μ_app).
type Load = (f64, f64, f64);

/// A load's search: (share guess, search), or why it failed.
type Outcome = std::result::Result<(f64, Pin3dInverse), String>;

/// The numeric options, the mesh they make included: checked before any input is read.
pub fn validate(sim: &Simulation3dOptions) -> Result<()> {
    for (v, field) in [
        (sim.tolerance, "sim_tolerance"),
        (sim.elements_per_radius, "sim3d_elements_per_radius"),
        (sim.slide_per_radius, "sim3d_slide_per_radius"),
    ] {
        greybox_core::setting::positive("adhesive", field, v)?;
    }
    // the mesh's size follows from the two ratios alone (not from the load's depth)
    let mut probe = Pin3dSetup::article(0.1e-3, 0.0);
    probe.elements_per_radius = sim.elements_per_radius;
    probe.slide_per_radius = sim.slide_per_radius;
    if let Err(e) = probe.mesh_spec().check_size() {
        let both = ["sim3d_elements_per_radius", "sim3d_slide_per_radius"];
        return Err(
            greybox_core::setting::refused_together("adhesive", &both, e.to_string()).into(),
        );
    }
    Ok(())
}

fn check(sim: &Simulation3dOptions) -> Result<()> {
    validate(sim)?;
    // a missing CalculiX is the user's set-up, not a load that failed to converge
    if let Err(e) = std::process::Command::new(&sim.ccx).arg("-v").output() {
        bail!(
            "adhesive.ccx: cannot start CalculiX '{}': {e} (Debian: apt install calculix-ccx)",
            sim.ccx.display()
        );
    }
    Ok(())
}

/// Each load's force history (`load_<F>N.csv`) and every search, converged or not
/// (`inverse.json`), into the runs directory.
fn write_searches(dir: &Path, loads: &[Load], all: &[Outcome]) -> Result<()> {
    let mut records = Vec::new();
    for (l, o) in loads.iter().zip(all) {
        if let Ok((_, inv)) = o {
            write_history(&dir.join(format!("load_{:.0}N.csv", l.0)), inv)?;
        }
        records.push(LoadRecord {
            normal_force_n: l.0,
            depth_um: l.1 * 1e6,
            share_guess: o.as_ref().map_or(f64::NAN, |x| x.0),
            search: o.as_ref().ok().map(|x| &x.1),
            error: o.as_ref().err(),
        });
    }
    write_string_atomic(
        &dir.join("inverse.json"),
        &serde_json::to_string_pretty(&records)?,
    )?;
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
/// `r` is the pin radius, m; `measured` the track widths; the runs go beside `out`.
pub fn correct(
    ds: &mut FrictionDataset,
    r: f64,
    measured: &[TrackWidth],
    out: &Path,
    sim: &Simulation3dOptions,
) -> Result<Correction> {
    check(sim)?;
    let law = WidthLaw::fit(measured)?;
    let loads = loads_to_simulate(ds, r, &law, sim.loads, sim.load_stride)?;
    let dir = runs_dir(out);
    let base = |depth: f64| {
        let mut s = Pin3dSetup::article(depth, 0.0);
        s.pin_radius_m = r;
        s.elements_per_radius = sim.elements_per_radius;
        s.slide_per_radius = sim.slide_per_radius;
        s.increments = sim.increments.get();
        s.ccx = sim.ccx.clone();
        s
    };
    let nominal = |f: f64| bowden_tabor_mu(r, law.width_um(f) * 1e-6);
    let all = search_loads(&loads, &nominal, &base, &dir, sim);
    let failed: Vec<&String> = all.iter().filter_map(|o| o.as_ref().err()).collect();
    let done: Vec<(&Load, &(f64, Pin3dInverse))> = loads
        .iter()
        .zip(&all)
        .filter_map(|(l, o)| Some((l, o.as_ref().ok()?)))
        .collect();
    if done.is_empty() {
        bail!(
            "3D pin: no simulated load converged: {}",
            failed
                .iter()
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    write_searches(&dir, &loads, &all)?;
    let share = ShareLaw::fit(
        &done
            .iter()
            .map(|(l, (_, i))| (l.0, i.deformation_share))
            .collect::<Vec<_>>(),
    )?;
    let runs = run_lines(&done, &failed);
    let method = format!(
        "simulation-3d: CalculiX half model of the spherical pin (r = {} mm, {} elements per contact radius, slide {} contact radii in {} increments), deformation share = {:.4e} F^{:.3}; {}",
        r * 1e3,
        sim.elements_per_radius,
        sim.slide_per_radius,
        sim.increments,
        share.a,
        share.b,
        runs.join("; ")
    );
    Ok(correct_with(ds, r, measured, method, |f, _| {
        Ok(share.share(f))
    })?)
}

/// Every load's inverse search, in order: the first [`PILOTS`] from the Bowden–Tabor
/// guess, the others from it scaled by the pilots' mean ratio of found share to guess.
fn search_loads(
    loads: &[Load],
    nominal: &(dyn Fn(f64) -> greybox_core::Result<f64> + Sync),
    base: &(dyn Fn(f64) -> Pin3dSetup + Sync),
    dir: &Path,
    sim: &Simulation3dOptions,
) -> Vec<Outcome> {
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
    // one load's search; a load whose runs do not converge is reported and left out of the
    // fit (as the article left out its low loads), an error only when no load converges
    let search = |&(f, depth, mu_app): &Load, factor: f64| -> Outcome {
        let guess = factor * nominal(f).map_err(|e| e.to_string())?;
        let d = dir.join(format!("load_{f:.0}N"));
        let inv = find_adhesive_mu(
            &base(depth),
            mu_app,
            guess,
            sim.tolerance,
            sim.max_runs.get(),
            &d,
        );
        progress.inc(1);
        inv.map(|i| (guess, i))
            .map_err(|e| format!("{f:.0} N: {e}"))
    };
    let split = PILOTS.min(loads.len());
    let pilots: Vec<Outcome> = loads[..split].par_iter().map(|l| search(l, 1.0)).collect();
    let ratios: Vec<f64> = loads
        .iter()
        .zip(&pilots)
        .filter_map(|(l, o)| Some(o.as_ref().ok()?.1.deformation_share / nominal(l.0).ok()?))
        .filter(|r| r.is_finite() && *r > 0.0)
        .collect();
    let factor = if ratios.is_empty() {
        1.0
    } else {
        ratios.iter().sum::<f64>() / ratios.len() as f64
    };
    let rest: Vec<Outcome> = loads[split..]
        .par_iter()
        .map(|l| search(l, factor))
        .collect();
    progress.finish("done");
    pilots.into_iter().chain(rest).collect()
}

/// One line per converged load (depth, μ_app → μ_adh, residual, runs), and one naming the
/// loads left out.
fn run_lines(done: &[(&Load, &(f64, Pin3dInverse))], failed: &[&String]) -> Vec<String> {
    let mut runs: Vec<String> = done
        .iter()
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
    if !failed.is_empty() {
        runs.push(format!(
            "not converged, left out of the fit: {}",
            failed
                .iter()
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join("; ")
        ));
    }
    runs
}
