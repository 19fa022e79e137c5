//! tanh and exp over a slice in straight-line arithmetic that the compiler vectorises, for
//! training: the MLP's passes (libm's `tanh` is a call per element and was a third of the
//! MLP's time at 10⁴ rows) and the SVR's rbf and sigmoid kernel rows. Inference keeps libm
//! (`greybox_model::mlp`, `greybox_model::svr`), so imported models still match
//! scikit-learn's to the last bits.
//!
//! With a = min(|x|, 20) and r = −2a, tanh(x) = sign(x) · (−expm1(r)) / (2 + expm1(r)):
//! - |r| < 0.7: expm1 by its Taylor series to r¹⁷ (truncation below 10⁻¹⁷ relative);
//! - otherwise: exp(r) − 1, exp by Cody–Waite reduction r = k ln 2 + s, |s| ≤ ln 2 / 2
//!   (ln 2 split into a high part with trailing zeros and a low part, as in fdlibm's
//!   `exp`), e^s by its Taylor series to s¹³, and 2^k from the bits of k (the loss of
//!   e^r − 1 is at most one bit there, e^r ≤ 0.5).
//!
//! Both branches are computed and one is selected, so the loop has no branch. Error
//! against libm's tanh: a few ulp (the test bounds it at 4). No fused multiply-add is
//! used, so every instruction set gives the same bits.

/// 1/n! for n = 0..=17.
const INV_FACT: [f64; 18] = {
    let mut t = [1.0; 18];
    let mut n = 1;
    while n < 18 {
        t[n] = t[n - 1] / n as f64;
        n += 1;
    }
    t
};

/// Rounds to the nearest integer (ties to even) when added and subtracted (|v| < 2⁵¹).
const ROUNDER: f64 = 6755399441055744.0; // 1.5 · 2⁵²
/// ln 2 = LN2_HI + LN2_LO, the high part with 32 trailing zero bits (fdlibm's `ln2HI[0]`,
/// `ln2LO[0]`: 6.93147180369123816490e-01, 1.90821492927058770002e-10).
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);

/// expm1(r) for −40 ≤ r ≤ 0, branch-free (module docs).
#[inline(always)]
fn expm1_nonpositive(r: f64) -> f64 {
    // Taylor series of expm1 about 0: r + r²/2! + … + r¹⁷/17!.
    let mut small = INV_FACT[17];
    for n in (1..17).rev() {
        small = small * r + INV_FACT[n];
    }
    small *= r;
    let large = exp_normal(r) - 1.0;
    if r > -0.7 {
        small
    } else {
        large
    }
}

/// Smallest r whose exp is a normal number (e^−708 ≈ 3.3·10⁻³⁰⁸ > 2⁻¹⁰²²).
const EXP_NORMAL_MIN: f64 = -708.0;

/// exp(r) for −708 ≤ r ≤ 709 (results that are normal numbers), branch-free.
#[inline(always)]
fn exp_normal(r: f64) -> f64 {
    // exp(r) = 2^k · e^s.
    let kf = r * std::f64::consts::LOG2_E + ROUNDER;
    let k = kf - ROUNDER;
    let s = (r - k * LN2_HI) - k * LN2_LO;
    let mut es = INV_FACT[13];
    for n in (0..13).rev() {
        es = es * s + INV_FACT[n];
    }
    // The low bits of kf hold k (two's complement): 2^k = (k + 1023) << 52.
    let k_int = kf.to_bits().wrapping_sub(ROUNDER.to_bits());
    let two_k = f64::from_bits(k_int.wrapping_add(1023) << 52);
    es * two_k
}

/// exp of every element of `v`, in place, for arguments ≤ 0 (the rbf kernel's −γ‖x − x'‖²):
/// within 2 ulp of libm down to −708; below, where libm's result is subnormal or 0, exactly
/// 0 (an error under 3.3·10⁻³⁰⁸). NaN stays NaN. Inlined, like [`tanh_in_place`].
#[inline(always)]
pub fn exp_nonpositive_in_place(v: &mut [f64]) {
    for x in v.iter_mut() {
        let r = x.clamp(EXP_NORMAL_MIN, 0.0);
        let e = exp_normal(r);
        *x = if x.is_nan() {
            *x
        } else if *x < EXP_NORMAL_MIN {
            0.0
        } else {
            e
        };
    }
}

/// tanh of every element of `v`, in place. Inlined, so that it is vectorised for the
/// instruction set of its caller (the MLP's training runs AVX2 where the CPU has it).
#[inline(always)]
pub fn tanh_in_place(v: &mut [f64]) {
    for x in v.iter_mut() {
        let a = x.abs().min(20.0);
        let e = expm1_nonpositive(-2.0 * a);
        let t = -e / (2.0 + e);
        // tanh(−0) = −0 and NaN stays NaN (the sign is copied, the NaN propagates).
        *x = if x.is_nan() { *x } else { t.copysign(*x) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ulps(a: f64, b: f64) -> u64 {
        if a == b {
            return 0;
        }
        let ia = a.to_bits() as i64;
        let ib = b.to_bits() as i64;
        (ia - ib).unsigned_abs()
    }

    /// The largest distance in ulp between `fast` over `xs` and `libm` at each x, with the x.
    fn worst_ulps(xs: &[f64], fast: fn(&mut [f64]), libm: fn(f64) -> f64) -> (u64, f64) {
        let mut got = xs.to_vec();
        fast(&mut got);
        let mut worst = (0, 0.0);
        for (&x, &g) in xs.iter().zip(&got) {
            let u = ulps(g, libm(x));
            if u > worst.0 {
                worst = (u, x);
            }
        }
        worst
    }

    #[test]
    fn within_four_ulp_of_libm_over_the_range() {
        let mut xs: Vec<f64> = Vec::new();
        // Dense around the branch point, log-spaced small values, linear to saturation.
        for i in 0..200_000 {
            xs.push(-25.0 + 50.0 * i as f64 / 200_000.0);
        }
        for i in 0..2_000 {
            let v = 10f64.powf(-300.0 + 300.0 * i as f64 / 2_000.0);
            xs.push(v);
            xs.push(-v);
        }
        for i in 0..2_000 {
            xs.push(0.34 + 0.02 * i as f64 / 2_000.0);
        }
        let worst = worst_ulps(&xs, tanh_in_place, f64::tanh);
        assert!(worst.0 <= 4, "{} ulp at x = {}", worst.0, worst.1);
    }

    #[test]
    fn exp_within_two_ulp_of_libm_and_zero_below_the_normal_range() {
        let mut xs: Vec<f64> = (0..200_000)
            .map(|i| -708.0 * i as f64 / 200_000.0)
            .collect();
        xs.extend((0..2_000).map(|i| -(10f64.powf(-300.0 + 300.0 * i as f64 / 2_000.0))));
        xs.extend([0.0, -0.0, -0.7, -1e-300]);
        let worst = worst_ulps(&xs, exp_nonpositive_in_place, f64::exp);
        assert!(worst.0 <= 2, "{} ulp at x = {}", worst.0, worst.1);
        let mut low = [-708.5, -745.0, -1e300, f64::NEG_INFINITY, f64::NAN];
        exp_nonpositive_in_place(&mut low);
        assert_eq!(&low[..4], &[0.0; 4]);
        assert!(low[4].is_nan());
    }

    #[test]
    fn signs_limits_and_nan() {
        let mut v = [
            0.0,
            -0.0,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        tanh_in_place(&mut v);
        assert_eq!(v[0].to_bits(), 0.0f64.to_bits());
        assert_eq!(v[1].to_bits(), (-0.0f64).to_bits());
        assert_eq!(&v[2..6], &[1.0, -1.0, 1.0, -1.0]);
        assert!(v[6].is_nan());
    }
}
