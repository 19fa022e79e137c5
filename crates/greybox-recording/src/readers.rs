//! The recording readers' registry: which reader a file goes to (by its content, the name
//! being only a hint: [`RecordingFormat::detect`]), and the one
//! call that reads any supported file into a [`Recording`]. It sits beside the readers and
//! the [`Recording`] seam, so neither imports the other back (readers → table → recording).
//!
//! Every reader is registered once, in [`READERS`]: its format, the file name extensions
//! that name it and the function that reads a file into a [`Table`]. Everything else that
//! enumerates formats is derived from that list or checked against it: the extensions
//! ([`RecordingFormat::of_path`], [`RecordingFormat::extension`]), the `--format` / `format`
//! choice (the [`RecordingFormat`] names, one per registered reader: a test checks it), the
//! dispatch of [`read_table`], and the lists of extensions in `README.md` and
//! `docs/recordings.md` (a test checks them).
//!
//! **Adding a reader** touches at most three files:
//! 1. its own module (`src/my_format.rs`): `fn read(path: &Path, opts: &ReaderOptions) ->
//!    Result<Table>` (columns named as in the file, units from the header where it states
//!    them; the channel map does the rest);
//! 2. `src/lib.rs`: `pub mod my_format;`
//! 3. this file: a variant of [`RecordingFormat`] with its name in the `choice!` list, an
//!    entry in [`READERS`], and, for a binary format, its signature in
//!    [`RecordingFormat::of_content`].
//!
//! A test below (`a_reader_added_to_the_registry_reads_through_the_same_path`) walks through
//! a toy reader built the same way.

use crate::table::Table;
use crate::{recording_from_table, ChannelMap, ReaderOptions, Recording};
use greybox_core::{Error, Result, SourcePos};
use serde::{Deserialize, Serialize};
use std::path::Path;

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

/// One registered reader: the format it reads, the file name extensions that name it, and
/// the function that reads a file into a [`Table`].
#[derive(Debug, Clone, Copy)]
pub struct Reader {
    pub format: RecordingFormat,
    /// Extensions naming the format (lower case, no dot); the first is the one written.
    pub extensions: &'static [&'static str],
    /// Read the file at the path with the reader options (delimiter, sheet, TDMS group, …).
    pub read: fn(&Path, &ReaderOptions) -> Result<Table>,
}

/// Every reader, once: the one place a reader is registered (see the module doc).
pub const READERS: &[Reader] = &[
    Reader {
        format: RecordingFormat::Csv,
        extensions: &["csv", "txt", "tsv", "dat", "asc", "prn", "dwf"],
        read: read_text,
    },
    Reader {
        format: RecordingFormat::Tdms,
        extensions: &["tdms"],
        read: read_tdms,
    },
    Reader {
        format: RecordingFormat::Spreadsheet,
        extensions: &["xlsx", "xlsm", "xls", "xlsb", "ods"],
        read: read_sheet,
    },
];

/// Delimited text, dialect sniffed unless the options name it.
fn read_text(path: &Path, opts: &ReaderOptions) -> Result<Table> {
    crate::text_table::read_text_table(path, &opts.text_options())
}

/// TDMS: the options' group, or the default / only group.
fn read_tdms(path: &Path, opts: &ReaderOptions) -> Result<Table> {
    let file = crate::tdms::TdmsFile::read(path)?;
    crate::tdms::table_from_tdms(file, opts.tdms_group.as_deref())
}

/// A spreadsheet: the options' sheet, or the first one holding a table.
fn read_sheet(path: &Path, opts: &ReaderOptions) -> Result<Table> {
    crate::xlsx_table::read_spreadsheet(path, opts.sheet.as_deref())
}

impl RecordingFormat {
    /// The format's registered reader ([`READERS`]).
    pub fn reader(self) -> &'static Reader {
        READERS
            .iter()
            .find(|r| r.format == self)
            .expect("every format has a reader in READERS (checked by a test)")
    }

    /// The extension a file of this format is written with (the first registered one).
    pub fn extension(self) -> &'static str {
        self.reader().extensions[0]
    }
    /// The format a file's first bytes say (its name plays no part): TDMS by its `TDSm`
    /// lead-in, a spreadsheet by the zip (`PK\x03\x04`: xlsx, xlsm, ods) or OLE (`D0 CF 11
    /// E0`: xls) signature, else delimited text when the head is text (no NUL byte, UTF-8 or a
    /// single-byte code page; a UTF-16 byte-order mark too, which the text reader refuses by
    /// name) and not JSON or XML ([`markup`]). A file without extension or with an unknown
    /// one (`.log`, `.out`) is read by its content like any other; a `.xls` that is really
    /// tab-separated text is text. `None`: content of no known format.
    pub fn of_content(head: &[u8]) -> Option<Self> {
        if head.starts_with(b"TDSm") {
            return Some(RecordingFormat::Tdms);
        }
        if head.starts_with(b"PK\x03\x04") || head.starts_with(&[0xD0, 0xCF, 0x11, 0xE0]) {
            return Some(RecordingFormat::Spreadsheet);
        }
        let utf16 = head.starts_with(&[0xFF, 0xFE]) || head.starts_with(&[0xFE, 0xFF]);
        let text = head
            .iter()
            .all(|&b| b != 0 && (b >= 0x20 || b"\t\n\r\x0c".contains(&b)));
        (utf16 || (text && markup(head).is_none())).then_some(RecordingFormat::Csv)
    }
    /// The format of the file at `path`, from its first KiB ([`Self::of_content`]). The name
    /// is a hint only where the content says nothing: an empty file, or one that is neither
    /// of a known signature nor plain text (nor markup), goes to the reader its extension
    /// names (which then refuses it by line and reason, e.g. gigabytes without a line end); a
    /// FIFO, device or directory is never opened here. An error names the file when it
    /// cannot be read or nothing tells its format.
    pub fn detect(path: &std::path::Path) -> Result<Self> {
        use std::io::Read;
        let by_name = Self::of_path(path);
        // a FIFO, a device or a directory is never opened here: its reader refuses it by name
        let regular = std::fs::metadata(path)
            .map_err(|e| Error::io(path, e))?
            .is_file();
        if !regular {
            return Ok(by_name.unwrap_or(RecordingFormat::Csv));
        }
        let mut head = Vec::with_capacity(1024);
        let (file, _) = greybox_core::input::open_recording(path)?;
        file.take(1024)
            .read_to_end(&mut head)
            .map_err(|e| Error::io(path, e))?;
        if head.is_empty() {
            return Ok(by_name.unwrap_or(RecordingFormat::Csv));
        }
        // content of no known format but a known name: that format's reader says what is
        // wrong with it (a file of zeros named .csv has no line end in its first line);
        // markup (HTML, XML) is refused here whatever its name
        let markup = markup(&head);
        Self::of_content(&head)
            .or(by_name.filter(|_| markup.is_none()))
            .ok_or_else(|| {
                let what = markup.map_or("binary data".to_string(), |m| format!("{m} text"));
                Error::input(
                    SourcePos::path(path),
                    format!(
                        "unknown recording format: the content is {what}, neither a delimited text table nor a spreadsheet (xlsx, xls, ods) nor TDMS{}",
                        by_name.map_or(String::new(), |f| format!(
                            " (the name says {f}, the first bytes do not)"
                        ))
                    ),
            )
        })
    }
    /// The format a file name's extension says (used to pick files from a directory; reading
    /// goes by the content, [`Self::detect`]).
    pub fn of_path(path: &std::path::Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        READERS
            .iter()
            .find(|r| r.extensions.contains(&ext.as_str()))
            .map(|r| r.format)
    }
}

/// Text that is JSON or XML/HTML (its first character after any BOM and blanks is `{` or
/// `<`): a side file such as a provenance record, never a recording's table.
fn markup(head: &[u8]) -> Option<&'static str> {
    let body = head.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(head);
    match body.iter().find(|b| !b.is_ascii_whitespace()) {
        Some(b'{') => Some("JSON"),
        Some(b'<') => Some("XML or HTML"),
        _ => None,
    }
}

/// Read a file's table, choosing the reader from the content ([`RecordingFormat::detect`]).
pub fn read_table(path: &std::path::Path, map: &ChannelMap) -> Result<Table> {
    (RecordingFormat::detect(path)?.reader().read)(path, &map.reader)
}

/// Read a recording (any supported format) through a channel map.
///
/// The seam for your own rig: a file greybox reads is mapped onto roles by column name and
/// unit (here found without help: forces in kgf are converted to N); a format it cannot read
/// becomes a [`Table`] from your own parser and goes through [`recording_with_profile`].
///
/// ```
/// use greybox_recording::readers::read_recording;
/// use greybox_recording::ChannelMap;
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
///
/// `map.columns` (`--columns`) names the table's columns first, so that the profile and the
/// role search see the given names.
pub fn recording_with_profile(mut table: Table, map: &ChannelMap) -> Result<Recording> {
    if !map.reader.columns.is_empty() {
        table.name_columns(&map.reader.columns)?;
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use greybox_core::choice::Choice;

    /// One reader per format, each registered once, and no extension claimed twice.
    #[test]
    fn every_format_is_registered_once() {
        for f in RecordingFormat::ALL {
            let n = READERS.iter().filter(|r| r.format == *f).count();
            assert_eq!(n, 1, "{f} has {n} readers in READERS");
        }
        assert_eq!(READERS.len(), RecordingFormat::ALL.len());
        let mut exts: Vec<&str> = READERS
            .iter()
            .flat_map(|r| r.extensions.iter().copied())
            .collect();
        let n = exts.len();
        exts.sort_unstable();
        exts.dedup();
        assert_eq!(exts.len(), n, "an extension is claimed by two readers");
        for r in READERS {
            let p = Path::new("x").with_extension(r.extensions[0].to_uppercase());
            assert_eq!(RecordingFormat::of_path(&p), Some(r.format));
        }
    }

    /// The user documentation (README, docs/recordings.md) lists every registered extension.
    #[test]
    fn the_documented_extensions_are_the_registered_ones() {
        let docs = [
            ("README.md", include_str!("../../../README.md")),
            (
                "docs/recordings.md",
                include_str!("../../../docs/recordings.md"),
            ),
        ];
        for (name, doc) in docs {
            for r in READERS {
                for e in r.extensions {
                    let dotted = format!(".{e}");
                    let listed = doc.match_indices(&dotted).any(|(i, _)| {
                        !doc[i + dotted.len()..].starts_with(|c: char| c.is_ascii_alphanumeric())
                    });
                    assert!(listed, "{name} does not list .{e} ({})", r.format);
                }
            }
        }
    }

    /// A toy reader (one `t=…;F=…;f=…` line per sample) built as the module doc says: its
    /// read function gives a [`Table`] that the same channel map and profile path turn into
    /// a recording. Registering it would be a `READERS` entry with this function.
    #[test]
    fn a_reader_added_to_the_registry_reads_through_the_same_path() {
        fn read_pairs(path: &Path, _opts: &ReaderOptions) -> Result<Table> {
            let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
            let mut cols: Vec<(String, Vec<f64>)> = Vec::new();
            for line in text.lines().filter(|l| !l.trim().is_empty()) {
                for (k, field) in line.split(';').enumerate() {
                    let (name, value) = field.split_once('=').expect("name=value");
                    if cols.len() <= k {
                        cols.push((name.to_string(), Vec::new()));
                    }
                    cols[k].1.push(value.parse().expect("a number"));
                }
            }
            Ok(Table {
                source: path.display().to_string(),
                rows: cols.first().map_or(0, |c| c.1.len()),
                layout: "name=value pairs".into(),
                columns: cols
                    .into_iter()
                    .map(|(h, v)| crate::table::Column::numbers(&h, v))
                    .collect(),
                ..Default::default()
            })
        }
        let toy = Reader {
            format: RecordingFormat::Csv,
            extensions: &["pairs"],
            read: read_pairs,
        };
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("run.pairs");
        std::fs::write(&p, "t_s=0;Fn_N=10;Ft_N=2\nt_s=0.1;Fn_N=10;Ft_N=3\n").unwrap();
        let map = ChannelMap::default();
        let table = (toy.read)(&p, &map.reader).unwrap();
        let rec = recording_with_profile(table, &map).unwrap();
        assert_eq!(rec.time_s, [0.0, 0.1]);
        assert_eq!(rec.tangential_n, [2.0, 3.0]);
    }
}
