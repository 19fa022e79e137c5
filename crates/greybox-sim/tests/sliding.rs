//! A block pressed by a rigid flat that then slides over it: with every contact particle
//! slipping, the Coulomb law gives F_t/F_N = μ exactly (±2 % asked).
mod common;
use greybox_material::Material;
use greybox_sim::output::ForceHistory;
use greybox_sim::{
    run, BoundaryGroup, ConstantMu, Motion, MotionSegment, RoundedPolygon, Solver, Tool,
};
use std::sync::Arc;

fn sliding_ratio(mu: f64, material: Material) -> f64 {
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
    model.tools.push(Tool::with_uniform_law(
        "flat",
        flat,
        [0.3e-3, top],
        motion,
        Arc::new(ConstantMu(mu)),
    ));
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
        "μ = {mu}: F_t/F_N = {:.5}, slip fraction {:.3}",
        -f[0] / f[1],
        stats.slip_fraction
    );
    -f[0] / f[1]
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
