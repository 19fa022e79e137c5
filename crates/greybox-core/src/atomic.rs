//! Atomic output: write to a temporary file in the target directory, then rename.
//! A reader never sees a half-written file, and a failed write leaves no file.

use crate::{Error, Result};
use std::io::{BufWriter, Write};
use std::path::Path;

/// Write `path` atomically. `fill` writes the content into a buffered writer.
/// Parent directories are created.
pub fn write_atomic<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let tmp = tempfile::Builder::new()
        .prefix(".greybox-")
        .suffix(".tmp")
        .tempfile_in(&dir)
        .map_err(|e| Error::io(&dir, e))?;
    {
        let mut w = BufWriter::with_capacity(1 << 20, tmp.as_file());
        fill(&mut w).map_err(|e| Error::io(path, e))?;
        w.flush().map_err(|e| Error::io(path, e))?;
    }
    tmp.as_file().sync_all().map_err(|e| Error::io(path, e))?;
    tmp.persist(path).map_err(|e| Error::io(path, e.error))?;
    Ok(())
}

/// Write a string atomically.
pub fn write_string_atomic(path: &Path, content: &str) -> Result<()> {
    write_atomic(path, |w| w.write_all(content.as_bytes()))
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn failed_write_leaves_no_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.csv");
        let r = write_atomic(&p, |w| {
            w.write_all(b"half")?;
            Err(std::io::Error::other("boom"))
        });
        assert!(r.is_err());
        assert!(!p.exists());
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            0,
            "temp file left behind"
        );
        write_string_atomic(&p, "ok\n").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "ok\n");
    }
}
