//! Root finding for expensive functions (each evaluation a simulation).

/// Illinois (modified regula falsi; Dowell & Jarratt, BIT 11, 1971) refinement of a bracket
/// of an increasing function: `lo` = (x, f(x)) with f < 0 and `hi` with f > 0. Each step
/// evaluates f at the secant point and keeps the sign change; a side kept twice in a row has
/// its stored value halved, which avoids the one-sided stalls of plain regula falsi.
///
/// Stops when an evaluation has |f| ≤ `tol` or after `max_evals` evaluations (`log` holds
/// every (x, f) evaluated here, appended). Returns the best x: the evaluated point with the
/// smallest |f| if it meets `tol`, otherwise the secant point of the final bracket, which
/// interpolates below the noise of the individual evaluations.
pub fn illinois_increasing<E>(
    mut f: impl FnMut(f64) -> std::result::Result<f64, E>,
    lo: (f64, f64),
    hi: (f64, f64),
    tol: f64,
    max_evals: usize,
    log: &mut Vec<(f64, f64)>,
) -> std::result::Result<f64, E> {
    let ((mut a, mut fa), (mut b, mut fb)) = (lo, hi);
    let mut best = if fa.abs() < fb.abs() {
        (a, fa)
    } else {
        (b, fb)
    };
    let bracketed = |fa: f64, fb: f64| fa < 0.0 && fb > 0.0;
    let mut evals = 0;
    let mut side = 0i8;
    while best.1.abs() > tol && evals < max_evals && bracketed(fa, fb) {
        let x = (a * fb - b * fa) / (fb - fa);
        let fx = f(x)?;
        evals += 1;
        log.push((x, fx));
        if fx.abs() < best.1.abs() {
            best = (x, fx);
        }
        if fx > 0.0 {
            b = x;
            fb = fx;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = x;
            fa = fx;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
    }
    Ok(if best.1.abs() > tol && bracketed(fa, fb) {
        (a * fb - b * fa) / (fb - fa)
    } else {
        best.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_root_of_a_convex_function_in_few_evaluations() {
        // f(x) = x³ + x − 3, root 1.21341166276223…
        let f = |x: f64| -> Result<f64, ()> { Ok(x.powi(3) + x - 3.0) };
        let mut log = Vec::new();
        let x = illinois_increasing(f, (0.0, -3.0), (2.0, 7.0), 1e-12, 50, &mut log).unwrap();
        assert!((x - 1.213_411_662_762_23).abs() < 1e-11, "{x}");
        assert!(log.len() < 15, "{} evaluations", log.len());
        // Budget exhausted: the secant of the last bracket, better than either end.
        let mut log = Vec::new();
        let x = illinois_increasing(f, (0.0, -3.0), (2.0, 7.0), 1e-12, 2, &mut log).unwrap();
        assert_eq!(log.len(), 2);
        assert!((x - 1.2134).abs() < 0.1);
    }
}
