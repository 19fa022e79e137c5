//! Option enums with one spelling everywhere: the command line (clap), the Python API, study
//! and sweep files all parse a value through [`Choice`], so a name accepted by one surface is
//! accepted by all, and an unknown one gets the same error listing the values.
//!
//! ```
//! use greybox_core::choice::Choice;
//! #[derive(Clone, Copy, Debug, PartialEq)]
//! enum Side { Rake, Flank }
//! impl Choice for Side {
//!     const FIELD: &'static str = "side";
//!     const ALL: &'static [Self] = &[Side::Rake, Side::Flank];
//!     fn name(self) -> &'static str {
//!         match self { Side::Rake => "rake", Side::Flank => "flank" }
//!     }
//! }
//! greybox_core::choice_traits!(Side);
//! assert_eq!("flank".parse::<Side>().unwrap(), Side::Flank);
//! assert_eq!(Side::Rake.to_string(), "rake");
//! let e = "chip".parse::<Side>().unwrap_err().to_string();
//! assert_eq!(e, "side: 'chip' is not one of rake, flank");
//! assert_eq!(serde_json::to_string(&Side::Flank).unwrap(), "\"flank\"");
//! ```

/// An option enum with a fixed list of named values.
pub trait Choice: Sized + Copy + 'static {
    /// The option's name in errors (the library's field name, e.g. `export.steps`).
    const FIELD: &'static str;
    /// Every value, in the order they are listed to users.
    const ALL: &'static [Self];
    /// The value's name (lower case, kebab-case).
    fn name(self) -> &'static str;
    /// The names of every value, in order.
    fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|c| c.name()).collect()
    }
    /// The value named `s` (exactly), or an error naming the field and listing the values.
    fn parse_choice(s: &str) -> Result<Self, UnknownChoice> {
        Self::ALL
            .iter()
            .copied()
            .find(|c| c.name() == s)
            .ok_or_else(|| UnknownChoice {
                field: Self::FIELD,
                given: s.to_string(),
                expected: Self::names().join(", "),
            })
    }
}

/// A name that is not one of a [`Choice`]'s values.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{field}: '{given}' is not one of {expected}")]
pub struct UnknownChoice {
    pub field: &'static str,
    pub given: String,
    pub expected: String,
}

/// `FromStr`, `Display`, `Serialize` and `Deserialize` of a [`Choice`] through its names
/// (`choice_traits!(T, text)`: `FromStr` and `Display` only, for a type whose serde names
/// are already its choice names).
#[macro_export]
macro_rules! choice_traits {
    ($t:ty) => {
        $crate::choice_traits!($t, text);
        impl ::serde::Serialize for $t {
            fn serialize<S: ::serde::Serializer>(
                &self,
                s: S,
            ) -> ::std::result::Result<S::Ok, S::Error> {
                s.serialize_str($crate::choice::Choice::name(*self))
            }
        }
        impl<'de> ::serde::Deserialize<'de> for $t {
            fn deserialize<D: ::serde::Deserializer<'de>>(
                d: D,
            ) -> ::std::result::Result<Self, D::Error> {
                let s = <::std::string::String as ::serde::Deserialize>::deserialize(d)?;
                <$t as $crate::choice::Choice>::parse_choice(&s).map_err(::serde::de::Error::custom)
            }
        }
    };
    ($t:ty, text) => {
        impl ::std::str::FromStr for $t {
            type Err = $crate::choice::UnknownChoice;
            fn from_str(s: &str) -> ::std::result::Result<Self, Self::Err> {
                <$t as $crate::choice::Choice>::parse_choice(s)
            }
        }
        impl ::std::fmt::Display for $t {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str($crate::choice::Choice::name(*self))
            }
        }
    };
}

/// serde of an optional list of a [`Choice`]'s values by their names, for settings
/// (`#[serde(with = "greybox_core::choice::names")]` on an `Option<Vec<T>>`): a name not among
/// them is refused as `'x' is not one of a, b, c`, the settings' path naming the field.
///
/// ```
/// # #[derive(Clone, Copy, Debug, PartialEq)]
/// # enum Side { Rake, Flank }
/// # greybox_core::choice!(Side, "side", [Rake => "rake", Flank => "flank"]);
/// #[derive(serde::Deserialize, serde::Serialize)]
/// struct S {
///     #[serde(with = "greybox_core::choice::names", default)]
///     sides: Option<Vec<Side>>,
/// }
/// let s: S = serde_json::from_str(r#"{"sides": ["flank", "rake"]}"#).unwrap();
/// assert_eq!(s.sides, Some(vec![Side::Flank, Side::Rake]));
/// let e = serde_json::from_str::<S>(r#"{"sides": ["chip"]}"#).err().unwrap().to_string();
/// assert!(e.starts_with("'chip' is not one of rake, flank"), "{e}");
/// ```
pub mod names {
    use super::{name::unknown, Choice};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// The values' names (`None` as null).
    pub fn serialize<S: Serializer, T: Choice>(
        values: &Option<Vec<T>>,
        s: S,
    ) -> Result<S::Ok, S::Error> {
        values
            .as_ref()
            .map(|v| v.iter().map(|c| c.name()).collect::<Vec<_>>())
            .serialize(s)
    }

    /// The values named (null: `None`), the first unknown name refused.
    pub fn deserialize<'de, D: Deserializer<'de>, T: Choice>(
        d: D,
    ) -> Result<Option<Vec<T>>, D::Error> {
        let Some(given) = Option::<Vec<String>>::deserialize(d)? else {
            return Ok(None);
        };
        given
            .iter()
            .map(|s| T::parse_choice(s).map_err(unknown))
            .collect::<Result<Vec<T>, D::Error>>()
            .map(Some)
    }
}

/// serde of one [`Choice`] value by its name, for settings whose type derives its serde
/// otherwise (`#[serde(with = "greybox_core::choice::name")]`): an unknown name is refused
/// as `'x' is not one of a, b, c`, as in [`names`].
pub mod name {
    use super::{Choice, UnknownChoice};
    use serde::{Deserialize, Deserializer, Serializer};

    /// The value's name.
    pub fn serialize<S: Serializer, T: Choice>(value: &T, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(value.name())
    }

    /// The value named.
    pub fn deserialize<'de, D: Deserializer<'de>, T: Choice>(d: D) -> Result<T, D::Error> {
        T::parse_choice(&String::deserialize(d)?).map_err(unknown)
    }

    /// An unknown name as a serde error, without the field (the settings' path names it).
    pub(super) fn unknown<E: serde::de::Error>(e: UnknownChoice) -> E {
        E::custom(format!("'{}' is not one of {}", e.given, e.expected))
    }
}

/// clap parsers of [`Choice`]s, so the command line accepts and lists exactly the names
/// Python and the study and sweep files accept (feature `clap`).
#[cfg(feature = "clap")]
pub mod clap_parsers {
    use super::Choice;

    /// A clap parser of a [`Choice`]: its values listed in `--help` and in errors.
    pub fn choice<T: Choice + Send + Sync + Clone>(
    ) -> impl clap::builder::TypedValueParser<Value = T> {
        use clap::builder::TypedValueParser;
        clap::builder::PossibleValuesParser::new(T::names())
            .try_map(|s| T::parse_choice(&s).map_err(|e| e.to_string()))
    }

    /// A clap parser of a [`Choice`]'s names, kept as text for settings that parse them.
    pub fn choice_name<T: Choice>() -> clap::builder::PossibleValuesParser {
        clap::builder::PossibleValuesParser::new(T::names())
    }
}

/// A [`Choice`] from its field name and each value's name, with [`choice_traits!`]
/// (`FromStr`, `Display`, serde through the names):
///
/// ```
/// #[derive(Clone, Copy, Debug, PartialEq)]
/// enum Side { Rake, Flank }
/// greybox_core::choice!(Side, "side", [Rake => "rake", Flank => "flank"]);
/// assert_eq!("rake".parse::<Side>().unwrap(), Side::Rake);
/// ```
#[macro_export]
macro_rules! choice {
    ($t:ident, $field:literal, [$($v:ident => $name:literal),+ $(,)?] $(, $text:ident)?) => {
        impl $crate::choice::Choice for $t {
            const FIELD: &'static str = $field;
            const ALL: &'static [Self] = &[$($t::$v),+];
            fn name(self) -> &'static str {
                match self {
                    $($t::$v => $name),+
                }
            }
        }
        $crate::choice_traits!($t $(, $text)?);
    };
}
