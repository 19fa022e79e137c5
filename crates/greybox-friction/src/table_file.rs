//! Table files (`greybox export --format table`): JSON with `"schema": "greybox-table"` and a
//! `schema_version`.
//!
//! * version 1 (files without `schema_version`, written before exact and adaptive tables):
//!   the uniform grid of [`TabulatedLaw`];
//! * version 2: a `kind` — `"uniform"` ([`TabulatedLaw`], the same fields), `"exact"`
//!   ([`ExactTable`]: cell boundaries in SI and μ per cell) or `"adaptive"`
//!   ([`AdaptiveTable`]: non-uniform nodes in SI and μ per node).
//!
//! Axis fields carry their units: `pressure_Pa`, `sliding_velocity_m_per_s`, `temperature_K`.
//! Numbers are written in Rust's shortest round-trip form and read back bit for bit.

use crate::adaptive::AdaptiveTable;
use crate::exact_table::ExactTable;
use crate::table::TabulatedLaw;
use greybox_core::choice::Choice;
use greybox_core::{Error, FrictionLaw, Result, SourcePos};
use serde::de::DeserializeOwned;
use std::path::Path;

pub use crate::table_schema::{TableKind, TABLE_SCHEMA, TABLE_SCHEMA_VERSION};

/// A table of any kind.
#[derive(Debug, Clone)]
pub enum AnyTable {
    Uniform(TabulatedLaw),
    Exact(ExactTable),
    Adaptive(AdaptiveTable),
}

impl AnyTable {
    pub fn kind(&self) -> TableKind {
        match self {
            AnyTable::Uniform(_) => TableKind::Uniform,
            AnyTable::Exact(_) => TableKind::Exact,
            AnyTable::Adaptive(_) => TableKind::Adaptive,
        }
    }
    /// The table as a law.
    pub fn law(&self) -> &dyn FrictionLaw {
        match self {
            AnyTable::Uniform(t) => t,
            AnyTable::Exact(t) => t,
            AnyTable::Adaptive(t) => t,
        }
    }
    /// The table as an owned law.
    pub fn into_law(self) -> Box<dyn FrictionLaw> {
        match self {
            AnyTable::Uniform(t) => Box::new(t),
            AnyTable::Exact(t) => Box::new(t),
            AnyTable::Adaptive(t) => Box::new(t),
        }
    }
    /// Grid lines (uniform, adaptive: nodes; exact: cells) per axis: pressure, velocity,
    /// temperature (1 when the table has no temperature axis).
    pub fn shape(&self) -> [usize; 3] {
        match self {
            AnyTable::Uniform(t) => [t.pressure.n, t.velocity.n, t.temperature.map_or(1, |a| a.n)],
            AnyTable::Exact(t) => t.shape(),
            AnyTable::Adaptive(t) => t.shape(),
        }
    }
    /// Stored μ values (nodes or cells).
    pub fn len(&self) -> usize {
        self.shape().iter().product()
    }
    /// Never: a table has at least one value.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The max deviation from the source recorded when the table was built.
    pub fn max_deviation(&self) -> Option<f64> {
        match self {
            AnyTable::Uniform(t) => t.max_deviation,
            AnyTable::Exact(t) => t.max_deviation,
            AnyTable::Adaptive(t) => t.max_deviation,
        }
    }
    /// The JSON text of the file.
    pub fn to_json(&self) -> Result<String> {
        let r = match self {
            AnyTable::Uniform(t) => serde_json::to_string(t),
            AnyTable::Exact(t) => serde_json::to_string(t),
            AnyTable::Adaptive(t) => serde_json::to_string(t),
        };
        r.map_err(|e| Error::invalid("table", e.to_string()))
    }
}

/// Read a table file of any version and kind.
pub fn read_table(path: &Path) -> Result<AnyTable> {
    let text = greybox_core::input::read_regular_text(path, "table file")?;
    parse_table(&text, path)
}

/// Parse table text; `path` names the file in errors (with the line, or the field).
pub fn parse_table(text: &str, path: &Path) -> Result<AnyTable> {
    let pos = || SourcePos::path(path);
    let v: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        Error::input(
            pos().line(e.line() as u64),
            format!("not a greybox table: {e}"),
        )
    })?;
    if v.get("schema").and_then(|s| s.as_str()) != Some(TABLE_SCHEMA) {
        return Err(Error::input(
            pos().field("schema"),
            format!("expected schema \"{TABLE_SCHEMA}\""),
        ));
    }
    let version = match v.get("schema_version") {
        None => 1,
        Some(n) => n
            .as_u64()
            .filter(|&n| (1..=TABLE_SCHEMA_VERSION as u64).contains(&n))
            .ok_or_else(|| {
                Error::input(
                    pos().field("schema_version"),
                    format!(
                        "expected 1 to {TABLE_SCHEMA_VERSION}, found {n} (a table from a newer greybox?)"
                    ),
                )
            })?,
    };
    let kind = match (version, v.get("kind")) {
        (1, _) => TableKind::Uniform,
        (_, Some(k)) => {
            let name = k.as_str().unwrap_or("?");
            TableKind::parse_choice(name).map_err(|_| {
                Error::input(
                    pos().field("kind"),
                    format!("unknown table kind '{name}' (expected uniform, exact or adaptive)"),
                )
            })?
        }
        (_, None) => {
            return Err(Error::input(
                pos().field("kind"),
                "missing (uniform, exact or adaptive)",
            ))
        }
    };
    let field_error = |e: Error| match e {
        Error::Invalid { what, message } => Error::input(pos().field(what), message),
        other => Error::input(pos(), other.to_string()),
    };
    Ok(match kind {
        TableKind::Uniform => {
            let t: TabulatedLaw = parse(text, path)?;
            t.validate().map_err(field_error)?;
            AnyTable::Uniform(t.prepare())
        }
        TableKind::Exact => AnyTable::Exact(
            parse::<ExactTable>(text, path)?
                .prepare()
                .map_err(field_error)?,
        ),
        TableKind::Adaptive => AnyTable::Adaptive(
            parse::<AdaptiveTable>(text, path)?
                .prepare()
                .map_err(field_error)?,
        ),
    })
}

fn parse<T: DeserializeOwned>(text: &str, path: &Path) -> Result<T> {
    serde_json::from_str(text).map_err(|e| {
        Error::input(
            SourcePos::path(path).line(e.line() as u64),
            format!("not a greybox table: {e}"),
        )
    })
}
