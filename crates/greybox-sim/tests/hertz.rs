//! A rigid cylinder pressed elastically into a half-space (plane strain): the contact
//! half-width matches Hertz, a = √(4 P R / (π E*)), E* = E/(1 − ν²) for a rigid indenter
//! (Johnson, *Contact Mechanics*, 1985, §4.2), within ±10 %, with P the simulated load; the
//! simulated a is 2√⟨x²⟩ of the contact-force distribution (exact for the Hertz ellipse).
mod common;
use greybox_material::Material;
use greybox_sim::{BoundaryGroup, ConstantMu, Motion, MotionSegment, RoundedPolygon, Solver, Tool};
use std::sync::Arc;

#[test]
fn cylinder_contact_half_width_matches_hertz() {
    let dx = 10e-6;
    let (nx, ny) = (120, 60);
    let r = 8e-3;
    let groups = vec![BoundaryGroup {
        name: "base".into(),
        vx: Some(0.0),
        vy: Some(0.0),
    }];
    let mut model = common::block_model(nx, ny, dx, Material::elastic_steel(), groups, |_, j| {
        (j < 2) as u8
    });
    model.numerics.thermal = false;
    let top = (ny as f64 - 0.5) * dx;
    let (v, depth) = (2.0, 4e-6);
    let press = depth / v;
    let motion = Motion {
        segments: vec![
            MotionSegment {
                duration_s: press,
                velocity: [0.0, -v],
                ramp_s: 0.2 * press,
            },
            MotionSegment {
                duration_s: f64::INFINITY,
                velocity: [0.0, 0.0],
                ramp_s: 0.2 * press,
            },
        ],
    };
    let centre = [0.5 * nx as f64 * dx, top + r];
    model.tools.push(Tool::with_uniform_law(
        "cylinder",
        RoundedPolygon::circle(r),
        centre,
        motion,
        Arc::new(ConstantMu(0.0)),
    ));
    let mut sim = Solver::new(model).unwrap();
    let end = press * 1.1 + 1.5e-6;
    // Average load and contact extent over the hold phase.
    let (mut load, mut half, mut k) = (0.0, 0.0, 0.0);
    while sim.time < end {
        sim.step().unwrap();
        if sim.time > press * 1.1 + 0.5e-6 {
            let t = &sim.tools[0];
            let p = &sim.particles;
            // Penalty forces are ∝ penetration: the force-weighted second moment of the
            // contact, ⟨x²⟩ = a²/4 for the Hertz ellipse, gives a without edge noise.
            let (mut s0, mut s2) = (0.0, 0.0);
            for i in 0..p.len() {
                let q = t
                    .shape
                    .closest([p.x[i] - t.position[0], p.y[i] - t.position[1]]);
                if q.distance < 0.0 {
                    let x = p.x[i] - t.position[0];
                    s0 -= q.distance;
                    s2 -= q.distance * x * x;
                }
            }
            half += 2.0 * (s2 / s0).sqrt();
            load += t.force[1];
            k += 1.0;
        }
    }
    let (load, half) = (load / k, half / k);
    let e_star = 200e9 / (1.0 - 0.09);
    let a = (4.0 * load * r / (std::f64::consts::PI * e_star)).sqrt();
    eprintln!(
        "P = {:.1} N/mm, simulated a = {:.1} µm, Hertz a = {:.1} µm",
        load * 1e-3,
        half * 1e6,
        a * 1e6
    );
    assert!((half / a - 1.0).abs() < 0.10, "a = {half} vs Hertz {a}");
}
