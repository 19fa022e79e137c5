//! Plane-strain compression between frictionless platens, isothermal, at three temperatures:
//! the macroscopic flow curve reproduces Johnson–Cook. Plane strain (von Mises): axial stress
//! σ_xx − σ_yy = (2/√3) σ_y (means over the interior particles), equivalent strain ε̄ = (2/√3) ln(H₀/H), equivalent rate (2/√3) V/H.
mod common;
use greybox_material::{FlowStress, FlowTable, Material, TanhJohnsonCook};
use greybox_sim::{BoundaryGroup, Solver};

fn flow_curve_error(mat: Material, temperature_k: f64) -> f64 {
    let jc: FlowStress = mat.plasticity.clone().unwrap();
    let mat_e = mat.elastic.youngs_modulus_pa;
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
            "{}, T {temperature_k} K: ε̄ {eps:.3}, interior ε_p {eps_p:.3}: σ_y {:.1} MPa vs model {:.1} MPa",
            jc.model_name(),
            got * 1e-6,
            want * 1e-6
        );
        // Kinematics: the interior plastic strain follows the imposed compression (less the
        // elastic strain σ_y/E and the platen rows).
        let lag = 0.02 + want / mat_e;
        assert!((eps_p - eps).abs() < lag, "ε_p {eps_p} vs ε̄ {eps}");
        worst = worst.max((got / want - 1.0).abs());
        checked += 1;
    }
    assert_eq!(checked, 3);
    worst
}

#[test]
fn compression_reproduces_johnson_cook_at_three_temperatures() {
    for t in [293.15, 573.15, 873.15] {
        let e = flow_curve_error(Material::aisi1045_article(), t);
        assert!(e < 0.02, "T = {t} K: worst relative error {e}");
    }
}

/// The same for the TANH Johnson–Cook of Sima & Özel (Ti6Al4V): the general return lands
/// on its yield surface, including the rate term.
#[test]
fn compression_reproduces_the_tanh_model() {
    let mut mat = Material::ti6al4v();
    mat.plasticity = Some(FlowStress::Tanh(TanhJohnsonCook::ti6al4v_sima_ozel_2010()));
    for t in [298.0, 773.0] {
        let e = flow_curve_error(mat.clone(), t);
        assert!(e < 0.02, "T = {t} K: worst relative error {e}");
    }
}

/// A flow-stress table tabulated from the article's J-C set (strains 0…1 in 0.05, rates
/// 10⁻³…10⁷ 1/s per decade, 293…1273 K per 70 K): the compression follows J-C within the
/// tolerance plus the table's interpolation error.
#[test]
fn compression_with_a_table_tabulated_from_johnson_cook_follows_johnson_cook() {
    let jc = greybox_material::JohnsonCook::aisi1045_article();
    let mut points = Vec::new();
    for k in 0..=10 {
        let rate = 10f64.powi(k - 3);
        for j in 0..=14 {
            let t = 293.15 + 70.0 * j as f64;
            for i in 0..=20 {
                let e = 0.05 * i as f64;
                points.push(greybox_material::fit::FlowPoint {
                    strain: e,
                    stress_pa: jc.flow_stress(e, rate, t),
                    temperature_k: t,
                    strain_rate: rate,
                });
            }
        }
    }
    let table = FlowTable::from_points(&points, jc.melt_temperature_k, 0.0, "test").unwrap();
    let mut mat = Material::aisi1045_article();
    mat.plasticity = Some(FlowStress::Table(table));
    let e = flow_curve_error(mat, 573.15);
    assert!(e < 0.02, "worst relative error {e}");
}
