//! Strict CSV helpers shared by every greybox CSV reader: header lookup and finite
//! numeric parsing that report file, line and column.

use crate::{Error, Result, SourcePos};

/// Column indices resolved from a header row.
pub struct Header {
    source: String,
    names: Vec<String>,
}

impl Header {
    pub fn new(source: &str, record: &csv::StringRecord) -> Self {
        Header {
            source: source.to_string(),
            names: record.iter().map(|s| s.trim().to_string()).collect(),
        }
    }
    /// The header row of the CSV file at `path` (only the first record is read).
    pub fn read(path: &std::path::Path) -> Result<Self> {
        let source = path.display().to_string();
        let mut rdr =
            crate::input::data_csv(path, "table", csv::ReaderBuilder::new().has_headers(true))?;
        let record = rdr.headers().map_err(|e| csv_error(&source, e))?;
        Ok(Header::new(&source, record))
    }
    pub fn names(&self) -> &[String] {
        &self.names
    }
    /// Index of a required column.
    pub fn require(&self, name: &str) -> Result<usize> {
        self.find(name).ok_or_else(|| {
            Error::input(
                SourcePos::file(&self.source).line(1).field(name),
                format!(
                    "missing column '{name}'; the header has: {}",
                    self.names.join(", ")
                ),
            )
        })
    }
    /// Index of an optional column.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
    /// Fail on any column not in `known`.
    pub fn reject_unknown(&self, known: &[&str]) -> Result<()> {
        for n in &self.names {
            if !known.contains(&n.as_str()) {
                return Err(Error::input(
                    SourcePos::file(&self.source).line(1).field(n.clone()),
                    format!(
                        "unknown column '{n}'; expected columns: {}",
                        known.join(", ")
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Parse a finite f64 from a field, naming file, line and column on failure.
pub fn parse_f64(text: &str, source: &str, line: u64, column: &str) -> Result<f64> {
    let t = text.trim();
    let v: f64 = t.parse().map_err(|_| {
        Error::input(
            SourcePos::file(source).line(line).field(column),
            format!("expected a number, found '{t}'"),
        )
    })?;
    if !v.is_finite() {
        return Err(Error::input(
            SourcePos::file(source).line(line).field(column),
            format!("expected a finite number, found '{t}'"),
        ));
    }
    Ok(v)
}

/// Parse a finite f64 from raw bytes (fast path for large recordings).
pub fn parse_f64_bytes(bytes: &[u8], source: &str, line: u64, column: &str) -> Result<f64> {
    match std::str::from_utf8(bytes) {
        Ok(s) => parse_f64(s, source, line, column),
        Err(_) => Err(Error::input(
            SourcePos::file(source).line(line).field(column),
            "expected a number, found non-UTF-8 bytes",
        )),
    }
}

/// Parse a non-negative integer field.
pub fn parse_u64(text: &str, source: &str, line: u64, column: &str) -> Result<u64> {
    let t = text.trim();
    t.parse().map_err(|_| {
        Error::input(
            SourcePos::file(source).line(line).field(column),
            format!("expected a non-negative integer, found '{t}'"),
        )
    })
}

/// Parse a non-negative integer that fits a `u32` (a pin or step number), naming file, line and
/// column on failure — never wrapped (pin 4 294 967 297 is not pin 1).
pub fn parse_u32(text: &str, source: &str, line: u64, column: &str) -> Result<u32> {
    let v = parse_u64(text, source, line, column)?;
    u32::try_from(v).map_err(|_| {
        Error::input(
            SourcePos::file(source).line(line).field(column),
            format!(
                "{v} is larger than the largest number a {column} can have ({})",
                u32::MAX
            ),
        )
    })
}

/// Line number (1-based) of a csv record, falling back to a counter.
pub fn record_line(pos: Option<&csv::Position>, fallback: u64) -> u64 {
    pos.map(|p| p.line()).unwrap_or(fallback)
}

/// Turn a csv crate error into a positioned input error.
pub fn csv_error(source: &str, e: csv::Error) -> Error {
    let mut pos = SourcePos::file(source);
    if let Some(p) = e.position() {
        pos = pos.line(p.line()).byte(p.byte());
    }
    let message = match e.kind() {
        csv::ErrorKind::UnequalLengths {
            expected_len, len, ..
        } => {
            format!("malformed CSV: expected {expected_len} fields, found {len}")
        }
        csv::ErrorKind::Utf8 { .. } => "malformed CSV: invalid UTF-8".to_string(),
        _ => format!("malformed CSV: {e}"),
    };
    Error::input(pos, message)
}
