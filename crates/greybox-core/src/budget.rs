//! Budgets: every reader of untrusted input has a named cap, checked *before* the work or
//! the allocation it bounds, and an error that says what was found, which cap it exceeds and
//! how to raise it.
//!
//! The caps of the readers ([`Cap`]) are process-wide: their defaults are in [`DEFAULT`],
//! the `greybox` command line raises them with global options (`--max-input-mib`, …, see
//! [`Cap::option`]), a library user with [`set`]. Caps that belong to one configuration live
//! in it: a sweep's `[sweep] max_cases`, a set-up's `numerics.max_particles`.

use std::sync::RwLock;

/// The process-wide caps of the readers. As JSON (Python's `greybox.set_budget`), every
/// field by its name; a key that is no field is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Budget {
    /// Largest configuration file read whole (cutting / pin set-up TOML, sweep file, a sweep's
    /// base configuration), bytes. Default 16 MiB (the bundled set-ups are 3 kB).
    pub max_input_bytes: u64,
    /// Most elements of a UBJSON typed container whose elements take no bytes in the file
    /// (`null`, `true`, `false`), elements. Other containers are bounded by the bytes left in
    /// the file. Default 1 048 576.
    pub max_array_len: u64,
    /// Most cells of one spreadsheet sheet: its declared `<dimension>`, the bounding box of
    /// its cells (what is held in memory) and its shared-strings count, cells.
    /// Default 20 000 000 (Excel's 1 048 576 rows × 19 columns).
    pub max_sheet_cells: u64,
    /// Most bytes the entries of a spreadsheet archive (xlsx, xlsm, xlsb, ods) expand to,
    /// together, bytes. Default 512 MiB.
    pub max_uncompressed_bytes: u64,
    /// Longest line in the head of a text recording (the lines its layout is sniffed from),
    /// bytes. Default 1 MiB.
    pub max_line_bytes: u64,
    /// Largest recording file read (delimited text, spreadsheet, TDMS), bytes. Default 2 GiB:
    /// a recording above it is refused with the cap named before any of it is read, never
    /// read until memory runs out.
    pub max_recording_bytes: u64,
    /// Largest data, model or state file read (training and calibration data, track widths,
    /// prediction points, wear tests, material curves, validation data, model, law and table
    /// files, FE decks, sweep plans, checkpoints), bytes. Default 2 GiB.
    pub max_data_bytes: u64,
}

/// The default caps.
pub const DEFAULT: Budget = Budget {
    max_input_bytes: 16 << 20,
    max_array_len: 1 << 20,
    max_sheet_cells: 20_000_000,
    max_uncompressed_bytes: 512 << 20,
    max_line_bytes: 1 << 20,
    max_recording_bytes: 2 << 30,
    max_data_bytes: 2 << 30,
};

impl Default for Budget {
    fn default() -> Self {
        DEFAULT
    }
}

static CURRENT: RwLock<Budget> = RwLock::new(DEFAULT);

/// The caps in force.
pub fn current() -> Budget {
    *CURRENT.read().unwrap_or_else(|e| e.into_inner())
}

/// Sets the caps for the rest of the process.
pub fn set(b: Budget) {
    *CURRENT.write().unwrap_or_else(|e| e.into_inner()) = b;
}

/// One cap of [`Budget`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cap {
    InputBytes,
    ArrayLen,
    SheetCells,
    UncompressedBytes,
    LineBytes,
    RecordingBytes,
    DataBytes,
}

impl Cap {
    /// Every cap.
    pub const ALL: [Cap; 7] = [
        Cap::InputBytes,
        Cap::ArrayLen,
        Cap::SheetCells,
        Cap::UncompressedBytes,
        Cap::LineBytes,
        Cap::RecordingBytes,
        Cap::DataBytes,
    ];

    /// The cap's name (the field of [`Budget`]).
    pub fn name(self) -> &'static str {
        match self {
            Cap::InputBytes => "max_input_bytes",
            Cap::ArrayLen => "max_array_len",
            Cap::SheetCells => "max_sheet_cells",
            Cap::UncompressedBytes => "max_uncompressed_bytes",
            Cap::LineBytes => "max_line_bytes",
            Cap::RecordingBytes => "max_recording_bytes",
            Cap::DataBytes => "max_data_bytes",
        }
    }
    /// The setting that raises it, named as a field (`` `max_input_mib` ``): the command line
    /// shows it as its flag.
    pub fn option(self) -> &'static str {
        match self {
            Cap::InputBytes => "`max_input_mib`",
            Cap::ArrayLen => "`max_array_len`",
            Cap::SheetCells => "`max_sheet_cells`",
            Cap::UncompressedBytes => "`max_uncompressed_mib`",
            Cap::LineBytes => "`max_line_kib`",
            Cap::RecordingBytes => "`max_recording_mib`",
            Cap::DataBytes => "`max_data_mib`",
        }
    }
    /// The cap's value now.
    pub fn limit(self) -> u64 {
        let b = current();
        match self {
            Cap::InputBytes => b.max_input_bytes,
            Cap::ArrayLen => b.max_array_len,
            Cap::SheetCells => b.max_sheet_cells,
            Cap::UncompressedBytes => b.max_uncompressed_bytes,
            Cap::LineBytes => b.max_line_bytes,
            Cap::RecordingBytes => b.max_recording_bytes,
            Cap::DataBytes => b.max_data_bytes,
        }
    }
    /// `Ok` when `value` is within the cap, else the message: `found` (what was found, e.g.
    /// "the sheet declares 3e9 cells"), the cap and the option that raises it.
    pub fn check(self, value: u64, found: impl FnOnce() -> String) -> Result<(), String> {
        let limit = self.limit();
        if value <= limit {
            return Ok(());
        }
        Err(over_cap(
            &found(),
            self.name(),
            &limit.to_string(),
            self.option(),
        ))
    }
}

/// The one wording of a refusal by a cap: what was found, the cap's name and value, and what
/// raises it.
pub fn over_cap(found: &str, cap: &str, limit: &str, raise: &str) -> String {
    format!("{found}: above the cap {cap} = {limit} (raise it with {raise} if this is intended)")
}

/// A byte count for messages: `3.00 GB`.
pub fn bytes_text(b: f64) -> String {
    const UNITS: [&str; 6] = ["B", "kB", "MB", "GB", "TB", "PB"];
    let mut v = b;
    let mut u = 0;
    while v >= 1000.0 && u + 1 < UNITS.len() {
        v /= 1000.0;
        u += 1;
    }
    if u == 0 {
        format!("{v:.0} B")
    } else {
        format!("{v:.2} {}", UNITS[u])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caps_name_themselves_and_their_option() {
        assert!(Cap::ArrayLen
            .check(DEFAULT.max_array_len, String::new)
            .is_ok());
        let e = Cap::SheetCells
            .check(DEFAULT.max_sheet_cells + 1, || {
                "the sheet has many cells".into()
            })
            .unwrap_err();
        assert!(
            e.contains("max_sheet_cells = 20000000") && e.contains("`max_sheet_cells`"),
            "{e}"
        );
        assert_eq!(bytes_text(2.9e12), "2.90 TB");
        assert_eq!(bytes_text(12.0), "12 B");
    }
}
