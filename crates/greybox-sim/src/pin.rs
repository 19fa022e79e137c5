//! The tribometer pin in plane strain (the article's section 5): a rigid circle of the pin
//! radius is pressed into a Johnson–Cook workpiece to the track depth d = r − √(r² − (w/2)²)
//! and slid along it with a prescribed Coulomb μ; the simulated F_t/F_N exceeds μ by the
//! ploughing (deformation) share. The inverse search finds the μ_adh whose simulated F_t/F_N
//! equals the measured μ_app.
//!
//! Time scaling: the process is quasi-static (at 150 m/min the inertial stress ρv² is
//! 0.05 MPa), so the pin slides at a fraction `mach` of the elastic wave speed instead of the
//! physical speed, and the strain rate seen by Johnson–Cook is scaled back to the physical
//! speed (`Numerics::strain_rate_scale`). Heat conduction is time-scaled the same way: the
//! conductivity is multiplied by the speed-up v_slide/v, so the thermal Péclet number v·L/α
//! is the physical one; the heat per unit of slide (force × distance) is unchanged, so the
//! temperatures are those of the physical speed. Without this the contact heated as if slid
//! 24× faster at article scale (1450 °C), the hot layer stuck to the pin and the delivered
//! friction fell below μ. The cost of a run is then set by the slide length over the
//! spacing, not by the physical time.

use crate::executor::{run, Hooks, RunSummary};
use crate::geometry::RoundedPolygon;
use crate::model::{BoundaryGroup, Model, Numerics};
use crate::output::ForceHistory;
use crate::particles::Particles;
use crate::solver::{SimError, Solver};
use crate::tool::{ConstantMu, Motion, MotionSegment, Tool};
use greybox_core::roots::illinois_increasing;
use greybox_material::Material;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The pin-sliding set-up (SI units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PinSetup {
    /// Pin tip radius r, m.
    pub pin_radius_m: f64,
    /// Indentation depth d below the workpiece surface, m.
    pub depth_m: f64,
    /// Coulomb μ on the pin surface.
    pub mu: f64,
    /// Physical sliding speed (sets the Johnson–Cook strain rate), m/s.
    pub sliding_speed_m_s: f64,
    /// Slide length after pressing, m.
    pub slide_length_m: f64,
    /// Particle spacing, m.
    pub spacing_m: f64,
    /// Workpiece height, m.
    pub workpiece_height_m: f64,
    /// Simulated sliding speed as a fraction of the longitudinal wave speed.
    pub mach: f64,
    /// Initial temperature, K.
    pub initial_temperature_k: f64,
    pub material: Material,
    pub numerics: Numerics,
}

impl PinSetup {
    /// The article's pin (r = 17 mm) on AISI 1045 at depth `depth_m`, 150 m/min, with a
    /// resolution of `spacing_m`.
    pub fn article(depth_m: f64, mu: f64, spacing_m: f64) -> Self {
        PinSetup {
            pin_radius_m: 17e-3,
            depth_m,
            mu,
            sliding_speed_m_s: 150.0 / 60.0,
            slide_length_m: 1.0e-3,
            spacing_m,
            workpiece_height_m: 0.5e-3,
            mach: 0.01,
            initial_temperature_k: 293.15,
            material: Material::aisi1045_article(),
            numerics: Numerics::default(),
        }
    }

    /// Half chord of the contact at full depth, √(2 r d − d²), m.
    pub fn half_chord(&self) -> f64 {
        (2.0 * self.pin_radius_m * self.depth_m - self.depth_m.powi(2)).sqrt()
    }

    /// The plane-strain Bowden–Tabor ploughing term of a cylinder on a rigid-plastic flat with
    /// uniform pressure on the leading arc of angle θ = acos(1 − d/r): μ_p = (1 − cos θ)/sin θ
    /// = tan(θ/2).
    pub fn analytic_ploughing(&self) -> f64 {
        let th = (1.0 - self.depth_m / self.pin_radius_m).acos();
        (0.5 * th).tan()
    }

    pub fn validate(&self) -> greybox_core::Result<()> {
        use greybox_core::physics::Quantity;
        greybox_core::rules::Rules::new("pin set-up")
            .positive("pin_radius_m", self.pin_radius_m)
            .positive("depth_m", self.depth_m)
            .physics("mu", Quantity::Mu, self.mu)
            .positive("sliding_speed_m_s", self.sliding_speed_m_s)
            .physics(
                "sliding_speed_m_s",
                Quantity::SlidingVelocity,
                self.sliding_speed_m_s,
            )
            .positive("slide_length_m", self.slide_length_m)
            .positive("spacing_m", self.spacing_m)
            .positive("workpiece_height_m", self.workpiece_height_m)
            .above_up_to("mach", self.mach, 0.0, 0.1)
            .positive("initial_temperature_k", self.initial_temperature_k)
            .physics(
                "initial_temperature_k",
                Quantity::Temperature,
                self.initial_temperature_k,
            )
            .relation(
                !(self.depth_m >= self.pin_radius_m),
                format!(
                    "depth_m ({}) must be below pin_radius_m ({})",
                    self.depth_m, self.pin_radius_m
                ),
            )
            .relation(
                !(self.workpiece_height_m < 6.0 * self.spacing_m),
                format!(
                    "workpiece_height_m ({:.1} µm) must be at least 6 spacings ({:.1} µm)",
                    self.workpiece_height_m * 1e6,
                    6e6 * self.spacing_m
                ),
            )
            .relation(
                !(self.depth_m < self.spacing_m),
                format!(
                    "the depth {:.2} µm is below one particle spacing {:.2} µm; refine the spacing",
                    self.depth_m * 1e6,
                    self.spacing_m * 1e6
                ),
            )
            .finish()?;
        crate::particles::check_workpiece_budget(
            "pin set-up",
            self.workpiece_length(),
            self.workpiece_height_m,
            self.spacing_m,
            self.numerics.max_particles.map(|c| c.as_u64()),
        )
    }

    /// Workpiece length: room for the pressed chord behind, the slide, the chord ahead and
    /// the plastic zone in front of it.
    pub fn workpiece_length(&self) -> f64 {
        // Ahead of the pin's final position the plastic zone of the bow wave reaches about one
        // workpiece height beyond the contact: twice that keeps it off the end wall (at r =
        // 17 mm with a 1 mm margin the normal force doubled as the wave reached the wall).
        2.0 * (self.half_chord() + 0.2e-3 + 10.0 * self.spacing_m)
            + self.slide_length_m
            + 2.0 * self.workpiece_height_m
    }

    /// Builds the model and the press / slide schedule (durations, s).
    pub fn model(&self) -> greybox_core::Result<(Model, f64, f64)> {
        self.validate()?;
        let (particles, groups) = self.held_workpiece();
        let c_long = (self.material.elastic.p_wave_modulus()
            / (self.material.density_kg_m3 * self.numerics.mass_scaling))
            .sqrt();
        let v_slide = self.mach * c_long;
        let (motion, press_time, slide_time) = self.pin_motion(c_long, v_slide);
        let dx = self.spacing_m;
        let surface = -0.5 * dx; // the top particle centres
        let gap = 0.1 * dx;
        let x_start = self.half_chord() + 0.2e-3 + 10.0 * dx;
        let centre = [x_start, surface + gap + self.pin_radius_m];
        let pin = Tool::with_uniform_law(
            "pin",
            RoundedPolygon::circle(self.pin_radius_m),
            centre,
            motion,
            Arc::new(ConstantMu(self.mu)),
        );
        let (numerics, material) = self.time_scaled(v_slide);
        Ok((
            Model {
                particles,
                material,
                tools: vec![pin],
                groups,
                numerics,
                refinement: None,
                sink: None,
            },
            press_time,
            slide_time,
        ))
    }

    /// The workpiece's particles with their boundary groups: group 1, the bottom two rows,
    /// fixed; group 2, the two outer columns, held in x.
    fn held_workpiece(&self) -> (Particles, Vec<BoundaryGroup>) {
        let (mut p, nx, ny) = Particles::workpiece(
            self.workpiece_length(),
            self.workpiece_height_m,
            self.spacing_m,
            self.material.density_kg_m3,
            self.initial_temperature_k,
        );
        for j in 0..ny {
            for i in 0..nx {
                let k = j * nx + i;
                if j < 2 {
                    p.group[k] = 1;
                } else if i < 2 || i >= nx - 2 {
                    p.group[k] = 2;
                }
            }
        }
        let groups = vec![
            BoundaryGroup {
                name: "bottom".into(),
                vx: Some(0.0),
                vy: Some(0.0),
            },
            BoundaryGroup {
                name: "sides".into(),
                vx: Some(0.0),
                vy: None,
            },
        ];
        (p, groups)
    }

    /// The pin's press and slide (longitudinal wave speed `c_long` and sliding speed
    /// `v_slide` of the run, m/s): its motion and the press and slide durations, s.
    fn pin_motion(&self, c_long: f64, v_slide: f64) -> (Motion, f64, f64) {
        let gap = 0.1 * self.spacing_m;
        // Quasi-static press: the pin accelerates smoothly over the first half of the press
        // and decelerates over the second (peak speed ≤ v_slide/2), and each half lasts at
        // least 20 wave transits through the workpiece, so the stress waves the press sends
        // stay small. A pin arriving at full speed sent a plastic wave (ρ c v ≈ 1.4 GPa at
        // 30 m/s) through the article-scale workpiece and threw its surface off.
        let press_time =
            (4.0 * (gap + self.depth_m) / v_slide).max(40.0 * self.workpiece_height_m / c_long);
        let v_press = 2.0 * (gap + self.depth_m) / press_time;
        // The slide starts with a ramp over 20 % of its length (covered at half speed).
        let ramp = 0.2 * self.slide_length_m / v_slide * 2.0;
        let slide_time = self.slide_length_m / v_slide + 0.5 * ramp;
        let motion = Motion {
            segments: vec![
                MotionSegment {
                    duration_s: 0.5 * press_time,
                    velocity: [0.0, -v_press],
                    ramp_s: 0.5 * press_time,
                },
                MotionSegment {
                    duration_s: 0.5 * press_time,
                    velocity: [0.0, 0.0],
                    ramp_s: 0.5 * press_time,
                },
                MotionSegment {
                    duration_s: slide_time,
                    velocity: [v_slide, 0.0],
                    ramp_s: ramp,
                },
                MotionSegment {
                    duration_s: f64::INFINITY,
                    velocity: [0.0, 0.0],
                    ramp_s: 0.0,
                },
            ],
        };
        (motion, press_time, slide_time)
    }

    /// Numerics and material of a run sliding at `v_slide` (m/s) instead of the physical
    /// speed: the flow stress sees the physical strain rate and conduction keeps pace.
    fn time_scaled(&self, v_slide: f64) -> (Numerics, Material) {
        let mut numerics = self.numerics.clone();
        numerics.strain_rate_scale = self.sliding_speed_m_s / v_slide;
        let mut material = self.material.clone();
        let speed_up = v_slide / self.sliding_speed_m_s;
        for k in material.thermal.conductivity.y.iter_mut() {
            *k *= speed_up;
        }
        (numerics, material)
    }
}

/// Result of one pin simulation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PinResult {
    pub mu: f64,
    pub depth_m: f64,
    /// Mean F_t/F_N over the second half of the slide.
    pub force_ratio: f64,
    /// Deformation (ploughing) share F_t/F_N − μ.
    pub deformation_share: f64,
    /// The analytic plane-strain value tan(θ/2) for the same geometry.
    pub analytic_share: f64,
    /// Mean normal and tangential force per mm of width, N/mm.
    pub normal_force_n_per_mm: f64,
    pub tangential_force_n_per_mm: f64,
    /// Coefficient of variation of the force ratio over the measuring window.
    pub ratio_cv: f64,
    pub particles: usize,
    pub steps: u64,
    pub wall_s: f64,
    pub particle_steps_per_s: f64,
    pub simulated_speed_m_s: f64,
    pub mass_scaling: f64,
    /// Energy-balance residual at the end, relative to the external work.
    pub energy_error: f64,
    /// Results outside the physics table's range ([`greybox_core::physics`]): the ploughing
    /// share (deformation share / F_t/F_N) outside 0..1 — a simulated F_t/F_N below the
    /// adhesive μ (ploughing only adds) — with the numbers.
    #[serde(default)]
    pub unusual: Vec<String>,
}

/// The ploughing share of a pin run, (F_t/F_N − μ) / (F_t/F_N), against the physics
/// table's [`Quantity::Share`](greybox_core::physics::Quantity::Share): a line for each
/// problem (none when it lies in 0..1).
pub fn ploughing_share_flags(force_ratio: f64, mu: f64) -> Vec<String> {
    let share = (force_ratio - mu) / force_ratio;
    let what = format!("ploughing (F_t/F_N {force_ratio:.4} − μ {mu}) / F_t/F_N");
    match greybox_core::physics::check(greybox_core::physics::Quantity::Share, share, &what) {
        Ok(None) => Vec::new(),
        Ok(Some(f)) => vec![f.text],
        Err(e) => vec![format!(
            "{e}: the simulated force ratio is below the adhesive μ (ploughing only adds): refine the particles or lengthen the slide"
        )],
    }
}

/// Runs the press and slide; extra seams (VTK, checkpoints) may be attached.
pub fn simulate(
    setup: &PinSetup,
    extra: &mut Hooks<'_>,
) -> Result<(PinResult, ForceHistory, Solver), SimError> {
    simulate_from(setup, None, extra)
}

/// As [`simulate`], optionally resuming from a checkpoint of the same set-up (the force
/// history then starts at the checkpoint, so resume before the measuring window).
pub fn simulate_from(
    setup: &PinSetup,
    resume: Option<crate::checkpoint::Checkpoint>,
    extra: &mut Hooks<'_>,
) -> Result<(PinResult, ForceHistory, Solver), SimError> {
    let (model, press, slide) = setup.model()?;
    let mut sim = Solver::new(model)?;
    let fresh_dt = sim.dt;
    let states = crate::checkpoint::Checkpoint::resume_into(resume, &mut sim, &fingerprint(setup))?;
    crate::cut_run::check_steps_ahead(&sim, press + slide, states.is_some(), 1.0, fresh_dt)?;
    let every = ((press + slide) / sim.dt / 400.0).ceil().max(1.0) as u64;
    let mut hist = ForceHistory::new(0, every);
    if let Some(states) = &states {
        hist = crate::executor::restored_state::<ForceHistory>(states)?;
    }
    let hooks = Hooks::new().observe(&mut hist).then(extra);
    let summary: RunSummary = run(&mut sim, press + slide, "pin", hooks)?;
    let (t0, t1) = (press + 0.5 * slide, press + slide);
    let sel: Vec<&[f64; 6]> = hist
        .rows
        .iter()
        .filter(|r| r[0] >= t0 && r[0] <= t1)
        .collect();
    if sel.is_empty() || sel.iter().all(|r| r[4] <= 0.0) {
        return Err(SimError::Invalid(
            "the pin never carried a normal load while sliding".into(),
        ));
    }
    let n = sel.len() as f64;
    let fn_ = sel.iter().map(|r| r[4]).sum::<f64>() / n;
    let ft = sel.iter().map(|r| -r[3]).sum::<f64>() / n;
    let ratios: Vec<f64> = sel
        .iter()
        .filter(|r| r[4] > 0.0)
        .map(|r| -r[3] / r[4])
        .collect();
    let rm = ratios.iter().sum::<f64>() / ratios.len() as f64;
    let sd = (ratios.iter().map(|r| (r - rm).powi(2)).sum::<f64>() / ratios.len() as f64).sqrt();
    let ratio = ft / fn_;
    let res = PinResult {
        mu: setup.mu,
        depth_m: setup.depth_m,
        force_ratio: ratio,
        deformation_share: ratio - setup.mu,
        analytic_share: setup.analytic_ploughing(),
        normal_force_n_per_mm: fn_ * 1e-3,
        tangential_force_n_per_mm: ft * 1e-3,
        ratio_cv: sd / rm.abs().max(1e-12),
        particles: sim.particle_count(),
        steps: summary.steps,
        wall_s: summary.wall_s,
        particle_steps_per_s: summary.particle_steps_per_s,
        simulated_speed_m_s: setup.mach * sim.wave_speed(),
        mass_scaling: sim.numerics.mass_scaling,
        energy_error: sim.energy_balance().relative_error,
        unusual: ploughing_share_flags(ratio, setup.mu),
    };
    Ok((res, hist, sim))
}

/// Result of the inverse search at one load.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct InverseResult {
    pub depth_m: f64,
    /// Measured apparent μ to match.
    pub mu_apparent: f64,
    /// The adhesive μ found.
    pub mu_adhesive: f64,
    /// Deformation share μ_app − μ_adh.
    pub deformation_share: f64,
    /// |simulated F_t/F_N − μ_app| at the returned μ.
    pub residual: f64,
    /// Every run: (μ, simulated F_t/F_N).
    pub runs: Vec<(f64, f64)>,
}

/// Finds μ_adh with simulated F_t/F_N(μ_adh) = μ_app by a bracketing Illinois search.
///
/// F_t/F_N(μ) increases with μ and F_t/F_N(μ_app) ≥ μ_app (ploughing only adds), so
/// μ_app is an upper bracket; the lower bracket starts from the analytic share and moves down
/// until it brackets. The two bracket runs go in parallel. Stops at |residual| ≤ `tol` or
/// after `max_runs`.
pub fn find_adhesive_mu(
    base: &PinSetup,
    mu_apparent: f64,
    tol: f64,
    max_runs: usize,
) -> Result<InverseResult, SimError> {
    let eval = |mu: f64| -> Result<f64, SimError> {
        let mut s = base.clone();
        s.mu = mu.max(0.0);
        Ok(simulate(&s, &mut Hooks::new())?.0.force_ratio - mu_apparent)
    };
    let guess = base.analytic_ploughing();
    let mut lo = (mu_apparent - 2.0 * guess - 0.02).max(0.0);
    let mut hi = mu_apparent;
    let (flo, fhi) = rayon::join(|| eval(lo), || eval(hi));
    let (mut flo, mut fhi) = (flo?, fhi?);
    let mut runs = vec![(lo, flo + mu_apparent), (hi, fhi + mu_apparent)];
    while flo > 0.0 && lo > 0.0 && runs.len() < max_runs {
        hi = lo;
        fhi = flo;
        lo = (lo - 2.0 * guess - 0.05).max(0.0);
        flo = eval(lo)?;
        runs.push((lo, flo + mu_apparent));
    }
    let mut log = Vec::new();
    let budget = max_runs.saturating_sub(runs.len());
    let mu_adh = illinois_increasing(&eval, (lo, flo), (hi, fhi), tol, budget, &mut log)?;
    runs.extend(log.iter().map(|&(mu, f)| (mu, f + mu_apparent)));
    let best_f = runs
        .iter()
        .map(|&(_, r)| r - mu_apparent)
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(f64::INFINITY);
    Ok(InverseResult {
        depth_m: base.depth_m,
        mu_apparent,
        mu_adhesive: mu_adh,
        deformation_share: mu_apparent - mu_adh,
        residual: best_f.abs(),
        runs,
    })
}

/// Power law share(F) = a F^b fitted in log space to (load, share) points (shares > 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShareLaw {
    pub a: f64,
    pub b: f64,
}

impl ShareLaw {
    pub fn fit(points: &[(f64, f64)]) -> greybox_core::Result<Self> {
        let pts: Vec<(f64, f64)> = points
            .iter()
            .copied()
            .filter(|&(f, s)| f > 0.0 && s > 0.0)
            .collect();
        let Some(&(f0, s0)) = pts.first() else {
            return Err(greybox_core::Error::invalid(
                "deformation share fit",
                "no load with a positive simulated deformation share",
            ));
        };
        // One distinct load: share ∝ √F (Bowden–Tabor scaling with w ∝ √F).
        let (a, b) = greybox_core::linalg::fit_power_law(&pts)
            .unwrap_or(((s0.ln() - 0.5 * f0.ln()).exp(), 0.5));
        Ok(ShareLaw { a, b })
    }
    pub fn share(&self, force_n: f64) -> f64 {
        self.a * force_n.powf(self.b)
    }
}

/// One simulated load of the inverse correction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoadInverse {
    #[serde(rename = "normal_force_N")]
    pub normal_force_n: f64,
    pub result: InverseResult,
}

/// Runs [`find_adhesive_mu`] for several (normal force N, depth m, μ_app) in parallel on the
/// base set-up (its depth and μ are replaced per load).
pub fn inverse_over_loads(
    base: &PinSetup,
    loads: &[(f64, f64, f64)],
    tol: f64,
    max_runs: usize,
) -> Result<Vec<LoadInverse>, SimError> {
    use rayon::prelude::*;
    loads
        .par_iter()
        .map(|&(force, depth, mu_app)| {
            let mut s = base.clone();
            s.depth_m = depth;
            s.mu = mu_app;
            Ok(LoadInverse {
                normal_force_n: force,
                result: find_adhesive_mu(&s, mu_app, tol, max_runs)?,
            })
        })
        .collect()
}

/// The set-up identity a checkpoint is tied to.
pub fn fingerprint(setup: &PinSetup) -> String {
    serde_json::to_string(setup).unwrap_or_default()
}
