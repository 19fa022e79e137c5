//! The chip measures of `greybox_sim::chip` on chips laid out by hand, whose thickness is
//! known by construction: a straight strip of particles of thickness t whose axis leaves the
//! rake face at an angle θ, moving along its axis with a velocity that varies across its
//! thickness (a secondary shear zone) and scatters particle by particle, its free side
//! ragged or not.
//!
//! * The continuity measure `chip_thickness` (h_c = h v_c / |v̄_chip|) finds t whatever θ,
//!   the shear profile and the roughness.
//! * The extent along the rake-face normal, `chip_extent` (the measure until 2026-12-01),
//!   finds t only for a chip lying on the rake face; a chip at θ measures, by the geometry of
//!   the horizontal band of height h it is read in, (h sin θ + t cos γ)/cos(γ − θ) (γ the
//!   rake angle), and a ragged free side adds its roughness.

mod common;

use greybox_sim::chip::{chip_extent, chip_thickness};
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::particles::FREE;
use greybox_sim::Solver;

/// A chip laid out by hand (module docs).
struct LaidChip {
    /// Thickness, m.
    thickness: f64,
    /// Angle of its axis from the rake face, away from the tool, rad.
    theta: f64,
    /// Speed at the tool side over the mean, minus one (negative: slower, as in a secondary
    /// shear zone), and the same at the free side with the opposite sign: a linear profile
    /// across the chip.
    shear: f64,
    /// Particle-by-particle scatter of the velocity, relative to the mean speed.
    scatter: f64,
    /// How far the free side's particles are pushed out at random, in spacings (0: smooth).
    roughness: f64,
}

/// A cut of the tests' AISI 1045 at 5 µm with rake angle `rake_deg`, built but not run, its
/// clock past the tool's speed ramp (the tool at the cutting speed).
fn built(rake_deg: f64) -> (Solver, CuttingSetup) {
    let mut setup = common::coarse_cut();
    setup.spacing_m = 5e-6;
    setup.insert.rake_deg = rake_deg;
    let (model, duration) = setup.model().expect("a cut model");
    let mut sim = Solver::new(model).expect("a solver");
    sim.time = 0.5 * duration;
    (sim, setup)
}

/// A uniform number in [0, 1) from a seeded 64-bit LCG (Knuth's MMIX constants).
fn uniform(state: &mut u64) -> f64 {
    *state = state
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

/// Lays `sim`'s free particles out as `chip` (the rest far below the workpiece, at rest):
/// the strip starts on the rake line at the uncut surface and rises 3h, each particle at
/// v_tool + w a, a its axis, w = w̄ (1 + shear (1 − 2u/t)) (1 + scatter ξ), w̄ = v_c h/t.
fn lay(sim: &mut Solver, setup: &CuttingSetup, chip: &LaidChip, seed: u64) {
    let g = setup.insert.rake_deg.to_radians();
    let h = setup.uncut_chip_thickness_m;
    let dx = sim.particles.spacing;
    let rake = [g.sin(), g.cos()];
    let normal = [-g.cos(), g.sin()];
    let (c, s) = (chip.theta.cos(), chip.theta.sin());
    let axis = [c * rake[0] + s * normal[0], c * rake[1] + s * normal[1]];
    let across = [-s * rake[0] + c * normal[0], -s * rake[1] + c * normal[1]];
    let tool = &sim.tools[0];
    let v_tool = tool.motion.velocity(sim.time);
    let cutting_speed = v_tool[0].hypot(v_tool[1]);
    // the rake line at the uncut surface (y = 0)
    let along = -tool.position[1] / rake[1];
    let origin = [
        tool.position[0] + along * rake[0],
        tool.position[1] + along * rake[1],
    ];
    let rows = (chip.thickness / dx).round() as usize;
    let columns = (3.0 * h / axis[1] / dx).ceil() as usize;
    let mean_speed = cutting_speed * h / chip.thickness;
    let mut state = seed;
    let p = &mut sim.particles;
    let free: Vec<usize> = (0..p.len()).filter(|&i| p.group[i] == FREE).collect();
    assert!(
        free.len() >= rows * columns,
        "enough particles to lay the chip"
    );
    for (k, &i) in free.iter().enumerate() {
        let (row, column) = (k % rows, k / rows);
        if column >= columns {
            (p.x[i], p.y[i], p.vx[i], p.vy[i]) = (origin[0], -1.0, 0.0, 0.0);
            continue;
        }
        let mut u = (row as f64 + 0.5) * dx;
        if row + 1 == rows {
            u += chip.roughness * dx * uniform(&mut state);
        }
        let a = (column as f64 + 0.5) * dx;
        p.x[i] = origin[0] + a * axis[0] + u * across[0];
        p.y[i] = origin[1] + a * axis[1] + u * across[1];
        let profile = 1.0 + chip.shear * (1.0 - 2.0 * (row as f64 + 0.5) / rows as f64);
        let w = mean_speed * profile;
        let jitter = [uniform(&mut state) - 0.5, uniform(&mut state) - 0.5];
        p.vx[i] = v_tool[0] + w * axis[0] + 2.0 * chip.scatter * mean_speed * jitter[0];
        p.vy[i] = v_tool[1] + w * axis[1] + 2.0 * chip.scatter * mean_speed * jitter[1];
    }
}

#[test]
fn continuity_finds_the_thickness_of_a_chip_at_any_angle_and_the_extent_only_on_the_rake() {
    for rake_deg in [0.0, 15.0] {
        let (mut sim, setup) = built(rake_deg);
        let h = setup.uncut_chip_thickness_m;
        let dx = sim.particles.spacing;
        let g = rake_deg.to_radians();
        for (k, (thickness_h, theta_deg, roughness)) in [
            (1.4, 0.0, 0.0),
            (1.4, 7.5, 0.0),
            (1.8, 12.0, 0.0),
            (1.3, 5.0, 0.8),
            (2.0, 0.0, 0.8),
        ]
        .into_iter()
        .enumerate()
        {
            let chip = LaidChip {
                thickness: thickness_h * h,
                theta: f64::to_radians(theta_deg),
                shear: -0.4,
                scatter: 0.1,
                roughness,
            };
            lay(&mut sim, &setup, &chip, 17 + k as u64);
            let t = chip.thickness;
            let measured = chip_thickness(&sim, &setup, 0).expect("a chip");
            assert!(
                (measured / t - 1.0).abs() < 0.01,
                "rake {rake_deg}°, θ {theta_deg}°, roughness {roughness}: continuity {measured:e} against {t:e}"
            );
            let extent = chip_extent(&sim, &setup, 0).expect("a chip");
            let th = chip.theta;
            let geometric = (h * th.sin() + t * g.cos()) / (g - th).cos();
            let rough = roughness * dx;
            assert!(
                extent >= geometric - dx && extent <= geometric + rough + dx,
                "rake {rake_deg}°, θ {theta_deg}°, roughness {roughness}: extent {extent:e}, the band's geometry {geometric:e}"
            );
            if theta_deg > 0.0 || roughness > 0.0 {
                assert!(
                    extent > t + 0.5 * dx,
                    "the extent overstates a chip off the rake or ragged: {extent:e} against {t:e}"
                );
            }
        }
    }
}

/// A chip whose particles all move with the tool (none has formed yet) or a tool at rest has
/// no thickness by continuity, rather than an infinite one.
#[test]
fn a_chip_at_rest_against_the_tool_has_no_thickness() {
    let (mut sim, setup) = built(15.0);
    let chip = LaidChip {
        thickness: 1.4 * setup.uncut_chip_thickness_m,
        theta: 0.0,
        shear: 0.0,
        scatter: 0.0,
        roughness: 0.0,
    };
    lay(&mut sim, &setup, &chip, 3);
    let v_tool = sim.tools[0].motion.velocity(sim.time);
    for i in 0..sim.particles.len() {
        if sim.particles.y[i] > 0.0 {
            (sim.particles.vx[i], sim.particles.vy[i]) = (v_tool[0], v_tool[1]);
        }
    }
    assert_eq!(chip_thickness(&sim, &setup, 0), None);
    assert!(chip_extent(&sim, &setup, 0).is_some());
}
