//! Plane-strain compression between frictionless platens, isothermal, at three temperatures:
//! the macroscopic flow curve reproduces Johnson–Cook. Plane strain (von Mises): axial stress
//! σ_xx − σ_yy = (2/√3) σ_y (means over the interior particles), equivalent strain ε̄ = (2/√3) ln(H₀/H), equivalent rate (2/√3) V/H.
mod common;
use greybox_material::{FlowStress, FlowTable, Material, TanhJohnsonCook};
use greybox_sim::{BoundaryGroup, Solver};

/// A 16 × 16 block of 6.25 µm particles between frictionless platens, the top one moving
/// down at 10 m/s, isothermal at `temperature_k`.
struct Compression {
    sim: Solver,
    n: usize,
    dx: f64,
    h0: f64,
    v: f64,
}

impl Compression {
    fn new(mat: Material, temperature_k: f64) -> Self {
        let (n, dx) = (16usize, 6.25e-6);
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
        Compression {
            sim: Solver::new(model).unwrap(),
            n,
            dx,
            h0: n as f64 * dx,
            v,
        }
    }

    /// Height between the platen particle rows (+ one spacing for the particle extent), m.
    fn height(&self) -> f64 {
        let p = &self.sim.particles;
        p.y[(self.n - 1) * self.n] - p.y[0] + self.dx
    }

    /// The imposed equivalent strain (2/√3) ln(H₀/H).
    fn strain(&self) -> f64 {
        (2.0 / 3f64.sqrt()) * (self.h0 / self.height()).ln()
    }

    /// The imposed equivalent rate (2/√3) V/H, 1/s.
    fn rate(&self) -> f64 {
        (2.0 / 3f64.sqrt()) * self.v / self.height()
    }

    fn compress_to(&mut self, strain: f64) {
        while self.strain() < strain {
            self.sim.step().unwrap();
        }
    }

    /// The mean of `f` over the interior quarter (free-surface particles carry a truncated
    /// kernel).
    fn interior_mean(&self, f: &dyn Fn(&greybox_sim::Particles, usize) -> f64) -> f64 {
        let n = self.n;
        let interior: Vec<usize> = (n / 4..3 * n / 4)
            .flat_map(|j| (n / 4..3 * n / 4).map(move |i| j * n + i))
            .collect();
        let p = &self.sim.particles;
        interior.iter().map(|&k| f(p, k)).sum::<f64>() / interior.len() as f64
    }

    /// The plane-strain flow stress (√3/2)(σ_xx − σ_yy) of the interior, Pa.
    fn flow_stress(&self) -> f64 {
        let sxx = self.interior_mean(&|p, k| p.sxx[k] - p.p[k]);
        let syy = self.interior_mean(&|p, k| p.syy[k] - p.p[k]);
        (sxx - syy) * 3f64.sqrt() / 2.0
    }
}

fn flow_curve_error(mat: Material, temperature_k: f64) -> f64 {
    let jc: FlowStress = mat.plasticity.clone().unwrap();
    let mat_e = mat.elastic.youngs_modulus_pa;
    let mut c = Compression::new(mat, temperature_k);
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for target in [0.1, 0.2, 0.3] {
        c.compress_to(target);
        let eps_p = c.interior_mean(&|p, k| p.eps_p[k]);
        let (eps, rate) = (c.strain(), c.rate());
        // Plane-strain flow: σ_xx − σ_yy = (2/√3) σ_y.
        let got = c.flow_stress();
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

/// Johnson–Cook damage under plane-strain compression. The interior's triaxiality
/// η = σ_m/σ_vm is read from its mean stresses (−0.53: near the −1/√3 of free sides, σ_xx
/// = 0, σ_yy = −(2/√3)σ_y, σ_zz = σ_yy/2, which the block's finite width does not quite
/// give). Before initiation the interior's damage indicator is ε_p/ε_f with Lesuer's
/// ε_f(η, ε̇) computed here by hand, and its flow stress is J-C's; after it the flow stress
/// is (1 − d) σ_JC with d = L/(2 G_f) ∫ σ_JC dε_p from the initiation strain (Hillerborg's
/// linear softening).
#[test]
fn compression_with_damage_initiates_at_the_johnson_cook_strain_and_softens_by_the_fracture_energy()
{
    let mut mat = Material::aisi1045_article();
    let jc: FlowStress = mat.plasticity.clone().unwrap();
    let (d1, d2, d3, d4) = (-0.09, 0.25, -0.5, 0.014);
    let fracture_energy = 2000.0;
    mat.damage = Some(greybox_material::JohnsonCookDamage {
        d1,
        d2,
        d3,
        d4,
        d5: 3.87,
        ref_strain_rate: 1.0,
        room_temperature_k: 293.15,
        melt_temperature_k: 1773.0,
        fracture_energy_j_m2: fracture_energy,
        max_degradation: 0.99,
    });
    let t = 293.15;
    let mut c = Compression::new(mat, t);
    let eps_f = |rate: f64, eta: f64| (d1 + d2 * (d3 * eta).exp()) * (1.0 + d4 * rate.ln());

    // Before initiation: ω = ε_p/ε_f, σ = σ_JC.
    c.compress_to(0.15);
    let eps_p = c.interior_mean(&|p, k| p.eps_p[k]);
    let omega = c.interior_mean(&|p, k| p.damage[k]);
    let sigma = c.flow_stress();
    let eta = c.interior_mean(&|p, k| -p.p[k]) / sigma;
    assert!((-0.6..-0.45).contains(&eta), "η {eta}");
    let want = eps_p / eps_f(c.rate(), eta);
    eprintln!("ε_p {eps_p:.4}: ω {omega:.4}, hand {want:.4}, η {eta:.4}");
    assert!((omega / want - 1.0).abs() < 0.03, "ω {omega} vs {want}");
    let sigma_jc = jc.flow_stress(eps_p, c.rate(), t);
    assert!(
        (sigma / sigma_jc - 1.0).abs() < 0.03,
        "{sigma} vs {sigma_jc}"
    );

    // After initiation: d from the fracture energy; every particle that yielded in the last
    // step on its damaged yield surface (1 − d) σ_JC(ε_p, ε̇_p), d as it was before the
    // step's own increment L Δε_p σ_JC/(2 G_f). A softening material
    // localises: the interior no longer deforms uniformly, so the macroscopic stress is
    // only checked to fall.
    c.compress_to(0.4);
    let eps_p = c.interior_mean(&|p, k| p.eps_p[k]);
    let rate = c.rate();
    let eps_i = eps_f(rate, eta);
    let steps = 1000;
    let integral: f64 = (0..steps)
        .map(|k| {
            let e = eps_i + (eps_p - eps_i) * (k as f64 + 0.5) / steps as f64;
            jc.flow_stress(e, rate, t) * (eps_p - eps_i) / steps as f64
        })
        .sum();
    let d_want = 6.25e-6 * integral / (2.0 * fracture_energy);
    let d_got = c.interior_mean(&|p, k| (p.damage[k] - 1.0).max(0.0));
    let sigma = c.flow_stress();
    let sigma_jc = jc.flow_stress(eps_p, rate, t);
    eprintln!(
        "ε_p {eps_p:.4} (initiation {eps_i:.4}): d {d_got:.4}, hand {d_want:.4}; σ {:.1} MPa, σ_JC {:.1} MPa",
        sigma * 1e-6,
        sigma_jc * 1e-6
    );
    assert!(
        d_want > 0.2,
        "the test must reach well into the softening: d {d_want}"
    );
    assert!((d_got / d_want - 1.0).abs() < 0.1, "d {d_got} vs {d_want}");
    assert!(
        sigma < (1.0 - 0.5 * d_want) * sigma_jc,
        "{sigma} vs {sigma_jc}"
    );
    let p = &c.sim.particles;
    let mut yielded = 0;
    for k in 0..p.len() {
        let undamaged = jc.flow_stress(p.eps_p[k], p.eps_rate[k], t);
        let step_increment =
            6.25e-6 * p.eps_rate[k] * c.sim.dt * undamaged / (2.0 * fracture_energy);
        let before = p.damage[k] - 1.0 - step_increment;
        // (particles at the cap d_max = 0.99 left out: their step's increment was cut)
        if p.eps_rate[k] > 0.0 && before > 0.0 && p.damage[k] < 1.99 {
            let own = (1.0 - before) * undamaged;
            assert!(
                (p.von_mises(k) / own - 1.0).abs() < 1e-6,
                "particle {k}: σ_vm {} vs (1 − d) σ_JC {own}",
                p.von_mises(k)
            );
            yielded += 1;
        }
    }
    assert!(yielded > 10, "{yielded} damaged particles yielded");
}
