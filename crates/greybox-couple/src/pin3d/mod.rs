//! The article's inverse pin route in 3D on CalculiX: a rigid sphere of the pin radius
//! pressed into an elastic-plastic disk to the track depth d = r − √(r² − (w/2)²) and slid
//! along it with a Coulomb μ; the simulated F_t/F_N exceeds μ by the ploughing share, and
//! the inverse search finds the μ_adh whose F_t/F_N equals the measured μ_app.
//!
//! **Model** (half model on the symmetry plane y = 0, [`mesh`], [`deck`]): eight-node bricks,
//! element size h = a / `elements_per_radius` over the band the contact sweeps (a the
//! nominal contact radius √(2rd − d²)), the disk `height` thick and clamped at its bottom.
//! The disk's flow curve is the material's, σ(ε_p) at the characteristic strain rate v/a of
//! the slide and the initial temperature (isothermal).
//!
//! **Quasi-static.** The analysis is static (implicit, no inertia): at the tribometer's speeds
//! the inertial stress ρv² is 0.05 MPa against GPa contact pressures. Its one discretisation
//! in time is the slide increment (at most slide/`increments`); halving it must not move
//! F_t by more than 2 % (checked in docs/simulator.md).
//!
//! **Measured** over the second half of the slide: F_t/F_N as mean F_t over mean F_N (like
//! the plane-strain route, `greybox_sim::pin`), and the contact area for the Bowden–Tabor
//! check on the contact the run has.

pub mod dat;
pub mod deck;
pub mod mesh;

use greybox_core::units;
use greybox_core::{Error, Result};
use greybox_material::Material;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The 3D pin run (SI units).
#[derive(Debug, Clone, PartialEq)]
pub struct Pin3dSetup {
    /// Pin tip radius r, m.
    pub pin_radius_m: f64,
    /// Depth d below the disk surface, m.
    pub depth_m: f64,
    /// Coulomb μ on the pin.
    pub mu: f64,
    /// Physical sliding speed, m/s (sets the strain rate v/a of the flow curve).
    pub sliding_speed_m_s: f64,
    /// Slide length in nominal contact radii.
    pub slide_per_radius: f64,
    /// Elements per nominal contact radius in the band.
    pub elements_per_radius: f64,
    /// Slide increments (each at most slide/increments).
    pub increments: usize,
    /// Disk thickness, m (the article's FE model: 1 mm).
    pub disk_height_m: f64,
    /// Disk temperature, K.
    pub temperature_k: f64,
    /// The disk; without plasticity it is elastic (the Hertz check).
    pub material: Material,
    /// The CalculiX executable.
    pub ccx: PathBuf,
}

/// Defaults of the numerical settings, also the CLI's.
pub const ELEMENTS_PER_RADIUS: f64 = 8.0;
/// Slide length in contact radii: F_t/F_N is steady within 0.5 % after about one radius.
pub const SLIDE_PER_RADIUS: f64 = 1.6;
/// Slide increments: F_t/F_N at the 1500 N track went 0.3103, 0.3079, 0.3068 at 16, 32 and
/// 64 (first order in the increment; F_t itself moved 0.5 %, then 0.0 %). 32 keeps six loads
/// within 30 min on 2 cores; 64 would take about twice the time of 16.
pub const INCREMENTS: usize = 32;
/// Slide increments of one run: each is a CalculiX increment (seconds to minutes).
pub type Increments = greybox_core::count::Count<1, 10_000>;

impl Pin3dSetup {
    /// The article's pin (r = 17 mm) on its AISI 1045 disk 1 mm thick at depth `depth_m`,
    /// 150 m/min, with the default resolution.
    pub fn article(depth_m: f64, mu: f64) -> Self {
        Pin3dSetup {
            pin_radius_m: 17e-3,
            depth_m,
            mu,
            sliding_speed_m_s: 150.0 / 60.0,
            slide_per_radius: SLIDE_PER_RADIUS,
            elements_per_radius: ELEMENTS_PER_RADIUS,
            increments: INCREMENTS,
            disk_height_m: 1e-3,
            temperature_k: 293.15,
            material: Material::aisi1045_article(),
            ccx: "ccx".into(),
        }
    }

    /// Nominal contact radius √(2 r d − d²), m.
    pub fn contact_radius_m(&self) -> f64 {
        (2.0 * self.pin_radius_m * self.depth_m - self.depth_m.powi(2)).sqrt()
    }

    /// The checks a run needs, each naming its field.
    pub fn validate(&self) -> Result<()> {
        let positive = |v: f64, what: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::invalid(
                    what,
                    format!("expected a positive number, got {v}"),
                ))
            }
        };
        positive(self.pin_radius_m, "pin3d.pin_radius")?;
        positive(self.depth_m, "pin3d.depth")?;
        positive(self.elements_per_radius, "pin3d.elements_per_radius")?;
        positive(self.disk_height_m, "pin3d.disk_height")?;
        positive(self.sliding_speed_m_s, "pin3d.sliding_speed")?;
        if self.depth_m >= 0.5 * self.pin_radius_m {
            return Err(Error::invalid(
                "pin3d.depth",
                "must be below half the pin radius",
            ));
        }
        if !(self.mu.is_finite() && self.mu >= 0.0) {
            return Err(Error::invalid(
                "pin3d.mu",
                format!("expected μ ≥ 0, got {}", self.mu),
            ));
        }
        if !(self.slide_per_radius.is_finite() && self.slide_per_radius >= 0.0) {
            return Err(Error::invalid(
                "pin3d.slide_per_radius",
                "expected a slide ≥ 0",
            ));
        }
        Increments::of_usize(self.increments, "pin3d.increments")
            .map_err(|e| Error::invalid("pin3d", e))?;
        self.mesh_spec()
            .check_size()
            .map_err(|e| Error::invalid("pin3d", e))?;
        self.material.validate()
    }

    /// The mesh in mm.
    pub fn mesh_spec(&self) -> mesh::MeshSpec {
        let a = self.contact_radius_m() * units::MM_PER_M;
        mesh::MeshSpec {
            pin_radius: self.pin_radius_m * units::MM_PER_M,
            contact_radius: a,
            element: a / self.elements_per_radius,
            slide: self.slide_per_radius * a,
            height: self.disk_height_m * units::MM_PER_M,
        }
    }

    /// The characteristic plastic strain rate of the slide, v/a, 1/s.
    pub fn strain_rate(&self) -> f64 {
        self.sliding_speed_m_s / self.contact_radius_m()
    }

    /// The deck's settings: the flow curve sampled at plastic strains 0–2 (MPa).
    pub fn deck_spec(&self) -> deck::DeckSpec {
        let m = self.mesh_spec();
        let strains = [
            0.0, 0.002, 0.005, 0.01, 0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0,
        ];
        let flow_curve = match &self.material.plasticity {
            Some(p) => strains
                .iter()
                .map(|&e| {
                    (
                        p.flow_stress(e, self.strain_rate(), self.temperature_k)
                            * units::MPA_PER_PA,
                        e,
                    )
                })
                .collect(),
            None => Vec::new(),
        };
        deck::DeckSpec {
            depth: self.depth_m * units::MM_PER_M,
            slide: m.slide,
            mu: self.mu,
            youngs_modulus: self.material.elastic.youngs_modulus_pa * units::MPA_PER_PA,
            poisson_ratio: self.material.elastic.poisson_ratio,
            flow_curve,
            element: m.element,
            increments: self.increments,
        }
    }
}

/// One sample of a run's force history (whole pin, both halves).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ForceSample {
    /// Slide so far, mm (0 during the press).
    pub slide_mm: f64,
    /// Pin depth so far, µm.
    pub depth_um: f64,
    #[serde(rename = "tangential_force_N")]
    pub tangential_force_n: f64,
    #[serde(rename = "normal_force_N")]
    pub normal_force_n: f64,
    /// Contact area, mm².
    pub contact_area_mm2: f64,
}

/// The result of one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pin3dResult {
    pub mu: f64,
    pub depth_m: f64,
    /// Mean F_t over mean F_N, second half of the slide.
    pub force_ratio: f64,
    /// Ploughing share F_t/F_N − μ.
    pub deformation_share: f64,
    /// Mean normal force and contact area over the same window (whole pin), N and mm².
    pub normal_force_n: f64,
    pub contact_area_mm2: f64,
    /// Bowden–Tabor for a sphere on the contact the run has: the front-half contact of area
    /// A = π a_c²/2 gives a_c, and μ_p = (2/π)[(r/a_c)² asin(a_c/r) − √((r/a_c)² − 1)].
    pub bowden_tabor_on_contact: f64,
    pub history: Vec<ForceSample>,
    pub elements: usize,
    pub wall_s: f64,
}

/// Bowden–Tabor sphere ploughing with contact radius `a` on a sphere of radius `r` (same
/// units): `greybox_contact::ploughing::bowden_tabor_mu` with the track width 2a.
pub fn bowden_tabor_sphere(r: f64, a: f64) -> f64 {
    greybox_contact::ploughing::bowden_tabor_mu(r, 2.0 * a.min(r)).unwrap_or(f64::NAN)
}

/// What CalculiX said about its failure: its first error with the lines after it, else the
/// end of its log.
fn log_tail(text: &str) -> String {
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let from = match lines.iter().position(|l| l.contains("*ERROR")) {
        Some(i) => i,
        None => lines.len().saturating_sub(6),
    };
    lines[from..(from + 6).min(lines.len())].join(" ")
}

/// Runs CalculiX on the deck in `dir` (created; the deck, `.dat` and log stay there).
pub fn simulate(setup: &Pin3dSetup, dir: &Path) -> Result<Pin3dResult> {
    setup.validate()?;
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let mesh = setup.mesh_spec().build();
    let spec = setup.deck_spec();
    let heading = format!(
        "greybox 3D pin: r {} mm, depth {} um, mu {}",
        setup.pin_radius_m * 1e3,
        setup.depth_m * 1e6,
        setup.mu
    );
    let inp = dir.join("pin.inp");
    greybox_core::atomic::write_string_atomic(&inp, &spec.write(&mesh, &heading))?;
    let started = std::time::Instant::now();
    let out = Command::new(&setup.ccx)
        .arg("-i")
        .arg("pin")
        .current_dir(dir)
        .env("OMP_NUM_THREADS", "1")
        .env("CCX_NPROC_EQUATION_SOLVER", "1")
        .output()
        .map_err(|e| {
            Error::invalid(
                "pin3d.ccx",
                format!("cannot start CalculiX '{}': {e}", setup.ccx.display()),
            )
        })?;
    let wall_s = started.elapsed().as_secs_f64();
    let log = String::from_utf8_lossy(&out.stdout).to_string();
    let log_path = dir.join("pin.log");
    greybox_core::atomic::write_string_atomic(&log_path, &log)?;
    let dat_path = dir.join("pin.dat");
    let text =
        greybox_core::input::read_data_text(&dat_path, "CalculiX results").unwrap_or_default();
    let incs = dat::parse(&text, &dat_path.display().to_string())?;
    let end = if spec.slide > 0.0 { 2.0 } else { 1.0 };
    let reached = incs.last().map_or(0.0, |i| i.time);
    if !out.status.success() || reached < end - 1e-9 || log.contains("*ERROR") {
        return Err(Error::invalid(
            "pin3d",
            format!(
                "CalculiX stopped at time {reached} of {end} (exit {}) in {}: {}",
                out.status,
                dir.display(),
                log_tail(&log)
            ),
        ));
    }
    let history: Vec<ForceSample> = incs
        .iter()
        .map(|i| ForceSample {
            slide_mm: (i.time - 1.0).max(0.0) * spec.slide,
            depth_um: i.time.min(1.0) * spec.depth * 1e3,
            tangential_force_n: 2.0 * i.force[0],
            normal_force_n: -2.0 * i.force[2],
            contact_area_mm2: 2.0 * i.contact_area,
        })
        .collect();
    let window: Vec<&ForceSample> = if spec.slide > 0.0 {
        history
            .iter()
            .filter(|s| s.slide_mm >= 0.5 * spec.slide)
            .collect()
    } else {
        history.last().into_iter().collect()
    };
    let mean =
        |f: fn(&ForceSample) -> f64| window.iter().map(|s| f(s)).sum::<f64>() / window.len() as f64;
    let (ft, fn_, area) = (
        mean(|s| s.tangential_force_n),
        mean(|s| s.normal_force_n),
        mean(|s| s.contact_area_mm2),
    );
    if fn_.is_nan() || fn_ <= 0.0 {
        return Err(Error::invalid(
            "pin3d",
            format!("the pin carried no normal load in {}", dir.display()),
        ));
    }
    let ratio = ft / fn_;
    let a_front = (2.0 * area / std::f64::consts::PI).sqrt();
    Ok(Pin3dResult {
        mu: setup.mu,
        depth_m: setup.depth_m,
        force_ratio: ratio,
        deformation_share: ratio - setup.mu,
        normal_force_n: fn_,
        contact_area_mm2: area,
        bowden_tabor_on_contact: if area > 0.0 {
            bowden_tabor_sphere(setup.pin_radius_m * 1e3, a_front)
        } else {
            f64::NAN
        },
        history,
        elements: mesh.disk_elements.len(),
        wall_s,
    })
}

/// The inverse search at one load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Pin3dInverse {
    pub mu_apparent: f64,
    pub mu_adhesive: f64,
    /// μ_app − μ_adh.
    pub deformation_share: f64,
    /// |simulated F_t/F_N − μ_app| of the returned μ's run.
    pub residual: f64,
    /// Every run: (μ, simulated F_t/F_N).
    pub runs: Vec<(f64, f64)>,
    /// The run at the returned μ.
    pub result: Pin3dResult,
}

/// Finds μ_adh with simulated F_t/F_N(μ_adh) = μ_app by Newton steps on
/// g(μ) = F_t/F_N(μ) − μ_app: the first with slope 1 (F_t/F_N = μ + share, the share
/// varying slowly with μ), then secant slopes clamped to [0.5, 2]. Starts at
/// μ_app − `share_guess`; stops at |g| ≤ `tol` or after `max_runs` runs (each in
/// `dir/run_N`), returning the best run.
pub fn find_adhesive_mu(
    base: &Pin3dSetup,
    mu_apparent: f64,
    share_guess: f64,
    tol: f64,
    max_runs: usize,
    dir: &Path,
) -> Result<Pin3dInverse> {
    let mut mu = (mu_apparent - share_guess).max(0.0);
    let mut runs: Vec<(f64, f64)> = Vec::new();
    let mut best: Option<Pin3dResult> = None;
    while runs.len() < max_runs.max(1) {
        let mut s = base.clone();
        s.mu = mu;
        let r = simulate(&s, &dir.join(format!("run_{}", runs.len() + 1)))?;
        let g = r.force_ratio - mu_apparent;
        runs.push((mu, r.force_ratio));
        if best
            .as_ref()
            .is_none_or(|b| g.abs() < (b.force_ratio - mu_apparent).abs())
        {
            best = Some(r);
        }
        if g.abs() <= tol {
            break;
        }
        let slope = match runs.len() {
            n if n >= 2 => {
                let ((m0, r0), (m1, r1)) = (runs[n - 2], runs[n - 1]);
                if (m1 - m0).abs() > 1e-12 {
                    ((r1 - r0) / (m1 - m0)).clamp(0.5, 2.0)
                } else {
                    1.0
                }
            }
            _ => 1.0,
        };
        let next = (mu - g / slope).max(0.0);
        if next == mu {
            break; // μ = 0 and still above μ_app: ploughing alone exceeds it
        }
        mu = next;
    }
    let result = best.ok_or_else(|| Error::invalid("pin3d", "no run"))?;
    Ok(Pin3dInverse {
        mu_apparent,
        mu_adhesive: result.mu,
        deformation_share: mu_apparent - result.mu,
        residual: (result.force_ratio - mu_apparent).abs(),
        runs,
        result,
    })
}
