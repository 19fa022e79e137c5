//! Plain decimal numbers (`-12.345`, `7`, `.5`) parsed exactly and fast.
//!
//! Recordings are mostly short decimals without an exponent. Such a number with at most 15
//! significant digits is an integer mantissa `m < 10^15 < 2^53` and a power of ten `10^k`
//! with `k ≤ 15`; both are exact in binary64, so `m / 10^k` is one correctly rounded IEEE
//! division and equals the correctly rounded value of the decimal (Clinger, "How to read
//! floating point numbers accurately", PLDI 1990, the fast path). Anything else (an exponent,
//! more digits) returns `None` and the caller falls back to a general parser (`fast-float2`).

/// 10^0 … 10^15, all exact in binary64.
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// The plain decimal at the start of `s` with `mark` as the decimal mark (`b'.'` or `b','`):
/// its value and the bytes it used. `None` when the start is not a plain decimal of at most
/// 15 digits, or when an exponent follows (the caller then parses it the general way).
#[inline]
pub fn parse_plain_prefix(s: &[u8], mark: u8) -> Option<(f64, usize)> {
    let mut i = 0;
    let negative = match s.first() {
        Some(b'-') => {
            i = 1;
            true
        }
        Some(b'+') => {
            i = 1;
            false
        }
        _ => false,
    };
    let mut mantissa: u64 = 0;
    let int_start = i;
    i = accumulate_digits(s, i, &mut mantissa);
    let mut digits = i - int_start;
    let mut fraction = 0;
    if i < s.len() && s[i] == mark {
        let frac_start = i + 1;
        i = accumulate_digits(s, frac_start, &mut mantissa);
        fraction = i - frac_start;
        digits += fraction;
    }
    if digits == 0 || digits > 15 || matches!(s.get(i), Some(b'e' | b'E')) {
        return None;
    }
    let v = mantissa as f64 / POW10[fraction];
    Some((if negative { -v } else { v }, i))
}

/// Append the decimal digits of `s` from `i` on to `mantissa` (wrapping: the caller rejects
/// more than 15 digits); the index of the first non-digit.
#[inline(always)]
fn accumulate_digits(s: &[u8], mut i: usize, mantissa: &mut u64) -> usize {
    while i < s.len() {
        let d = s[i].wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        *mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    i
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Against Rust's standard parser (correctly rounded), on random plain decimals.
    #[test]
    fn equals_std_parse_bit_for_bit() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for _ in 0..200_000 {
            let int_digits = rng.gen_range(0..9);
            let frac_digits = rng.gen_range(0..(16 - int_digits).min(12));
            if int_digits + frac_digits == 0 {
                continue;
            }
            let mut s = String::new();
            if rng.gen_bool(0.4) {
                s.push('-');
            }
            for _ in 0..int_digits {
                s.push(char::from(b'0' + rng.gen_range(0..10u8)));
            }
            if frac_digits > 0 || rng.gen_bool(0.2) {
                s.push('.');
            }
            for _ in 0..frac_digits {
                s.push(char::from(b'0' + rng.gen_range(0..10u8)));
            }
            let want: f64 = s.parse().unwrap();
            let (got, used) = parse_plain_prefix(s.as_bytes(), b'.').expect(&s);
            assert_eq!(used, s.len(), "{s}");
            assert_eq!(got.to_bits(), want.to_bits(), "{s}");
            let comma = s.replace('.', ",");
            let (got, _) = parse_plain_prefix(comma.as_bytes(), b',').expect(&comma);
            assert_eq!(got.to_bits(), want.to_bits(), "{comma}");
        }
    }

    #[test]
    fn stops_at_the_first_other_byte_and_declines_the_rest() {
        assert_eq!(parse_plain_prefix(b"1.25,3", b'.'), Some((1.25, 4)));
        assert_eq!(parse_plain_prefix(b"-0.5;", b'.'), Some((-0.5, 4)));
        assert_eq!(parse_plain_prefix(b"+3", b'.'), Some((3.0, 2)));
        assert_eq!(parse_plain_prefix(b".5", b'.'), Some((0.5, 2)));
        assert_eq!(parse_plain_prefix(b"7.", b'.'), Some((7.0, 2)));
        assert!(parse_plain_prefix(b"-0", b'.')
            .unwrap()
            .0
            .is_sign_negative());
        // the general parser's business
        assert_eq!(parse_plain_prefix(b"1e5", b'.'), None);
        assert_eq!(parse_plain_prefix(b"1.5E-3", b'.'), None);
        assert_eq!(parse_plain_prefix(b"1234567890.1234567", b'.'), None);
        // not numbers
        assert_eq!(parse_plain_prefix(b"", b'.'), None);
        assert_eq!(parse_plain_prefix(b"-", b'.'), None);
        assert_eq!(parse_plain_prefix(b".", b'.'), None);
        assert_eq!(parse_plain_prefix(b"nan", b'.'), None);
        assert_eq!(parse_plain_prefix(b"abc", b'.'), None);
    }
}
