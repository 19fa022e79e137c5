//! Configuration TOML read one way everywhere: a regular file within the input budget
//! (`--max-input-mib`), deserialised with errors that name the file and line, and refused
//! when any number in it is not finite. TOML has literals for ±∞ and NaN (`inf`, `nan`);
//! no greybox setting means them, and one that slips through a range check written as
//! `x > 0.0` becomes an ∞ or NaN in an output file, so they are refused here, naming the key.

use anyhow::{bail, Context, Result};
use serde::de::DeserializeOwned;
use std::path::Path;

/// Reads the TOML file at `path` (its role in messages: `what`, e.g. "study file") into `T`.
pub fn read<T: DeserializeOwned>(path: &Path, what: &str) -> Result<T> {
    let text = read_text(path, what)?;
    parse(&text, &path.display().to_string(), what)
}

/// The text of a configuration file: a regular file within the input budget.
pub fn read_text(path: &Path, what: &str) -> Result<String> {
    Ok(greybox_core::input::read_config(path, what)?)
}

/// Parses configuration text from `source` (a file name for messages) into `T`.
pub fn parse<T: DeserializeOwned>(text: &str, source: &str, what: &str) -> Result<T> {
    Ok(parse_with_raw(text, source, what)?.0)
}

/// [`parse`], and the TOML as written (for what a file states, beside what it means).
pub fn parse_with_raw<T: DeserializeOwned>(
    text: &str,
    source: &str,
    what: &str,
) -> Result<(T, toml::Value)> {
    let value: T = toml::from_str(text).with_context(|| format!("{source}: invalid {what}"))?;
    let raw: toml::Value =
        toml::from_str(text).with_context(|| format!("{source}: invalid {what}"))?;
    check_finite(&raw, source)?;
    Ok((value, raw))
}

/// Refuses a TOML value holding ±∞ or NaN anywhere, naming its dotted key.
pub fn check_finite(value: &toml::Value, source: &str) -> Result<()> {
    match first_non_finite(value, &mut String::new()) {
        Some((key, x)) => bail!(
            "{source}: {key} = {x}: expected a finite number (TOML's inf and nan are not settings)"
        ),
        None => Ok(()),
    }
}

fn first_non_finite(value: &toml::Value, key: &mut String) -> Option<(String, f64)> {
    match value {
        toml::Value::Float(x) if !x.is_finite() => Some((key.clone(), *x)),
        toml::Value::Table(t) => t.iter().find_map(|(k, v)| {
            let len = key.len();
            if !key.is_empty() {
                key.push('.');
            }
            key.push_str(k);
            let found = first_non_finite(v, key);
            key.truncate(len);
            found
        }),
        toml::Value::Array(a) => a.iter().enumerate().find_map(|(i, v)| {
            let len = key.len();
            key.push_str(&format!("[{i}]"));
            let found = first_non_finite(v, key);
            key.truncate(len);
            found
        }),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    struct S {
        #[allow(dead_code)]
        a: f64,
        #[allow(dead_code)]
        t: Option<toml::Value>,
    }

    #[test]
    fn non_finite_numbers_are_refused_with_their_key() {
        assert!(parse::<S>("a = 1.5\n", "s.toml", "study file").is_ok());
        for (text, key) in [
            ("a = inf\n", "a = inf"),
            ("a = 1.0\n[t]\nb = -inf\n", "t.b = -inf"),
            ("a = 1.0\n[t]\nc = [1.0, nan]\n", "t.c[1] = NaN"),
            (
                "a = 1.0\n[[t.d]]\nx = 2.0\n[[t.d]]\nx = +inf\n",
                "t.d[1].x = inf",
            ),
        ] {
            let e = format!(
                "{:#}",
                parse::<S>(text, "s.toml", "study file").unwrap_err()
            );
            assert!(e.starts_with("s.toml: ") && e.contains(key), "{text}: {e}");
        }
        let e = format!(
            "{:#}",
            parse::<S>("a = \"x\"\n", "s.toml", "study file").unwrap_err()
        );
        assert!(
            e.contains("s.toml: invalid study file") && e.contains("line 1"),
            "{e}"
        );
    }
}
