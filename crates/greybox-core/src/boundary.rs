//! Exact boundaries of monotone floating-point predicates.
//!
//! A split `g(x) <= t`, where `g` is a chain of roundings that never decreases as `x` grows
//! (a unit conversion, a scaler, a cast to `f32`), holds exactly for `x <= b` for one f64 `b`.
//! [`last_true`] finds `b` by bisection over the ordered f64 bit patterns (at most 64 steps),
//! so a threshold stated in one space (a model's float32 features, a scaled feature) can be
//! restated in another (raw SI inputs) without losing a single point.

/// The f64 `x` of an ordered key (see [`key`]).
fn from_key(k: i64) -> f64 {
    if k >= 0 {
        f64::from_bits(k as u64)
    } else {
        f64::from_bits((-(k + 1)) as u64 | (1 << 63))
    }
}

/// An integer key that orders f64 values as numbers (−0 just before +0; NaN excluded):
/// non-negative values keep their bit pattern, a negative one −(|bits|) − 1.
fn key(x: f64) -> i64 {
    let b = x.to_bits() as i64;
    if b >= 0 {
        b
    } else {
        -(b & i64::MAX) - 1
    }
}

/// The largest f64 `x` (±∞ included) with `holds(x)`, for a predicate that holds on a
/// down-set of the reals: once false, it stays false as `x` grows. `None` when it holds for
/// no `x` (not even −∞); `Some(∞)` when it holds everywhere.
///
/// ```
/// use greybox_core::boundary::last_true;
/// // A float32 feature compared with a float64 threshold, as scikit-learn's trees do:
/// // (x as f32) as f64 <= 0.1 holds exactly up to the boundary found.
/// let t = 0.1_f64;
/// let b = last_true(|x| (x as f32) as f64 <= t).unwrap();
/// assert!((b as f32) as f64 <= t && (b.next_up() as f32) as f64 > t);
/// assert_eq!(last_true(|x| x <= 2.5), Some(2.5));
/// assert_eq!(last_true(|_| false), None);
/// ```
pub fn last_true(holds: impl Fn(f64) -> bool) -> Option<f64> {
    let (mut lo, mut hi) = (key(f64::NEG_INFINITY), key(f64::INFINITY));
    if !holds(from_key(lo)) {
        return None;
    }
    if holds(from_key(hi)) {
        return Some(f64::INFINITY);
    }
    // invariant: holds(lo), !holds(hi)
    while (hi as i128) - (lo as i128) > 1 {
        let mid = ((lo as i128 + hi as i128) / 2) as i64;
        if holds(from_key(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(from_key(lo))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_order_like_numbers() {
        let xs = [
            f64::NEG_INFINITY,
            -f64::MAX,
            -1.0,
            -f64::MIN_POSITIVE,
            -0.0,
            0.0,
            5e-324,
            1.0,
            f64::MAX,
            f64::INFINITY,
        ];
        for w in xs.windows(2) {
            assert!(key(w[0]) < key(w[1]), "{} {}", w[0], w[1]);
        }
        for x in xs {
            assert_eq!(from_key(key(x)).to_bits(), x.to_bits());
        }
    }

    #[test]
    fn float32_boundaries_are_exact() {
        for t in [0.1, -0.3, 1e-40, 3.0e38, 123.456, -7.0] {
            let b = last_true(|x| (x as f32) as f64 <= t).unwrap();
            assert!((b as f32) as f64 <= t);
            assert!((b.next_up() as f32) as f64 > t, "t = {t}");
        }
    }
}
