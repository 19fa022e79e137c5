//! Plane-strain compression between frictionless platens, isothermal, at three temperatures:
//! the macroscopic flow curve reproduces Johnson–Cook. Plane strain (von Mises): axial stress
//! σ_xx − σ_yy = (2/√3) σ_y (means over the interior particles), equivalent strain ε̄ = (2/√3) ln(H₀/H), equivalent rate (2/√3) V/H.
mod common;
use greybox_material::{JohnsonCook, Material};
use greybox_sim::{BoundaryGroup, Solver};

fn flow_curve_error(temperature_k: f64) -> f64 {
    let mut mat = Material::aisi1045_article();
    let jc: JohnsonCook = mat.plasticity.unwrap();
    mat.name = "AISI 1045".into();
    let (n, dx) = (16usize, 6.25e-6);
    let h0 = n as f64 * dx;
    let v = 10.0;
    let groups = vec![
        BoundaryGroup {
            name: "bottom platen".into(),
            vx: None,
            vy: Some(0.0),
        },
        BoundaryGroup {
            name: "top platen".into(),
            vx: None,
            vy: Some(-v),
        },
    ];
    let mut model = common::block_model(n, n, dx, mat, groups, |_, j| {
        if j == 0 {
            1
        } else if j == n - 1 {
            2
        } else {
            0
        }
    });
    model.numerics.thermal = false;
    model
        .particles
        .temp
        .iter_mut()
        .for_each(|t| *t = temperature_k);
    let mut sim = Solver::new(model).unwrap();
    let s3 = 3f64.sqrt();
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for target in [0.1, 0.2, 0.3] {
        // Height between the platen particle rows (+ one spacing for the particle extent).
        let height = |sim: &Solver| {
            let p = &sim.particles;
            let top = p.y[(n - 1) * n];
            top - p.y[0] + dx
        };
        while (2.0 / s3) * (h0 / height(&sim)).ln() < target {
            sim.step().unwrap();
        }
        let h = height(&sim);
        // Interior quarter (free-surface particles carry a truncated kernel): mean stresses
        // and plastic strain.
        let p = &sim.particles;
        let interior: Vec<usize> = (n / 4..3 * n / 4)
            .flat_map(|j| (n / 4..3 * n / 4).map(move |i| j * n + i))
            .collect();
        let ni = interior.len() as f64;
        let mean = |f: &dyn Fn(usize) -> f64| interior.iter().map(|&k| f(k)).sum::<f64>() / ni;
        let sxx = mean(&|k| p.sxx[k] - p.p[k]);
        let syy = mean(&|k| p.syy[k] - p.p[k]);
        let eps_p = mean(&|k| p.eps_p[k]);
        let eps = (2.0 / s3) * (h0 / h).ln();
        let rate = (2.0 / s3) * v / h;
        // Plane-strain flow: σ_xx − σ_yy = (2/√3) σ_y.
        let got = (sxx - syy) * s3 / 2.0;
        let want = jc.flow_stress(eps_p, rate, temperature_k);
        eprintln!(
            "T {temperature_k} K: ε̄ {eps:.3}, interior ε_p {eps_p:.3}: σ_y {:.1} MPa vs J-C {:.1} MPa",
            got * 1e-6,
            want * 1e-6
        );
        // Kinematics: the interior plastic strain follows the imposed compression (less the
        // elastic strain and the platen rows).
        assert!((eps_p - eps).abs() < 0.02, "ε_p {eps_p} vs ε̄ {eps}");
        worst = worst.max((got / want - 1.0).abs());
        checked += 1;
    }
    assert_eq!(checked, 3);
    worst
}

#[test]
fn compression_reproduces_johnson_cook_at_three_temperatures() {
    for t in [293.15, 573.15, 873.15] {
        let e = flow_curve_error(t);
        assert!(e < 0.02, "T = {t} K: worst relative error {e}");
    }
}
