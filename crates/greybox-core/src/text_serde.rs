//! serde of a value written as text (`64x32`, `a.csv@500`): through its `Display` and its
//! `FromStr`, whose error text is serde's error, so that settings read the same text from
//! JSON and TOML as the command line reads from a flag.
//!
//! ```
//! use std::str::FromStr;
//! #[derive(Debug, PartialEq)]
//! struct Pair(u32, u32);
//! impl FromStr for Pair {
//!     type Err = String;
//!     fn from_str(s: &str) -> Result<Self, String> {
//!         let (a, b) = s.split_once('x').ok_or(format!("'{s}': expected AxB"))?;
//!         Ok(Pair(a.parse().map_err(|_| "A")?, b.parse().map_err(|_| "B")?))
//!     }
//! }
//! impl std::fmt::Display for Pair {
//!     fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
//!         write!(f, "{}x{}", self.0, self.1)
//!     }
//! }
//! greybox_core::text_serde!(Pair);
//! assert_eq!(serde_json::from_str::<Pair>(r#""3x4""#).unwrap(), Pair(3, 4));
//! assert_eq!(serde_json::to_string(&Pair(3, 4)).unwrap(), r#""3x4""#);
//! let e = serde_json::from_str::<Pair>(r#""3-4""#).unwrap_err().to_string();
//! assert!(e.starts_with("'3-4': expected AxB"), "{e}");
//! ```

/// `Serialize` through `Display` and `Deserialize` through `FromStr` for `$t` (its `Err`
/// displayed as the serde error).
#[macro_export]
macro_rules! text_serde {
    ($t:ty) => {
        impl ::serde::Serialize for $t {
            fn serialize<S: ::serde::Serializer>(
                &self,
                s: S,
            ) -> ::std::result::Result<S::Ok, S::Error> {
                s.collect_str(self)
            }
        }
        impl<'de> ::serde::Deserialize<'de> for $t {
            fn deserialize<D: ::serde::Deserializer<'de>>(
                d: D,
            ) -> ::std::result::Result<Self, D::Error> {
                let text = <::std::string::String as ::serde::Deserialize>::deserialize(d)?;
                <$t as ::std::str::FromStr>::from_str(&text).map_err(::serde::de::Error::custom)
            }
        }
    };
}
