//! Tiny dense linear algebra for small least-squares fits.

/// Solve the 3 × 3 system a x = b by Gaussian elimination with partial pivoting;
/// `None` if it is singular.
pub fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for k in 0..3 {
        let p = (k..3).max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))?;
        if a[p][k].abs() < 1e-300 {
            return None;
        }
        a.swap(k, p);
        b.swap(k, p);
        for i in k + 1..3 {
            let f = a[i][k] / a[k][k];
            let row = a[k];
            for (x, y) in a[i].iter_mut().zip(row.iter()).skip(k) {
                *x -= f * y;
            }
            b[i] -= f * b[k];
        }
    }
    let mut x = [0.0; 3];
    for k in (0..3).rev() {
        x[k] = (b[k] - (k + 1..3).map(|j| a[k][j] * x[j]).sum::<f64>()) / a[k][k];
    }
    Some(x)
}

/// Least-squares power law y = a xᵇ on ln y = ln a + b ln x; `None` unless every point is
/// positive and there are at least two distinct x.
pub fn fit_power_law(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    if points.len() < 2 || points.iter().any(|&(x, y)| !(x > 0.0 && y > 0.0)) {
        return None;
    }
    let n = points.len() as f64;
    let (xm, ym) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + x.ln() / n, b + y.ln() / n)
    });
    let sxx: f64 = points.iter().map(|&(x, _)| (x.ln() - xm).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let b = points
        .iter()
        .map(|&(x, y)| (x.ln() - xm) * (y.ln() - ym))
        .sum::<f64>()
        / sxx;
    Some(((ym - b * xm).exp(), b))
}

#[cfg(test)]
mod tests {
    /// Exact points of y = 3 x^0.4 give back (3, 0.4); one distinct x or a non-positive value
    /// gives None.
    #[test]
    fn power_law_recovers_exact_points() {
        let pts: Vec<(f64, f64)> = [1.0, 10.0, 150.0]
            .iter()
            .map(|&x| (x, 3.0 * f64::powf(x, 0.4)))
            .collect();
        let (a, b) = super::fit_power_law(&pts).unwrap();
        assert!((a - 3.0).abs() < 1e-12 && (b - 0.4).abs() < 1e-12);
        assert!(super::fit_power_law(&[(2.0, 1.0), (2.0, 3.0)]).is_none());
        assert!(super::fit_power_law(&[(2.0, 1.0), (3.0, 0.0)]).is_none());
    }

    #[test]
    fn solves() {
        let a = [[2.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 4.0]];
        let x = super::solve3(a, [3.0, 5.0, 5.0]).unwrap();
        for (xi, e) in x.iter().zip([1.0, 1.0, 1.0]) {
            assert!((xi - e).abs() < 1e-14);
        }
        assert!(super::solve3(
            [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]],
            [1.0, 2.0, 3.0]
        )
        .is_none());
    }
}
