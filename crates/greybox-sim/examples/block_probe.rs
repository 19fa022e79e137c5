use greybox_material::Material;
use greybox_sim::*;
fn main() {
    let sides = std::env::var("SIDES").is_ok();
    let (nx, ny, dx) = (167usize, 40usize, 5e-6);
    let mut p = Particles::block(0.0, 0.0, nx, ny, dx, 7850.0, 293.15);
    for j in 0..ny {
        for i in 0..nx {
            let k = j * nx + i;
            if j < 2 {
                p.group[k] = 1
            } else if sides && (i < 2 || i >= nx - 2) {
                p.group[k] = 2
            } else if j >= ny - 2 && (70..97).contains(&i) {
                p.group[k] = 3
            }
        }
    }
    let groups = vec![
        BoundaryGroup {
            name: "b".into(),
            vx: Some(0.0),
            vy: Some(0.0),
        },
        BoundaryGroup {
            name: "s".into(),
            vx: Some(0.0),
            vy: None,
        },
        BoundaryGroup {
            name: "t".into(),
            vx: None,
            vy: Some(-20.0),
        },
    ];
    let model = Model {
        particles: p,
        material: Material::elastic_steel(),
        tools: vec![],
        groups,
        numerics: {
            let mut n = Numerics::default();
            if let Ok(v) = std::env::var("AS") {
                n.artificial_stress = v.parse().unwrap();
            }
            if let Ok(v) = std::env::var("XSPH") {
                n.xsph = v.parse().unwrap();
            }
            if let Ok(v) = std::env::var("CFL") {
                n.cfl = v.parse().unwrap();
            }
            if let Ok(v) = std::env::var("AV") {
                n.av_alpha = v.parse().unwrap();
                n.av_beta = n.av_alpha;
            }
            n
        },
    };
    let mut sim = Solver::new(model).unwrap();
    for s in 0..3000 {
        if let Err(e) = sim.step() {
            println!("{e}");
            let i = match e {
                SimError::Unstable { particle, .. } => particle,
                _ => 0,
            };
            println!("row {} col {}", i / nx, i % nx);
            return;
        }
        if s % 500 == 0 {
            let e = sim.energy_balance();
            println!("{s} {:?}", e);
        }
    }
}
