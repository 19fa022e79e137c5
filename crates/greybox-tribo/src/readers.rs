//! The recording readers' registry: which reader a file goes to (by extension), and the one
//! call that reads any supported file into a [`Recording`]. It sits beside the readers and
//! the [`Recording`] seam, so neither imports the other back (readers → table → recording).

use crate::recording::{recording_from_table, ChannelMap, Recording};
use crate::table::Table;
use greybox_core::{Error, Result, SourcePos};
use serde::{Deserialize, Serialize};

/// File formats of raw recordings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RecordingFormat {
    /// Delimited text: `.csv`, `.txt`, `.tsv`, `.dat`, `.asc`, `.prn`, `.dwf` (a pin-on-disc
    /// program's `;`-separated time/friction-force export).
    Csv,
    Tdms,
    /// Spreadsheets: `.xlsx`, `.xlsm`, `.xls`, `.xlsb`, `.ods`.
    Spreadsheet,
}

greybox_core::choice!(RecordingFormat, "format", [Csv => "csv", Tdms => "tdms", Spreadsheet => "spreadsheet"], text);

impl RecordingFormat {
    pub fn extension(self) -> &'static str {
        match self {
            RecordingFormat::Csv => "csv",
            RecordingFormat::Tdms => "tdms",
            RecordingFormat::Spreadsheet => "xlsx",
        }
    }
    /// The format a file name's extension says.
    pub fn of_path(path: &std::path::Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "csv" | "txt" | "tsv" | "dat" | "asc" | "prn" | "dwf" => Some(RecordingFormat::Csv),
            "tdms" => Some(RecordingFormat::Tdms),
            "xlsx" | "xlsm" | "xls" | "xlsb" | "ods" => Some(RecordingFormat::Spreadsheet),
            _ => None,
        }
    }
}

/// Read a file's table, choosing the reader from the extension.
pub fn read_table(path: &std::path::Path, map: &ChannelMap) -> Result<Table> {
    match RecordingFormat::of_path(path) {
        Some(RecordingFormat::Csv) => crate::text_table::read_text_table(path, &map.text_options()),
        Some(RecordingFormat::Tdms) => {
            let file = crate::tdms::TdmsFile::read(path)?;
            crate::tdms::table_from_tdms(file, map.tdms_group.as_deref())
        }
        Some(RecordingFormat::Spreadsheet) => {
            crate::xlsx_table::read_spreadsheet(path, map.sheet.as_deref())
        }
        None => Err(Error::input(
            SourcePos::path(path),
            "unknown recording format: expected delimited text (.csv, .txt, .tsv, .dat, .dwf), a spreadsheet (.xlsx, .xls, .ods) or .tdms",
        )),
    }
}

/// Read a recording (any supported format) through a channel map.
///
/// The seam for your own rig: a file greybox reads is mapped onto roles by column name and
/// unit (here found without help: forces in kgf are converted to N); a format it cannot read
/// becomes a [`Table`] from your own parser and goes through [`recording_with_profile`].
///
/// ```
/// use greybox_tribo::readers::read_recording;
/// use greybox_tribo::recording::ChannelMap;
/// let dir = tempfile::tempdir()?;
/// let file = dir.path().join("run.csv");
/// std::fs::write(&file, "Time [s],Fn [kgf],Ff [kgf]\n0.0,10,2\n0.1,10,2.5\n0.2,10,3\n")?;
/// let rec = read_recording(&file, &ChannelMap::default())?;
/// assert_eq!(rec.time_s, [0.0, 0.1, 0.2]);
/// assert!((rec.normal_n[0] - 98.0665).abs() < 1e-9); // 10 kgf
/// assert!((rec.tangential_n[2] / rec.normal_n[2] - 0.3).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_recording(path: &std::path::Path, map: &ChannelMap) -> Result<Recording> {
    recording_with_profile(read_table(path, map)?, map)
}

/// A table's recording through `map` completed by the rig profile named in it or detected
/// from the table ([`crate::profiles`]); the profile used is noted in the read report.
pub fn recording_with_profile(mut table: Table, map: &ChannelMap) -> Result<Recording> {
    let mut notes = std::mem::take(&mut table.notes);
    let mode = crate::profiles::detect(&table, map.rig.as_deref())
        .ok()
        .flatten()
        .map(|p| p.mode);
    let map = crate::profiles::apply(&table, map, &mut notes)?;
    table.notes = notes;
    let mut rec = recording_from_table(table, &map)?;
    if let Some(r) = rec.provenance.as_mut() {
        r.test_mode = mode;
    }
    Ok(rec)
}
