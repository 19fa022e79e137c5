//! Reading a study directory's files within budgets: only regular files are opened (a FIFO,
//! a device or a socket is described and never opened, so it can neither block nor stream
//! forever), every read stops at a cap, and a header is read as at most one bounded line.

use anyhow::{bail, Context, Result};
use std::fs::Metadata;
use std::io::Read;
use std::os::unix::fs::FileTypeExt;
use std::path::Path;

/// A cap, with the option field that holds (and raises) it.
#[derive(Debug, Clone, Copy)]
pub struct Cap {
    pub bytes: u64,
    /// The `ReportOptions` field, e.g. `max_file_bytes`.
    pub field: &'static str,
}

impl Cap {
    /// The setting that raises it, as a field in backticks (`` `max_file_bytes` ``): the
    /// command line shows it as its flag.
    pub fn flag(&self) -> String {
        format!("`{}`", self.field)
    }
    /// "over max_svg_bytes (8388608 bytes; raise it with `max_svg_bytes`)".
    pub fn exceeded(&self) -> String {
        format!(
            "over {} ({} bytes; raise it with {})",
            self.field,
            self.bytes,
            self.flag()
        )
    }
}

/// What a non-regular file is, in words.
pub fn kind(m: &Metadata) -> &'static str {
    let t = m.file_type();
    if t.is_dir() {
        "a directory"
    } else if t.is_fifo() {
        "a FIFO"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "not a regular file"
    }
}

/// The size of `p` (links followed) if it is a regular file of at most `cap` bytes; never
/// opens it.
pub fn regular_within(p: &Path, cap: Cap) -> Result<u64> {
    let m = std::fs::metadata(p).context("cannot read the file")?;
    if !m.is_file() {
        bail!("{}, not a regular file: not opened", kind(&m));
    }
    if m.len() > cap.bytes {
        bail!("{} bytes, {}", m.len(), cap.exceeded());
    }
    Ok(m.len())
}

/// Opens a regular file through greybox's one safe open (without blocking on a FIFO swapped
/// in after the check; what was opened checked again); reads stop at its length then.
fn open_regular(p: &Path) -> Result<greybox_core::input::Input> {
    Ok(greybox_core::input::open_regular(p, "study file")?)
}

/// The whole of `p`, at most `cap` bytes (a file that grows past the cap while read is
/// refused too).
pub fn read_capped(p: &Path, cap: Cap) -> Result<Vec<u8>> {
    let len = regular_within(p, cap)?;
    let f = open_regular(p)?;
    let mut buf = Vec::with_capacity(len as usize);
    f.take(cap.bytes + 1)
        .read_to_end(&mut buf)
        .context("cannot read the file")?;
    if buf.len() as u64 > cap.bytes {
        bail!("grew past {} while read", cap.exceeded());
    }
    Ok(buf)
}

/// The first line of `p` (without its line end), reading at most `cap` bytes; an error if
/// no line ends within them.
pub fn first_line(p: &Path, cap: Cap) -> Result<String> {
    let m = std::fs::metadata(p).context("cannot read the file")?;
    if !m.is_file() {
        bail!("{}, not a regular file: not opened", kind(&m));
    }
    let mut buf = Vec::new();
    open_regular(p)?
        .take(cap.bytes)
        .read_to_end(&mut buf)
        .context("cannot read the file")?;
    let end = match buf.iter().position(|&b| b == b'\n') {
        Some(i) => i,
        None if (buf.len() as u64) < cap.bytes => buf.len(),
        None => bail!(
            "no line end in its first {} bytes: {}",
            cap.bytes,
            cap.exceeded()
        ),
    };
    Ok(String::from_utf8_lossy(&buf[..end])
        .trim_end_matches('\r')
        .to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    const CAP: Cap = Cap {
        bytes: 16,
        field: "max_file_bytes",
    };

    #[test]
    fn caps_name_their_option_and_fifos_are_never_opened() {
        let d = tempfile::tempdir().unwrap();
        let small = d.path().join("a.csv");
        std::fs::write(&small, "x,y\n1,2\n").unwrap();
        assert_eq!(read_capped(&small, CAP).unwrap(), b"x,y\n1,2\n");
        assert_eq!(first_line(&small, CAP).unwrap(), "x,y");
        let big = d.path().join("big.csv");
        std::fs::File::create(&big)
            .unwrap()
            .set_len(1 << 30)
            .unwrap();
        let e = format!("{:#}", read_capped(&big, CAP).unwrap_err());
        assert!(e.contains("max_file_bytes (16 bytes"), "{e}");
        let e = format!("{:#}", first_line(&big, CAP).unwrap_err());
        assert!(e.contains("no line end in its first 16 bytes"), "{e}");
        let fifo = d.path().join("x.csv");
        let st = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(st.success());
        let e = format!("{:#}", read_capped(&fifo, CAP).unwrap_err());
        assert!(e.contains("a FIFO, not a regular file"), "{e}");
        let e = format!("{:#}", first_line(&fifo, CAP).unwrap_err());
        assert!(e.contains("a FIFO"), "{e}");
        let e = format!(
            "{:#}",
            read_capped(Path::new("/dev/zero"), CAP).unwrap_err()
        );
        assert!(e.contains("a character device"), "{e}");
    }
}
