//! Terminal and JSON output helpers (the tables and output directories are the library's).

use anyhow::Result;
use serde::Serialize;

/// Print a value as pretty JSON on stdout.
pub fn print_json<T: Serialize>(value: &T) -> Result<()> {
    println!("{}", serde_json::to_string_pretty(value)?);
    Ok(())
}

/// Print `value` as JSON (`json`), else its text report.
pub fn emit<T: Serialize>(json: bool, value: &T, text: impl FnOnce(&T) -> String) -> Result<()> {
    if json {
        return print_json(value);
    }
    print!("{}", text(value));
    Ok(())
}
