//! The cached, shrinking SMO of `greybox-learn` against the full-matrix solver it replaced
//! (`common/old_svr.rs`, kept verbatim as the reference): the same iterates, bit for bit.

mod common;

use common::old_svr;
use greybox_learn::svr_test_kit;
use greybox_model::matrix::Standardizer;
use greybox_model::svr::{Kernel, SvrParams};
use greybox_model::Matrix;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// μ(F, v) falling with load and speed, 1 % noise; standardised rows.
fn data(n: usize, seed: u64) -> (Matrix, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let normal = rand_distr::Normal::new(0.0, 1.0).unwrap();
    let mut rows = Vec::new();
    let mut y = Vec::new();
    for _ in 0..n {
        let f: f64 = rng.gen_range(150.0..2000.0);
        let v: f64 = rng.gen_range(20.0..250.0);
        let e: f64 = rand_distr::Distribution::sample(&normal, &mut rng);
        rows.push(vec![f, v]);
        y.push((0.2 + 0.45 * (f / 150.0).powf(-0.18) * (v / 20.0).powf(-0.2)) * (1.0 + 0.01 * e));
    }
    let x = Matrix::from_rows(&rows);
    (Standardizer::fit(&x).transform(&x), y)
}

/// The cached, shrinking solver takes the full-matrix solver's steps exactly: the same α,
/// the same gradient (so the same dual objective, ρ and predictions) and the same number
/// of iterations, bit for bit, whether the cache holds the whole matrix, a few rows, or
/// only the two of the working set; and again on a second run.
#[test]
fn cached_smo_takes_the_full_matrix_solvers_steps_bit_for_bit() {
    let (z, y) = data(300, 5);
    let l = z.n_rows;
    for (kernel, c, epsilon) in [
        (Kernel::Rbf, 1.0, 0.005),
        (Kernel::Rbf, 100.0, 0.002),
        (Kernel::Sigmoid, 1.0, 0.005),
        (Kernel::Sigmoid, 100.0, 0.001),
    ] {
        let p = SvrParams {
            kernel,
            c,
            epsilon,
            ..Default::default()
        };
        let want = old_svr::solve(&p, &z, &y, 0.5);
        // shrinking (every l iterations here) must have run for the comparison to cover it
        assert!(want.iterations > l, "{kernel:?} C={c}: {}", want.iterations);
        for bytes in [usize::MAX / 2, 8 * l * 7, 0, 0] {
            let got = svr_test_kit::solve(&p, &z, &y, 0.5, bytes);
            assert_eq!(
                got.iterations, want.iterations,
                "{kernel:?} C={c} cache {bytes}"
            );
            for t in 0..2 * l {
                assert_eq!(got.alpha[t].to_bits(), want.alpha[t].to_bits(), "α_{t}");
                assert_eq!(got.grad[t].to_bits(), want.grad[t].to_bits(), "G_{t}");
            }
        }
        eprintln!(
            "{kernel:?} C={c} ε={epsilon}: {} iterations",
            want.iterations
        );
    }
}
