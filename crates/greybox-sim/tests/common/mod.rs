#![allow(dead_code)]
use greybox_material::Material;
use greybox_sim::{BoundaryGroup, Model, Numerics, Particles};

/// A block model without tools.
pub fn block_model(
    nx: usize,
    ny: usize,
    dx: f64,
    material: Material,
    groups: Vec<BoundaryGroup>,
    assign: impl Fn(usize, usize) -> u8,
) -> Model {
    let mut p = Particles::block(0.0, 0.0, nx, ny, dx, material.density_kg_m3, 293.15);
    for j in 0..ny {
        for i in 0..nx {
            p.group[j * nx + i] = assign(i, j);
        }
    }
    Model {
        particles: p,
        material,
        tools: vec![],
        groups,
        numerics: Numerics::default(),
    }
}
