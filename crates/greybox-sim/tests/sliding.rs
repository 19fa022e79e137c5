//! A block pressed by a rigid flat that then slides over it: with every contact particle
//! slipping, the Coulomb law gives F_t/F_N = μ exactly (±2 % asked); with a limiting shear
//! stress below μσ_n, the friction stress is that limit.
mod common;
use greybox_material::Material;
use greybox_sim::output::ForceHistory;
use greybox_sim::{
    run, BoundaryGroup, ConstantMu, Motion, MotionSegment, RoundedPolygon, Solver, Tool,
};
use std::sync::Arc;

/// The sliding block's mean forces (F_t, F_N, N/m) over the second half of the slide, and
/// the mean number of particles in contact.
struct Slide {
    tangential: f64,
    normal: f64,
    contacts: f64,
}

fn sliding_ratio(mu: f64, material: Material) -> f64 {
    let s = slide(mu, None, material);
    -s.tangential / s.normal
}

fn slide(mu: f64, shear_limit_pa: Option<f64>, material: Material) -> Slide {
    let dx = 10e-6;
    let (nx, ny) = (60, 20);
    let groups = vec![BoundaryGroup {
        name: "base".into(),
        vx: Some(0.0),
        vy: Some(0.0),
    }];
    let mut model = common::block_model(nx, ny, dx, material, groups, |_, j| (j < 2) as u8);
    let top = ny as f64 * dx - 0.5 * dx;
    let flat = RoundedPolygon::new(
        vec![[-1e-3, 0.0], [1e-3, 0.0], [1e-3, 0.1e-3], [-1e-3, 0.1e-3]],
        0.0,
    )
    .unwrap();
    let (v_press, depth, v_slide) = (10.0, 2e-6, 40.0);
    let press = depth / v_press;
    let ramp = 0.03e-3 / v_slide;
    let slide = 0.1e-3 / v_slide + 0.5 * ramp;
    let motion = Motion {
        segments: vec![
            MotionSegment {
                duration_s: press,
                velocity: [0.0, -v_press],
                ramp_s: 0.0,
            },
            MotionSegment {
                duration_s: f64::INFINITY,
                velocity: [v_slide, 0.0],
                ramp_s: ramp,
            },
        ],
    };
    let mut tool = Tool::with_uniform_law(
        "flat",
        flat,
        [0.3e-3, top],
        motion,
        Arc::new(ConstantMu(mu)),
    );
    tool.shear_limit_pa = shear_limit_pa;
    model.tools.push(tool);
    model.numerics.thermal = false;
    let mut sim = Solver::new(model).unwrap();
    let mut hist = ForceHistory::new(0, 20);
    run(
        &mut sim,
        press + 0.5 * slide,
        "pin",
        greybox_sim::Hooks::new().observe(&mut hist),
    )
    .unwrap();
    sim.tools[0].windows[0].acc = Default::default();
    run(
        &mut sim,
        press + slide,
        "pin",
        greybox_sim::Hooks::new().observe(&mut hist),
    )
    .unwrap();
    let f = hist.mean_force(press + 0.5 * slide, press + slide).unwrap();
    let stats = sim.tools[0].windows[0].acc.stats(dx, 1.0).unwrap();
    eprintln!(
        "μ = {mu}, τ_max {shear_limit_pa:?}: F_t/F_N = {:.5}, slip fraction {:.3}",
        -f[0] / f[1],
        stats.slip_fraction
    );
    Slide {
        tangential: f[0],
        normal: f[1],
        contacts: hist
            .mean_contacts(press + 0.5 * slide, press + slide)
            .unwrap(),
    }
}

#[test]
fn sliding_block_force_ratio_equals_mu() {
    for (mu, mat) in [
        (0.3, Material::elastic_steel()),
        (0.15, Material::aisi1045_article()),
    ] {
        let r = sliding_ratio(mu, mat);
        assert!((r / mu - 1.0).abs() < 0.02, "μ = {mu}: F_t/F_N = {r}");
    }
}

/// Coulomb friction with a limiting shear stress (Zorev; Abaqus's `TAUMAX`): where μσ_n
/// exceeds τ_max, every contact particle carries τ_max over its spacing, so
/// F_t = τ_max · (particles in contact) · Δx per unit depth (±2 % asked, the contact count
/// varying within the averaging window); a limit far above μσ_n changes no byte.
#[test]
fn a_limiting_shear_stress_caps_the_friction_stress() {
    let (mu, dx) = (0.3, 10e-6);
    let free = slide(mu, None, Material::elastic_steel());
    let pressure = free.normal.abs() / (free.contacts * dx);
    let tau = 0.5 * mu * pressure;
    let capped = slide(mu, Some(tau), Material::elastic_steel());
    let want = tau * capped.contacts * dx;
    eprintln!(
        "σ_n {:.0} MPa, τ_max {:.0} MPa: F_t {:.1} N/m against τ_max·N·Δx {want:.1}",
        pressure * 1e-6,
        tau * 1e-6,
        -capped.tangential
    );
    assert!((-capped.tangential / want - 1.0).abs() < 0.02);
    assert!(-capped.tangential / capped.normal < 0.6 * mu);
    let loose = slide(mu, Some(1e3 * mu * pressure), Material::elastic_steel());
    assert_eq!(
        (loose.tangential, loose.normal),
        (free.tangential, free.normal)
    );
}
