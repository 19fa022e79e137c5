//! Counts as a type: every number of things a user or a file asks for (trees, folds,
//! resamples, plan steps, increments, check points, …) is a [`Count`] whose bounds are part of
//! its type, so the cap is checked where the number enters — clap on the command line, serde
//! for Python's JSON and for TOML/JSON files — before anything is allocated or started.
//!
//! Bounds are stated once, as a type alias next to the quantity it counts
//! (`pub type Trees = Count<1, 100_000>;`); `--help` shows them (`[count: 1..=100000]`, added
//! by the command line from [`HELP_MARKER`]), and every refusal says the range:
//!
//! ```
//! use greybox_core::count::Count;
//! type Trees = Count<1, 100_000>;
//! assert_eq!("300".parse::<Trees>().unwrap().get(), 300);
//! let e = "1000000000".parse::<Trees>().unwrap_err().to_string();
//! assert_eq!(e, "1000000000 is above the cap of 100000 (a count in 1..=100000)");
//! let e = "-1".parse::<Trees>().unwrap_err().to_string();
//! assert_eq!(e, "'-1' is not a count: a whole number in 1..=100000 is expected");
//! let e: Result<Trees, _> = serde_json::from_str("0");
//! assert!(e.unwrap_err().to_string().starts_with("0 is below the least allowed 1"));
//! const DEFAULT_TREES: Trees = Trees::of(300); // out of range: a compile-time error
//! assert_eq!(DEFAULT_TREES.to_string(), "300");
//! ```
//!
//! A count that is computed (a grid from a spacing, increments from a slide length) is
//! checked with [`Count::new`] (or [`checked`] for a `f64`) before the allocation it sizes,
//! with the field named in the error.

use std::fmt;
use std::str::FromStr;

/// A whole number in `MIN..=MAX`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Count<const MIN: u64, const MAX: u64>(u64);

/// A number that is not a count of its type: why, and the range.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CountError {
    /// Not a whole number at all (`-1`, `3.5`, `lots`).
    #[error("'{given}' is not a count: a whole number in {min}..={max} is expected")]
    NotACount { given: String, min: u64, max: u64 },
    /// Below the least count that means something (`0` trees).
    #[error("{given} is below the least allowed {min} (a count in {min}..={max})")]
    Below { given: u64, min: u64, max: u64 },
    /// Above the cap.
    #[error("{given} is above the cap of {max} (a count in {min}..={max})")]
    Above { given: String, min: u64, max: u64 },
}

/// The text a count's clap parser carries (as a hidden possible value) so that the command
/// line can state the range in `--help`: `count:MIN..=MAX`.
pub const HELP_MARKER: &str = "count:";

impl<const MIN: u64, const MAX: u64> Count<MIN, MAX> {
    /// The least count.
    pub const MIN: u64 = MIN;
    /// The cap.
    pub const MAX: u64 = MAX;

    /// `n`, checked; for constants (defaults), where an out-of-range value fails to compile.
    pub const fn of(n: u64) -> Self {
        assert!(MIN <= n && n <= MAX, "count constant out of its range");
        Self(n)
    }

    /// `n` if it lies in `MIN..=MAX`.
    pub fn new(n: u64) -> Result<Self, CountError> {
        if n < MIN {
            Err(CountError::Below {
                given: n,
                min: MIN,
                max: MAX,
            })
        } else if n > MAX {
            Err(CountError::Above {
                given: n.to_string(),
                min: MIN,
                max: MAX,
            })
        } else {
            Ok(Self(n))
        }
    }

    /// `n` (a `usize` length or index computed elsewhere), checked, the error naming `field`.
    pub fn of_usize(n: usize, field: &str) -> Result<Self, String> {
        Self::new(n as u64).map_err(|e| format!("{field}: {e}"))
    }

    /// The count, as a length.
    pub fn get(self) -> usize {
        // MAX fits a usize wherever greybox runs (64-bit targets); saturate elsewhere.
        usize::try_from(self.0).unwrap_or(usize::MAX)
    }

    /// The count, as a `u64`.
    pub fn as_u64(self) -> u64 {
        self.0
    }

    /// The range as text: `1..=100000`.
    pub fn range_text() -> String {
        format!("{MIN}..={MAX}")
    }
}

/// A computed count given as a float (`ceil(slide / element)`), checked before it is used:
/// NaN and infinities are refused like any count above the cap.
///
/// ```
/// use greybox_core::count::{checked, Count};
/// let n: Count<1, 1000> = checked(12.0, "increments").unwrap();
/// assert_eq!(n.get(), 12);
/// let e = checked::<1, 1000>(1e12, "increments").unwrap_err();
/// assert_eq!(e, "increments: 1000000000000 is above the cap of 1000 (a count in 1..=1000)");
/// assert!(checked::<1, 1000>(f64::NAN, "increments").is_err());
/// ```
pub fn checked<const MIN: u64, const MAX: u64>(
    value: f64,
    field: &str,
) -> Result<Count<MIN, MAX>, String> {
    let err = |e: CountError| format!("{field}: {e}");
    if value.is_nan() || value < 0.0 {
        return Err(err(CountError::NotACount {
            given: format!("{value}"),
            min: MIN,
            max: MAX,
        }));
    }
    if value > MAX as f64 {
        return Err(err(CountError::Above {
            given: format!("{value:.0}"),
            min: MIN,
            max: MAX,
        }));
    }
    Count::new(value as u64).map_err(err)
}

impl<const MIN: u64, const MAX: u64> Default for Count<MIN, MAX> {
    /// The least count (as `usize::default()` is 0): a settings type whose default is
    /// another count states it (`Count::of`).
    fn default() -> Self {
        Self(MIN)
    }
}

impl<const MIN: u64, const MAX: u64> fmt::Display for Count<MIN, MAX> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl<const MIN: u64, const MAX: u64> FromStr for Count<MIN, MAX> {
    type Err = CountError;
    /// Digits only (an optional `+`); a number too large for 64 bits is above the cap, not
    /// "not a number".
    fn from_str(s: &str) -> Result<Self, CountError> {
        let t = s.trim();
        let digits = t.strip_prefix('+').unwrap_or(t);
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(CountError::NotACount {
                given: s.to_string(),
                min: MIN,
                max: MAX,
            });
        }
        match digits.parse::<u64>() {
            Ok(n) => Self::new(n),
            Err(_) => Err(CountError::Above {
                given: digits.to_string(),
                min: MIN,
                max: MAX,
            }),
        }
    }
}

impl<const MIN: u64, const MAX: u64> serde::Serialize for Count<MIN, MAX> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u64(self.0)
    }
}

impl<'de, const MIN: u64, const MAX: u64> serde::Deserialize<'de> for Count<MIN, MAX> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(CountVisitor::<MIN, MAX>)
    }
}

struct CountVisitor<const MIN: u64, const MAX: u64>;

impl<const MIN: u64, const MAX: u64> serde::de::Visitor<'_> for CountVisitor<MIN, MAX> {
    type Value = Count<MIN, MAX>;
    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "a whole number in {MIN}..={MAX}")
    }
    fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Self::Value, E> {
        Count::new(v).map_err(E::custom)
    }
    fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Self::Value, E> {
        u64::try_from(v)
            .map_err(|_| CountError::NotACount {
                given: v.to_string(),
                min: MIN,
                max: MAX,
            })
            .and_then(Count::new)
            .map_err(E::custom)
    }
    fn visit_u128<E: serde::de::Error>(self, v: u128) -> Result<Self::Value, E> {
        u64::try_from(v)
            .map_err(|_| CountError::Above {
                given: v.to_string(),
                min: MIN,
                max: MAX,
            })
            .and_then(Count::new)
            .map_err(E::custom)
    }
    fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Self::Value, E> {
        Err(E::custom(CountError::NotACount {
            given: v.to_string(),
            min: MIN,
            max: MAX,
        }))
    }
    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Self::Value, E> {
        v.parse().map_err(E::custom)
    }
}

/// The clap parser of a [`Count`] (`#[arg(long)] trees: Trees` needs nothing more): it
/// refuses with the range, and carries [`HELP_MARKER`] so `--help` can state it.
#[cfg(feature = "clap")]
mod clap_parser {
    use super::{Count, HELP_MARKER};
    use clap::builder::{PossibleValue, TypedValueParser, ValueParserFactory};

    /// Parses a [`Count`] of the range `MIN..=MAX`.
    #[derive(Clone, Copy, Debug)]
    pub struct CountParser<const MIN: u64, const MAX: u64>;

    impl<const MIN: u64, const MAX: u64> TypedValueParser for CountParser<MIN, MAX> {
        type Value = Count<MIN, MAX>;
        fn parse_ref(
            &self,
            cmd: &clap::Command,
            arg: Option<&clap::Arg>,
            value: &std::ffi::OsStr,
        ) -> Result<Self::Value, clap::Error> {
            let text = value.to_string_lossy();
            text.parse().map_err(|e: super::CountError| {
                let name = arg.map_or_else(|| "value".to_string(), |a| a.to_string());
                clap::Error::raw(
                    clap::error::ErrorKind::ValueValidation,
                    format!("invalid value for '{name}': {e}\n"),
                )
                .with_cmd(cmd)
            })
        }
        fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
            let marker = format!("{HELP_MARKER}{MIN}..={MAX}");
            Some(Box::new(std::iter::once(
                PossibleValue::new(marker).hide(true),
            )))
        }
    }

    impl<const MIN: u64, const MAX: u64> ValueParserFactory for Count<MIN, MAX> {
        type Parser = CountParser<MIN, MAX>;
        fn value_parser() -> Self::Parser {
            CountParser
        }
    }
}

#[cfg(feature = "clap")]
pub use clap_parser::CountParser;

#[cfg(test)]
mod tests {
    use super::*;
    type C = Count<2, 1000>;

    #[test]
    fn hostile_counts_are_refused_with_the_range() {
        for (given, want) in [
            ("0", "0 is below the least allowed 2 (a count in 2..=1000)"),
            (
                "-1",
                "'-1' is not a count: a whole number in 2..=1000 is expected",
            ),
            ("1000000000", "1000000000 is above the cap of 1000"),
            ("1000000000000000000", "above the cap of 1000"),
            ("99999999999999999999999", "above the cap of 1000"),
            ("1e9", "'1e9' is not a count"),
            ("3.5", "'3.5' is not a count"),
            ("", "is not a count"),
        ] {
            let e = given.parse::<C>().unwrap_err().to_string();
            assert!(e.contains(want), "{given}: {e}");
        }
        assert_eq!("+7".parse::<C>().unwrap().get(), 7);
        assert_eq!(" 1000".parse::<C>().unwrap().get(), 1000);
    }

    #[test]
    fn serde_checks_the_range_for_json_and_toml() {
        let ok: C = serde_json::from_str("12").unwrap();
        assert_eq!(ok.as_u64(), 12);
        assert_eq!(serde_json::to_string(&ok).unwrap(), "12");
        for bad in ["1", "1001", "-3", "2.5", "1e300", "18446744073709551616"] {
            let e = serde_json::from_str::<C>(bad).unwrap_err().to_string();
            assert!(e.contains("2..=1000"), "{bad}: {e}");
        }
    }

    #[test]
    fn computed_counts_refuse_nan_and_huge_values() {
        assert!(checked::<1, 10>(f64::INFINITY, "n")
            .unwrap_err()
            .contains("above"));
        assert!(checked::<1, 10>(-1.0, "n")
            .unwrap_err()
            .contains("not a count"));
        assert_eq!(
            checked::<1, 10>(0.0, "n").unwrap_err(),
            "n: 0 is below the least allowed 1 (a count in 1..=10)"
        );
        assert_eq!(
            C::of_usize(5000, "grid").unwrap_err(),
            "grid: 5000 is above the cap of 1000 (a count in 2..=1000)"
        );
    }
}
