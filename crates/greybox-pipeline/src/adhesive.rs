//! Stage 3: the ploughing correction μ_adh = μ_app − μ_plough, by the analytic
//! Bowden–Tabor model or by inverse pin-sliding simulation (the article's method).

pub use crate::adhesive_3d::Simulation3dOptions;
use crate::adhesive_loads::loads_to_simulate;
pub use crate::adhesive_loads::{LoadStride, SimLoads, SimRuns};
use crate::output::provenance;
use anyhow::{Context, Result};
use greybox_contact::hertz::ARTICLE_PIN_TIP_RADIUS_MM;
use greybox_contact::ploughing::{
    article_table3, correct_analytic, correct_with, Correction, TrackWidth, WidthLaw,
};
use greybox_core::dataset::FrictionDataset;
use greybox_core::outputs::check_file_output;
use greybox_sim::pin::{inverse_over_loads, PinSetup, ShareLaw};
use std::path::{Path, PathBuf};

/// How the ploughing share is found.
#[derive(Debug, Clone, PartialEq)]
pub enum AdhesiveMethod {
    /// Bowden–Tabor sphere ploughing with measured track widths.
    Analytic,
    /// Inverse pin-sliding simulation with the built-in SPH solver (the article's method).
    Simulation(SimulationOptions),
    /// The article's inverse route on a 3D model of the spherical pin on CalculiX.
    Simulation3d(Simulation3dOptions),
}

/// The inverse pin-sliding simulation of [`AdhesiveMethod::Simulation`].
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationOptions {
    /// Number of highest distinct loads simulated (the share is fitted against load and
    /// applied to all loads, as in the article).
    pub loads: SimLoads,
    /// Particle spacing, µm.
    pub spacing_um: f64,
    /// Slide length, mm.
    pub slide_mm: f64,
    /// Workpiece height, mm (the article's FE model: 1 mm).
    pub height_mm: f64,
    /// Stop when |simulated F_t/F_N − μ_app| ≤ this.
    pub tolerance: f64,
    /// Maximum runs per load.
    pub max_runs: SimRuns,
}

impl SimulationOptions {
    /// The defaults: the three highest loads, 10 µm particles, a 1.5 mm slide on the
    /// article's 1 mm workpiece, |Δμ| ≤ 0.002 in at most 5 runs per load.
    pub const DEFAULT: SimulationOptions = SimulationOptions {
        loads: SimLoads::of(3),
        spacing_um: 10.0,
        slide_mm: 1.5,
        height_mm: 1.0,
        tolerance: 0.002,
        max_runs: SimRuns::of(5),
    };
}

impl Default for SimulationOptions {
    fn default() -> Self {
        SimulationOptions::DEFAULT
    }
}

/// Options of [`adhesive`].
#[derive(Debug, Clone)]
pub struct AdhesiveOptions {
    /// Friction dataset CSV (from identification).
    pub data: PathBuf,
    pub method: AdhesiveMethod,
    /// Pin tip radius, mm.
    pub pin_radius_mm: f64,
    /// Measured track widths; with `track_widths_csv` empty too, the article's Table 3.
    pub track_widths: Vec<TrackWidth>,
    /// CSV of measured track widths (columns normal_force_N, track_width_um).
    pub track_widths_csv: Option<PathBuf>,
    /// Output dataset with the cof_adhesive column; the correction goes beside it
    /// ([`correction_path`]).
    pub out: PathBuf,
}

impl AdhesiveOptions {
    /// The analytic correction of `data` into `out` with the article's pin (17 mm) and
    /// track widths (Table 3).
    pub fn analytic(data: PathBuf, out: PathBuf) -> Self {
        AdhesiveOptions {
            data,
            method: AdhesiveMethod::Analytic,
            pin_radius_mm: ARTICLE_PIN_TIP_RADIUS_MM,
            track_widths: Vec::new(),
            track_widths_csv: None,
            out,
        }
    }
}

/// The measured track widths: those given, then those of the CSV, else the article's Table 3.
pub fn track_widths(a: &AdhesiveOptions) -> Result<Vec<TrackWidth>> {
    let mut w = a.track_widths.clone();
    if let Some(p) = &a.track_widths_csv {
        let mut rdr = greybox_core::input::data_csv(p, "track widths", &csv::ReaderBuilder::new())?;
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
    // each width and load against the physics table: a width of 0.8 µm (mm typed as µm)
    // is said, one of 1e300 refused
    for (k, t) in w.iter().enumerate() {
        use greybox_core::physics::{admit, Quantity};
        admit(
            Quantity::TrackWidth,
            greybox_core::units::um_to_m(t.width_um),
            &format!("adhesive track width {} (track_width_um, as m)", k + 1),
        )
        .and_then(|()| {
            admit(
                Quantity::NormalForce,
                t.normal_force_n,
                &format!("adhesive track width {} (normal_force_N)", k + 1),
            )
        })
        .map_err(anyhow::Error::msg)?;
    }
    Ok(w)
}

/// After a simulated correction, the analytic Bowden–Tabor correction of the same dataset
/// for comparison, as one line of text (`None` for an analytic correction).
pub fn analytic_beside(a: &AdhesiveOptions, data: &FrictionDataset) -> Result<Option<String>> {
    if a.method == AdhesiveMethod::Analytic {
        return Ok(None);
    }
    let mut twin = data.clone();
    let r = greybox_core::units::mm_to_m(a.pin_radius_mm);
    let bt = correct_analytic(&mut twin, r, &track_widths(a)?)?;
    Ok(Some(format!(
        "  analytic Bowden-Tabor (sphere) for comparison: mean reduction {:.2} %",
        bt.mean_reduction_percent
    )))
}

/// Apply the correction and write the dataset and the correction record.
pub fn adhesive(a: &AdhesiveOptions) -> Result<(FrictionDataset, Correction)> {
    if let AdhesiveMethod::Simulation3d(sim) = &a.method {
        crate::adhesive_3d::validate(sim)?;
    }
    let mut inputs = vec![("data", a.data.as_path())];
    if let Some(w) = &a.track_widths_csv {
        inputs.push(("track_widths_csv", w.as_path()));
    }
    check_file_output(&a.out, "out", &inputs)?;
    check_file_output(
        &correction_path(&a.out),
        "the correction record beside out",
        &inputs,
    )?;
    let mut ds = FrictionDataset::read_csv(&a.data)?;
    let corr = match &a.method {
        AdhesiveMethod::Analytic => {
            correct_analytic(&mut ds, a.pin_radius_mm * 1e-3, &track_widths(a)?)?
        }
        AdhesiveMethod::Simulation(sim) => correct_by_simulation(&mut ds, a, sim)?,
        AdhesiveMethod::Simulation3d(sim) => crate::adhesive_3d::correct(
            &mut ds,
            a.pin_radius_mm * 1e-3,
            &track_widths(a)?,
            &a.out,
            sim,
        )?,
    };
    // all three written in full before any is put in place, the provenance record first: a
    // full disk leaves none of them new, never a dataset without its record
    let correction = serde_json::to_string_pretty(&corr)?;
    let staged = vec![
        provenance(&inputs)?.stage_beside(&a.out)?,
        greybox_core::atomic::stage(&correction_path(&a.out), |w| {
            w.write_all(correction.as_bytes())
        })?,
        ds.stage_csv(&a.out)?,
    ];
    greybox_core::atomic::commit_together(staged)?;
    Ok((ds, corr))
}

/// The article's inverse step: simulate the highest loads, find μ_adh per load so that the
/// simulated F_t/F_N equals the mean measured μ_app, fit the deformation share against load
/// (power law) and subtract it at every load.
fn correct_by_simulation(
    ds: &mut FrictionDataset,
    a: &AdhesiveOptions,
    sim: &SimulationOptions,
) -> Result<Correction> {
    let r = a.pin_radius_mm * 1e-3;
    let measured = track_widths(a)?;
    let law = WidthLaw::fit(&measured)?;
    greybox_core::setting::positive("adhesive", "sim_tolerance", sim.tolerance)?;
    let loads = loads_to_simulate(ds, r, &law, sim.loads, LoadStride::of(1))?;
    let simulated: Vec<f64> = loads.iter().map(|l| l.0).collect();
    let mut base = PinSetup::article(loads[0].1, loads[0].2, sim.spacing_um * 1e-6);
    base.pin_radius_m = r;
    base.slide_length_m = sim.slide_mm * 1e-3;
    base.workpiece_height_m = sim.height_mm * 1e-3;
    // announced as a task (silent under --quiet and in library use); each pin run inside
    // reports its own steps
    let progress = greybox_core::progress::task(
        &format!(
            "ploughing share by simulation: {} load(s) ({} N), up to {} pin runs each",
            loads.len(),
            simulated
                .iter()
                .map(|f| format!("{f:.0}"))
                .collect::<Vec<_>>()
                .join(", "),
            sim.max_runs
        ),
        None,
        "loads",
    );
    let inv = inverse_over_loads(&base, &loads, sim.tolerance, sim.max_runs.get().max(2))?;
    progress.set(inv.len() as u64);
    progress.finish("done");
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
        sim.spacing_um,
        sim.slide_mm,
        share.a,
        share.b,
        runs.join("; ")
    );
    Ok(correct_with(ds, r, &measured, method, |f, _| {
        Ok(share.share(f))
    })?)
}

/// Where the correction record goes beside the corrected dataset `out`.
pub fn correction_path(out: &Path) -> PathBuf {
    out.with_extension("correction.json")
}
