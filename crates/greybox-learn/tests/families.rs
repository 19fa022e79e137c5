//! Each model family learns a smooth friction-like surface; protocol pieces behave.

use greybox_learn::importance::permutation_importance;
use greybox_learn::metrics::r2;
use greybox_learn::regressor::Regressor;
use greybox_learn::regressor::Train;
use greybox_model::ensemble::BoostParams;
use greybox_model::ensemble::ForestParams;
use greybox_model::mlp::{Activation, MlpParams};
use greybox_model::svr::{Kernel, SvrParams};
use greybox_model::Matrix;
use greybox_model::{Hyperparameters, Predictor};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// μ = 0.3 + 0.15 exp(−v/80) − 0.05 (p − 900)/1300 + N(0, σ), v ∈ [20, 250], p ∈ [900, 2200].
fn data(n: usize, noise: f64, seed: u64, with_noise_feature: bool) -> (Matrix, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = rand_distr::Normal::new(0.0, 1.0).unwrap();
    let mut rows = Vec::new();
    let mut y = Vec::new();
    for _ in 0..n {
        let v: f64 = rng.gen_range(20.0..250.0);
        let p: f64 = rng.gen_range(900.0..2200.0);
        let e: f64 = rand_distr::Distribution::sample(&normal, &mut rng);
        let mut r = vec![v, p];
        if with_noise_feature {
            r.push(rng.gen_range(0.0..1.0));
        }
        rows.push(r);
        y.push(0.3 + 0.15 * (-v / 80.0).exp() - 0.05 * (p - 900.0) / 1300.0 + noise * e);
    }
    (Matrix::from_rows(&rows), y)
}

fn test_r2(hp: &Hyperparameters) -> f64 {
    let (x, y) = data(300, 0.005, 1, false);
    let (xt, yt) = data(200, 0.0, 2, false);
    hp.validate().unwrap();
    let m = hp.fit(&x, &y, 7).unwrap();
    r2(&yt, &m.predict(&xt))
}

#[test]
fn random_forest_learns() {
    let r = test_r2(&Hyperparameters::RandomForest(ForestParams::default()));
    assert!(r > 0.95, "{r}");
}

#[test]
fn boosting_learns() {
    let r = test_r2(&Hyperparameters::GradientBoosting(BoostParams {
        n_estimators: 300,
        max_depth: 3,
        learning_rate: 0.1,
        ..Default::default()
    }));
    assert!(r > 0.97, "{r}");
}

#[test]
fn svr_learns_with_every_kernel() {
    for (k, min) in [
        (Kernel::Rbf, 0.97),
        (Kernel::Poly, 0.8),
        (Kernel::Linear, 0.8),
        (Kernel::Sigmoid, f64::NEG_INFINITY),
    ] {
        let r = test_r2(&Hyperparameters::Svr(SvrParams {
            kernel: k,
            c: 10.0,
            epsilon: 0.005,
            ..Default::default()
        }));
        eprintln!("svr {k:?}: R² {r}");
        assert!(r > min && r.is_finite(), "{k:?}: {r}");
    }
}

#[test]
fn mlp_learns() {
    for a in [Activation::Relu, Activation::Tanh] {
        let r = test_r2(&Hyperparameters::Mlp(MlpParams {
            activation: a,
            learning_rate: 0.01,
            max_epochs: 500,
            ..Default::default()
        }));
        eprintln!("mlp {a:?}: R² {r}");
        assert!(r > 0.95, "{a:?}: {r}");
    }
}

/// A one-round, depth-1 boosted stump against hand-computed XGBoost arithmetic:
/// y = [0, 0, 1, 1] at x = [1, 2, 3, 4]; base 0.5; g = [0.5, 0.5, −0.5, −0.5], h = 1, λ = 1;
/// split at 2.5; leaf weights −G/(H+λ) = −1/3 and +1/3, times η = 0.3.
#[test]
fn boosting_stump_matches_hand_computation() {
    let x = Matrix::from_rows(&[vec![1.0], vec![2.0], vec![3.0], vec![4.0]]);
    let y = [0.0, 0.0, 1.0, 1.0];
    let m = BoostParams {
        n_estimators: 1,
        max_depth: 1,
        learning_rate: 0.3,
        ..Default::default()
    }
    .fit(&x, &y, 0)
    .unwrap();
    assert!((m.predict_one(&[1.5]) - (0.5 - 0.1)).abs() < 1e-15);
    assert!((m.predict_one(&[3.5]) - (0.5 + 0.1)).abs() < 1e-15);
    assert_eq!(m.nodes[m.roots[0] as usize].value, 2.5);
}

/// ε-SVR on exactly linear data: with a linear kernel, ε = 0.01 and large C the fitted line
/// stays within ε (+ solver tolerance) of every training point.
#[test]
fn linear_svr_fits_a_line_within_the_tube() {
    let rows: Vec<Vec<f64>> = (0..30).map(|i| vec![i as f64]).collect();
    let y: Vec<f64> = (0..30).map(|i| 2.0 + 0.5 * i as f64).collect();
    let x = Matrix::from_rows(&rows);
    let m = SvrParams {
        kernel: Kernel::Linear,
        c: 1000.0,
        epsilon: 0.01,
        ..Default::default()
    }
    .fit(&x, &y, 0)
    .unwrap();
    for (i, yi) in y.iter().enumerate() {
        assert!(
            (m.predict_one(x.row(i)) - yi).abs() < 0.01 + 2e-3,
            "row {i}"
        );
    }
}

#[test]
fn same_seed_same_model() {
    let (x, y) = data(120, 0.005, 3, false);
    for hp in [
        Hyperparameters::RandomForest(ForestParams {
            n_estimators: 20,
            ..Default::default()
        }),
        Hyperparameters::Mlp(MlpParams {
            max_epochs: 30,
            ..Default::default()
        }),
    ] {
        assert_eq!(hp.fit(&x, &y, 5).unwrap(), hp.fit(&x, &y, 5).unwrap());
        assert_ne!(hp.fit(&x, &y, 5).unwrap(), hp.fit(&x, &y, 6).unwrap());
    }
}

/// Permutation importance of a pure-noise feature is ≈ 0; the real features matter.
#[test]
fn noise_feature_has_no_importance() {
    let (x, y) = data(300, 0.003, 4, true);
    let m = BoostParams {
        n_estimators: 200,
        max_depth: 3,
        learning_rate: 0.1,
        ..Default::default()
    }
    .fit(&x, &y, 0)
    .unwrap();
    let names = vec!["v".to_string(), "p".to_string(), "noise".to_string()];
    let imp = permutation_importance(&m, &x, &y, &names, 30, 42);
    eprintln!("{imp:?}");
    assert!(imp[0].mean > 0.3 && imp[1].mean > 0.3);
    assert!(imp[2].mean.abs() < 0.02, "noise importance {}", imp[2].mean);
}

/// SMO keeps kernel rows in a bounded cache, not the kernel matrix: an rbf SVR fits 20 000
/// rows (beyond the 13 377 rows the full matrices allowed in 4 GiB) and follows the data; the
/// linear kernel, solved in feature space, fits 100 000 rows.
#[test]
fn svr_fits_more_rows_than_a_kernel_matrix_would_hold() {
    let (x, y) = data(20_000, 0.002, 3, false);
    let m = SvrParams {
        c: 10.0,
        epsilon: 0.005,
        ..Default::default()
    }
    .fit(&x, &y, 0)
    .unwrap();
    let (xt, yt) = data(2_000, 0.0, 4, false);
    let worst = (0..xt.n_rows)
        .map(|r| (m.predict_one(xt.row(r)) - yt[r]).abs())
        .fold(0.0, f64::max);
    assert!(worst < 0.01, "worst error {worst}");
    assert!(
        m.coef.len() < x.n_rows / 2,
        "{} support vectors",
        m.coef.len()
    );
    let n = 100_000;
    let x = greybox_model::Matrix::new(n, 2, (0..2 * n).map(|i| (i % 977) as f64).collect());
    let y: Vec<f64> = (0..n).map(|r| 0.3 - 1e-4 * x.row(r)[0]).collect();
    let m = SvrParams {
        kernel: Kernel::Linear,
        epsilon: 1e-3,
        ..Default::default()
    }
    .fit(&x, &y, 0)
    .unwrap();
    for r in [0, 500, 976, 99_999] {
        assert!((m.predict_one(x.row(r)) - y[r]).abs() < 2e-3, "row {r}");
    }
}

/// A forest and a boosted ensemble compiled to decision grids give their trees' predictions
/// bit for bit: on random points, exactly on every split threshold and on its neighbouring
/// floats, outside the data, and for NaN features.
/// A random forest of `trees` trees and a boosted ensemble of (trees, max depth)
/// `boosting` at learning rate 0.1, both fitted with `seed`.
fn forest_and_boosting(
    x: &Matrix,
    y: &[f64],
    trees: usize,
    (boosted_trees, max_depth): (usize, usize),
    seed: u64,
) -> (
    greybox_model::tree::TreeEnsemble,
    greybox_model::tree::TreeEnsemble,
) {
    let forest = ForestParams {
        n_estimators: trees,
        ..Default::default()
    }
    .fit(x, y, seed)
    .unwrap();
    let boost = BoostParams {
        n_estimators: boosted_trees,
        max_depth,
        learning_rate: 0.1,
        ..Default::default()
    }
    .fit(x, y, seed)
    .unwrap();
    (forest, boost)
}

#[test]
fn decision_grids_equal_their_tree_ensembles_bit_for_bit() {
    use greybox_model::tree::{DecisionGrid, TreeEnsemble};
    let (x, y) = data(210, 0.01, 7, false);
    let (forest, boost) = forest_and_boosting(&x, &y, 50, (100, 5), 3);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for e in [&forest, &boost] {
        let grid = DecisionGrid::build(e, 1 << 20).expect("a grid within the cap");
        let thresholds = |f: u32| -> Vec<f64> {
            e.nodes
                .iter()
                .filter(|n| n.feature == f)
                .map(|n| n.value)
                .collect()
        };
        let (t0, t1) = (thresholds(0), thresholds(1));
        let ranges = x.column_ranges();
        let mut points: Vec<[f64; 2]> = (0..20_000)
            .map(|_| {
                let mut u = |r: (f64, f64)| r.0 + (r.1 - r.0) * rng.gen_range(-0.2..1.2);
                [u(ranges[0]), u(ranges[1])]
            })
            .collect();
        for (k, &a) in t0.iter().enumerate() {
            let b = t1[k % t1.len()];
            for (p, q) in [
                (a, b),
                (a.next_up(), b),
                (a.next_down(), b.next_up()),
                (a, b.next_down()),
            ] {
                points.push([p, q]);
            }
        }
        points.extend([[f64::NAN, 0.5], [1.0, f64::NAN], [f64::NAN, f64::NAN]]);
        points.extend([[f64::INFINITY, f64::NEG_INFINITY], [-1e300, 1e300]]);
        for p in &points {
            let (want, got) = (e.predict_one(p), grid.predict_one(p));
            assert_eq!(want.to_bits(), got.to_bits(), "at {p:?}: {want} vs {got}");
        }
        assert!(grid.len() <= (t0.len() + 1) * (t1.len() + 1));
        // a cap below the size refuses to build
        assert!(DecisionGrid::build(e, grid.len() - 1).is_none());
        let _: &TreeEnsemble = e;
    }
}

/// ½ βᵀKβ + ε‖β‖₁ − yᵀβ of a fitted SVR (on its own standardised rows) — the ε-SVR dual
/// objective both solvers minimise.
fn svr_dual_objective(
    m: &greybox_model::svr::SvrModel,
    z_rows: &Matrix,
    y: &[f64],
    epsilon: f64,
) -> f64 {
    use greybox_model::svr::kernel_value;
    // β per training row: match support vectors to rows
    let mut beta = vec![0.0; z_rows.n_rows];
    for (k, c) in m.coef.iter().enumerate() {
        let sv = m.support.row(k);
        let r = (0..z_rows.n_rows)
            .find(|&r| z_rows.row(r) == sv)
            .expect("a support vector is a row");
        beta[r] += c;
    }
    let kv = |i: usize, j: usize| {
        kernel_value(
            m.kernel,
            m.gamma,
            m.degree,
            m.coef0,
            z_rows.row(i),
            z_rows.row(j),
        )
    };
    let mut quad = 0.0;
    for i in 0..beta.len() {
        if beta[i] == 0.0 {
            continue;
        }
        for j in 0..beta.len() {
            quad += beta[i] * beta[j] * kv(i, j);
        }
    }
    0.5 * quad + epsilon * beta.iter().map(|b| b.abs()).sum::<f64>()
        - y.iter().zip(&beta).map(|(a, b)| a * b).sum::<f64>()
}

#[test]
fn interior_point_svr_reaches_the_dual_optimum_smo_approaches() {
    use greybox_model::matrix::Standardizer;
    use greybox_model::svr::SvrSolver;
    let (x, y) = data(200, 0.01, 11, false);
    let z = Standardizer::fit(&x).transform(&x);
    for kernel in [Kernel::Linear, Kernel::Poly] {
        for c in [0.1, 10.0, 100.0] {
            for eps in [0.005, 0.05] {
                let p = SvrParams {
                    kernel,
                    c,
                    epsilon: eps,
                    ..Default::default()
                };
                let smo = SvrParams {
                    solver: SvrSolver::Smo,
                    ..p.clone()
                };
                let a = p.fit(&x, &y, 0).unwrap();
                let b = smo.fit(&x, &y, 0).unwrap();
                let (oa, ob) = (
                    svr_dual_objective(&a, &z, &y, eps),
                    svr_dual_objective(&b, &z, &y, eps),
                );
                let dev = (0..x.n_rows)
                    .map(|r| (a.predict_one(x.row(r)) - b.predict_one(x.row(r))).abs())
                    .fold(0.0, f64::max);
                eprintln!("{kernel:?} C={c} eps={eps}: objective ipm {oa:.9} smo {ob:.9}; max |Δf| {dev:.2e}; {} vs {} iterations", a.iterations, b.iterations);
                // the interior-point solution is optimal: never worse than SMO's, which stops at
                // a KKT violation of 1e-3
                assert!(
                    oa <= ob + 1e-9 * ob.abs().max(1.0),
                    "{kernel:?} C={c}: {oa} > {ob}"
                );
                assert!(
                    dev < 5e-3,
                    "{kernel:?} C={c} eps={eps}: predictions differ by {dev}"
                );
            }
        }
    }
}

/// Block prediction (trees chunk by chunk over blocks of rows) gives every row the bits of
/// its one-row prediction, for f64 and f32 leaf sums, over several blocks and a partial one,
/// with the rows taken in the first tree's leaf order (700 rows: more than two blocks).
#[test]
fn block_predictions_equal_one_row_predictions_bit_for_bit() {
    use greybox_model::tree::Accumulation;
    let (x, y) = data(400, 0.01, 9, true);
    let (xt, _) = data(700, 0.0, 10, true);
    let (forest, boost) = forest_and_boosting(&x, &y, 21, (37, 4), 5);
    let mut boost_f32 = boost.clone();
    boost_f32.accumulation = Accumulation::F32;
    for e in [&forest, &boost, &boost_f32] {
        let block = e.predict_rows(&xt);
        assert_eq!(block.len(), xt.n_rows);
        for (i, b) in block.iter().enumerate() {
            assert_eq!(b.to_bits(), e.predict_one(xt.row(i)).to_bits(), "row {i}");
        }
    }
}
