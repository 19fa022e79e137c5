//! One safe way to open every input: the only place a greybox library crate opens a file it
//! reads (recordings, datasets, training and calibration data, track widths, prediction
//! points, wear tests and height maps, material curves, validation data, hammer recordings,
//! model, law and table files, FE decks and meshes, configurations, sweep plans and case
//! markers, checkpoints, and what Python's `load_law` / `read_csv` read).
//!
//! The rules, each checked before any byte is read:
//!
//! * only a **regular file** after links are followed: a FIFO is never opened for reading
//!   (that would wait for a writer for ever), a link to `/dev/zero` or any other device, a
//!   socket or a directory is refused with the path and its kind named; the file is opened
//!   with `O_NONBLOCK` and its kind checked again, should the path change between the two;
//! * at most the **size cap** of its kind ([`Cap`]: configurations `max_input_bytes`,
//!   recordings `max_recording_bytes`, every other data, model or state file
//!   `max_data_bytes`), refused with the cap and the setting that raises it named;
//! * read no further than the **length found** when it was opened (a file that grows while
//!   it is read cannot take more), into a buffer asked for without aborting (memory that
//!   cannot be had is an error naming the file and the size);
//! * a **missing file** is an [`Error::Io`] of kind `NotFound` ("…: not found"), never a
//!   "malformed" file: Python raises `FileNotFoundError` for it.
//!
//! `cli/tests/cli_source_rules.rs::every_input_is_opened_through_the_one_safe_open` finds a
//! library source that opens a file any other way.

use crate::budget::{bytes_text, Cap};
use crate::{Error, Result, SourcePos};
use std::fs::File;
use std::io::Read;
use std::path::Path;

/// An input file opened by [`open`]: reads at most the length it had when it was opened.
#[derive(Debug)]
pub struct Input {
    reader: std::io::Take<File>,
    len: u64,
}

impl Input {
    /// The file's length when it was opened, bytes.
    pub fn len(&self) -> u64 {
        self.len
    }
    /// Whether the file was empty when it was opened.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
    /// The open file and its length (for readers that seek, such as TDMS and spreadsheets:
    /// they must not read past the length).
    pub fn into_parts(self) -> (File, u64) {
        (self.reader.into_inner(), self.len)
    }
}

impl Read for Input {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.reader.read(buf)
    }
}

/// The refusal of a path that is not a regular file: `what` names its role ("recording",
/// "training data"), the message says what it is and what to give instead.
fn not_regular(path: &Path, what: &str, meta: &std::fs::Metadata) -> Error {
    Error::input(
        SourcePos::path(path),
        format!(
            "the {what} is {}, not a regular file: greybox reads inputs only from regular files (give the file itself, not a pipe, device or directory)",
            crate::atomic::describe_kind(meta)
        ),
    )
}

/// Opens `path` for reading as the input `what` without a size cap: the regular-file rules
/// of the module. For reading again a file already read under its cap (the SHA-256 of a
/// provenance record); readers use [`open`].
pub fn open_regular(path: &Path, what: &str) -> Result<Input> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(not_regular(path, what, &meta));
    }
    let mut opts = std::fs::OpenOptions::new();
    opts.read(true);
    // the path may have been replaced by a FIFO since the check: never wait for a writer
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::OpenOptionsExt;
        opts.custom_flags(libc::O_NONBLOCK);
    }
    let file = opts.open(path).map_err(|e| Error::io(path, e))?;
    let meta = file.metadata().map_err(|e| Error::io(path, e))?;
    if !meta.is_file() {
        return Err(not_regular(path, what, &meta));
    }
    let len = meta.len();
    Ok(Input {
        reader: file.take(len),
        len,
    })
}

/// Opens `path` for reading as the input `what` ("training data", "sweep plan"): a regular
/// file of at most `cap` bytes (see the module). The one open of every reader.
pub fn open(path: &Path, what: &str, cap: Cap) -> Result<Input> {
    let input = open_regular(path, what)?;
    let len = input.len;
    cap.check(len, || {
        format!("the {what} is {} ({len} bytes)", bytes_text(len as f64))
    })
    .map_err(|m| Error::input(SourcePos::path(path), m))?;
    Ok(input)
}

/// The bytes of the input `what` at `path`, whole: [`open`]'s checks, then at most the length
/// it found, in a buffer asked for without aborting.
pub fn read_bytes(path: &Path, what: &str, cap: Cap) -> Result<Vec<u8>> {
    let mut input = open(path, what, cap)?;
    let size = usize::try_from(input.len).unwrap_or(usize::MAX);
    let mut bytes = Vec::new();
    bytes.try_reserve_exact(size).map_err(|_| {
        Error::input(
            SourcePos::path(path),
            format!(
                "the {what} is {} and that much memory is not available to read it",
                bytes_text(input.len as f64)
            ),
        )
    })?;
    input
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    Ok(bytes)
}

/// [`read_bytes`] as UTF-8 text; text that is not UTF-8 is an error naming the byte.
pub fn read_text(path: &Path, what: &str, cap: Cap) -> Result<String> {
    String::from_utf8(read_bytes(path, what, cap)?).map_err(|e| {
        Error::input(
            SourcePos::path(path).byte(e.utf8_error().valid_up_to() as u64),
            format!("the {what} is not UTF-8 text"),
        )
    })
}

/// A CSV reader over the input `what` at `path` opened by [`open`] with `builder`'s settings
/// (in place of `csv::Reader::from_path`, which opens anything).
pub fn csv_reader(
    path: &Path,
    what: &str,
    cap: Cap,
    builder: &csv::ReaderBuilder,
) -> Result<csv::Reader<Input>> {
    Ok(builder.from_reader(open(path, what, cap)?))
}

/// A data file (a table, a model, a state file) read as text under `max_data_bytes`: the
/// common case of [`read_text`].
pub fn read_data_text(path: &Path, what: &str) -> Result<String> {
    read_text(path, what, Cap::DataBytes)
}

/// A data table's CSV reader under `max_data_bytes` with `builder`'s settings: the common
/// case of [`csv_reader`].
pub fn data_csv(
    path: &Path,
    what: &str,
    builder: &csv::ReaderBuilder,
) -> Result<csv::Reader<Input>> {
    csv_reader(path, what, Cap::DataBytes, builder)
}

/// Reads a configuration file whole through the one safe open : a regular
/// file of at most [`crate::budget::Budget::max_input_bytes`]. `what` names the file's role in messages
/// ("sweep file", "base configuration").
pub fn read_config_bytes(path: &Path, what: &str) -> Result<Vec<u8>> {
    read_bytes(path, what, Cap::InputBytes)
}

/// Opens a recording for reading (text, spreadsheet, TDMS) through the one safe open
/// : a regular file of at most [`crate::budget::Budget::max_recording_bytes`]. Returns the
/// open file and its length; a reader reads at most that length.
pub fn open_recording(path: &Path) -> Result<(std::fs::File, u64)> {
    Ok(open(path, "recording", Cap::RecordingBytes)?.into_parts())
}

/// A recording's bytes, whole: [`open_recording`]'s checks, then at most the length it found.
pub fn read_recording_bytes(path: &Path) -> Result<Vec<u8>> {
    read_bytes(path, "recording", Cap::RecordingBytes)
}

/// Reads a model, law or table file whole through the one safe open: a regular file (`/dev/zero`
/// or a FIFO named as a model would never end or never start) of at most
/// [`crate::budget::Budget::max_data_bytes`].
pub fn read_regular_text(path: &Path, what: &str) -> Result<String> {
    read_data_text(path, what)
}

/// [`read_config_bytes`] as UTF-8 text.
pub fn read_config(path: &Path, what: &str) -> Result<String> {
    read_text(path, what, Cap::InputBytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hostile kinds every reader must refuse, made in `dir`: a FIFO, a link to
    /// `/dev/zero`, a directory, and (for `cap`) a sparse file one byte over it.
    fn hostile(dir: &Path) -> Vec<(std::path::PathBuf, &'static str)> {
        let mut out = Vec::new();
        let link = dir.join("zero.csv");
        std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
        out.push((link, "character device"));
        let fifo = dir.join("fifo.csv");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: a valid NUL-terminated path
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
        out.push((fifo, "FIFO"));
        let sub = dir.join("dir.csv");
        std::fs::create_dir(&sub).unwrap();
        out.push((sub, "directory"));
        out
    }

    #[test]
    fn only_regular_files_within_their_cap_are_read() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("a.csv");
        std::fs::write(&p, "x\n1\n").unwrap();
        assert_eq!(read_data_text(&p, "training data").unwrap(), "x\n1\n");
        let mut r = data_csv(&p, "training data", &csv::ReaderBuilder::new()).unwrap();
        assert_eq!(r.records().count(), 1);
        for (path, kind) in hostile(d.path()) {
            let e = read_data_text(&path, "training data")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(kind)
                    && e.contains("the training data is")
                    && e.contains("not a regular file")
                    && e.contains(path.file_name().unwrap().to_str().unwrap()),
                "{e}"
            );
        }
        let big = d.path().join("big.json");
        std::fs::File::create(&big)
            .unwrap()
            .set_len(crate::budget::DEFAULT.max_input_bytes + 1)
            .unwrap();
        let e = read_text(&big, "sweep plan", Cap::InputBytes)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("big.json")
                && e.contains("the sweep plan is")
                && e.contains("max_input_bytes"),
            "{e}"
        );
    }

    #[test]
    fn a_missing_file_is_not_found_not_malformed() {
        let e = read_data_text(Path::new("/nonexistent/fit.csv"), "training data").unwrap_err();
        assert!(
            matches!(&e, Error::Io { error, .. } if error.kind() == std::io::ErrorKind::NotFound)
        );
        let m = e.to_string();
        assert!(m.contains("fit.csv") && m.contains("not found"), "{m}");
    }

    #[test]
    fn a_file_that_grows_is_read_to_its_length_at_open() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("g.csv");
        std::fs::write(&p, "abc").unwrap();
        let mut input = open(&p, "recording", Cap::RecordingBytes).unwrap();
        std::fs::OpenOptions::new()
            .append(true)
            .open(&p)
            .and_then(|mut f| std::io::Write::write_all(&mut f, b"def"))
            .unwrap();
        let mut s = String::new();
        input.read_to_string(&mut s).unwrap();
        assert_eq!(s, "abc");
    }

    #[test]
    fn configurations_are_regular_files_within_their_cap() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("c.toml");
        std::fs::write(&p, "a = 1\n").unwrap();
        assert_eq!(read_config(&p, "set-up").unwrap(), "a = 1\n");
        let e = read_config(Path::new("/dev/zero"), "base configuration")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("/dev/zero") && e.contains("character device") && e.contains("regular"),
            "{e}"
        );
        let e = read_config(d.path(), "set-up").unwrap_err().to_string();
        assert!(e.contains("directory"), "{e}");
        let big = d.path().join("big.toml");
        let f = std::fs::File::create(&big).unwrap();
        f.set_len(crate::budget::DEFAULT.max_input_bytes + 1)
            .unwrap();
        let e = read_config(&big, "sweep file").unwrap_err().to_string();
        assert!(
            e.contains("big.toml")
                && e.contains("max_input_bytes")
                && e.contains("`max_input_mib`"),
            "{e}"
        );
    }

    #[test]
    fn recordings_are_regular_files_under_the_cap() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("r.csv");
        std::fs::write(&p, "t,Fn\n0,1\n").unwrap();
        assert_eq!(read_recording_bytes(&p).unwrap(), b"t,Fn\n0,1\n");
        #[cfg(unix)]
        {
            let link = d.path().join("zero.csv");
            std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
            let e = open_recording(&link).unwrap_err().to_string();
            assert!(
                e.contains("zero.csv") && e.contains("character device") && e.contains("regular"),
                "{e}"
            );
        }
        #[cfg(target_os = "linux")]
        {
            let fifo = d.path().join("fifo.csv");
            let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
            // SAFETY: a valid NUL-terminated path
            assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
            let e = open_recording(&fifo).unwrap_err().to_string();
            assert!(e.contains("FIFO") && e.contains("fifo.csv"), "{e}");
        }
        let big = d.path().join("big.csv");
        let f = std::fs::File::create(&big).unwrap();
        f.set_len(crate::budget::DEFAULT.max_recording_bytes + 1)
            .unwrap();
        let e = open_recording(&big).unwrap_err().to_string();
        assert!(
            e.contains("big.csv")
                && e.contains("max_recording_bytes")
                && e.contains("`max_recording_mib`"),
            "{e}"
        );
    }
}
