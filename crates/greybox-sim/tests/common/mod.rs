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
        refinement: None,
        sink: None,
    }
}

/// A coarse cut (20 µm spacing, 0.3 mm of cut, mass scaling 100) of the article's AISI 1045
/// with a rigid adiabatic tool: the tests' standard cut, ten seconds in release.
pub fn coarse_cut() -> greybox_sim::cutting::CuttingSetup {
    use greybox_sim::cutting::{CuttingSetup, FrictionSetup, InsertGeometry, SteadySetup};
    CuttingSetup {
        insert: InsertGeometry {
            rake_deg: 0.0,
            clearance_deg: 7.0,
            edge_radius_m: 20e-6,
            rake_length_m: 0.4e-3,
            flank_length_m: 0.2e-3,
        },
        cutting_speed_m_s: 2.5,
        uncut_chip_thickness_m: 0.1e-3,
        cut_length_m: 0.3e-3,
        spacing_m: 20e-6,
        workpiece_height_m: 0.24e-3,
        mu: 0.35,
        initial_temperature_k: 293.15,
        material: Material::aisi1045_article(),
        numerics: Numerics {
            mass_scaling: 100.0,
            ..Numerics::default()
        },
        friction: FrictionSetup {
            window_length_m: 20e-6,
            update_every_steps: 100,
            ..FrictionSetup::default()
        },
        steady: SteadySetup::default(),
        tool_thermal: None,
        physical_cutting_speed_m_s: None,
        refinement: None,
        chip_break_height_m: None,
    }
}

/// `setup` with one refinement level around the cutting edge (half its spacing): a region
/// from 0.2 mm ahead of the edge to 20 µm behind it, 40 µm below it and 0.3 mm above it,
/// which holds the primary shear zone and the chip of the tests' cuts.
pub fn refined(
    mut setup: greybox_sim::cutting::CuttingSetup,
) -> greybox_sim::cutting::CuttingSetup {
    use greybox_sim::cutting::{CutRefinement, CutRegion};
    setup.refinement = Some(CutRefinement {
        regions: vec![CutRegion {
            ahead_m: 0.2e-3,
            behind_m: 20e-6,
            below_m: 40e-6,
            above_m: 0.3e-3,
        }],
        pattern: Default::default(),
        coarsen_behind_m: None,
        coarsen_chip_above_m: None,
    });
    setup
}

/// Runs `setup` whole with its constant μ on the whole tool, no extra seams.
#[allow(dead_code)] // not every test binary cuts
pub fn cut_with_its_mu(setup: &greybox_sim::cutting::CuttingSetup) -> greybox_sim::cut_run::CutRun {
    greybox_sim::cut_run::CutRun::execute(
        setup,
        std::sync::Arc::new(greybox_sim::ConstantMu(setup.mu)),
        1.0,
        None,
        &mut greybox_sim::Hooks::new(),
    )
    .unwrap()
}
