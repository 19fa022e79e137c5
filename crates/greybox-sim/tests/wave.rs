//! Elastic wave speed in a plane-strain bar (thin strip, free lateral faces):
//! c = √(E / (ρ (1 − ν²))) (the plate/strip speed; Graff, *Wave Motion in Elastic Solids*, §8).
mod common;
use greybox_material::Material;
use greybox_sim::{BoundaryGroup, Solver};

#[test]
fn bar_wave_speed_matches_plane_strain_strip_speed() {
    let mat = Material::elastic_steel();
    let (e, nu, rho): (f64, f64, f64) = (200e9, 0.3, 7850.0);
    let c = (e / (rho * (1.0 - nu * nu))).sqrt();
    let dx = 10e-6;
    let (nx, ny) = (300, 20);
    let v0 = 1.0;
    let groups = vec![BoundaryGroup {
        name: "driver".into(),
        vx: Some(v0),
        vy: None,
    }];
    let model = common::block_model(nx, ny, dx, mat, groups, |i, _| (i < 2) as u8);
    let mut sim = Solver::new(model).unwrap();
    // Arrival time of half the driving velocity at two stations.
    let stations = [100usize, 200];
    let mut arrival = [f64::NAN; 2];
    while sim.time < 3.2e-3 / c {
        sim.step().unwrap();
        for (k, &s) in stations.iter().enumerate() {
            if arrival[k].is_nan() {
                let mean: f64 =
                    (0..ny).map(|j| sim.particles.vx[j * nx + s]).sum::<f64>() / ny as f64;
                if mean >= 0.5 * v0 {
                    arrival[k] = sim.time;
                }
            }
        }
    }
    let measured = (stations[1] - stations[0]) as f64 * dx / (arrival[1] - arrival[0]);
    eprintln!("strip wave speed {measured:.1} m/s, theory {c:.1} m/s");
    assert!((measured / c - 1.0).abs() < 0.05, "{measured} vs {c}");
}
