//! Atomic output: write to a temporary file beside the target, then rename.
//!
//! A reader never sees a half-written file, a failed write leaves no file, and an interrupted
//! one leaves none either when the program removes [`crate::cleanup`]'s registered paths on
//! a signal. What is replaced is looked at first: only a regular file is ever replaced; a
//! symbolic link at the output path is refused (a link planted in a directory could point
//! anywhere, and a write through it would change a file outside), and so are a FIFO, a
//! device, a socket or a directory, never turned into a regular file. The temporary file is
//! created new (`O_EXCL`, which never follows a link), and the rename replaces a name, never
//! what a link there points to. A replaced file keeps its permission bits; a new one gets
//! `0666` less the umask (`0644` usually), as any program's `open(2)` would give it.
//!
//! This module is the one way greybox opens an output file: [`write_atomic`] (and
//! [`write_string_atomic`]) for a complete file, [`create_output_file`] for one written as a
//! stream (a child process's log).

use crate::{Error, Result, SourcePos};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// The path a write to `path` replaces: `path` itself, once known to be nothing, or a regular
/// file. An error if a symbolic link (even a dangling one), a directory, a FIFO, a device or
/// a socket is there, or if the path is under `/dev`, `/proc` or `/sys`.
pub fn replaceable_target(path: &Path) -> Result<PathBuf> {
    refuse_system_path(path)?;
    let meta = match std::fs::symlink_metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(path.to_path_buf()),
        Err(e) => return Err(Error::io(path, e)),
    };
    if meta.file_type().is_symlink() {
        let to = std::fs::read_link(path)
            .map(|t| format!(" (to {})", t.display()))
            .unwrap_or_default();
        return Err(Error::input(
            SourcePos::path(path),
            format!(
                "the output path is a symbolic link{to}: greybox never writes through a link, which could change a file outside the output's directory; remove the link or give the path it points to"
            ),
        ));
    }
    if !meta.is_file() {
        return Err(Error::input(
            SourcePos::path(path),
            format!(
                "the output path is {}, not a regular file: greybox only replaces regular files (give a file path)",
                describe_kind(&meta)
            ),
        ));
    }
    Ok(path.to_path_buf())
}

/// Create (or truncate) the output file `path` for writing as a stream, never through a link:
/// [`replaceable_target`]'s checks, then an open that refuses a link planted since
/// (`O_NOFOLLOW` on Linux). Parent directories are created. For a file written while
/// something runs (a log); a complete file is written with [`write_atomic`].
pub fn create_output_file(path: &Path) -> Result<std::fs::File> {
    let target = replaceable_target(path)?;
    if let Some(dir) = target.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let mut o = std::fs::OpenOptions::new();
    o.write(true).create(true).truncate(true);
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::fs::OpenOptionsExt;
        o.custom_flags(libc::O_NOFOLLOW);
    }
    o.open(&target).map_err(|e| Error::io(path, e))
}

/// Directories of the system's pseudo-files: an output there is a stream (`/dev/stdout`, a
/// `/proc/self/fd/N`), never a file greybox may replace and write a provenance record beside.
const SYSTEM_DIRS: [&str; 3] = ["/dev", "/proc", "/sys"];

/// Refuse an output path under `/dev`, `/proc` or `/sys`, as written or once resolved:
/// `/dev/stdout` redirected to a log file resolves to that (regular) file, which a write
/// would replace, and its sidecar would land in `/dev`.
fn refuse_system_path(path: &Path) -> Result<()> {
    let absolute = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir().map_or_else(|_| path.to_path_buf(), |d| d.join(path))
    };
    let resolved = std::fs::canonicalize(&absolute).ok();
    let under = |p: &Path| SYSTEM_DIRS.iter().find(|d| p.starts_with(d)).copied();
    if let Some(dir) = under(&absolute).or_else(|| resolved.as_deref().and_then(under)) {
        let kind = std::fs::metadata(path).map_or("a system path", |m| describe_kind(&m));
        return Err(Error::input(
            SourcePos::path(path),
            format!(
                "the output path is under {dir} ({kind}): greybox writes outputs only as regular files (with a provenance record beside them), never to {dir}; give a file path and read it from there"
            ),
        ));
    }
    Ok(())
}

/// "a directory", "a FIFO", … for messages.
pub fn describe_kind(meta: &std::fs::Metadata) -> &'static str {
    let t = meta.file_type();
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a directory"
    } else if t.is_file() {
        "a regular file"
    } else {
        "not a regular file"
    }
}

/// Write `path` atomically. `fill` writes the content into a buffered writer.
/// Parent directories are created.
pub fn write_atomic<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    stage(path, fill)?.commit()
}

/// A file written in full beside its target (synced), not yet in place: [`Staged::commit`]
/// renames it there; dropped without a commit, it is removed. Outputs that belong together
/// (a dataset and its provenance record) are all staged before any is committed, so that a
/// full disk or a failed write leaves none of them new rather than one without the other
/// ([`commit_together`]).
pub struct Staged {
    tmp: tempfile::NamedTempFile,
    target: PathBuf,
    path: PathBuf,
    guard: crate::cleanup::CleanupGuard,
}

/// Write `path`'s new content beside it (parent directories are created), synced, without
/// putting it in place yet: see [`Staged`].
pub fn stage<F>(path: &Path, fill: F) -> Result<Staged>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    let target = replaceable_target(path)?;
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let existing_mode = std::fs::metadata(&target).ok().map(|m| m.permissions());
    let mut builder = tempfile::Builder::new();
    builder.prefix(".greybox-").suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        // the mode passed to open(2): the umask applies, as for any new file
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let tmp = builder.tempfile_in(&dir).map_err(|e| Error::io(&dir, e))?;
    let guard = crate::cleanup::register(tmp.path(), false);
    {
        let mut w = BufWriter::with_capacity(1 << 20, tmp.as_file());
        fill(&mut w).map_err(|e| Error::io(path, e))?;
        w.flush().map_err(|e| Error::io(path, e))?;
    }
    if let Some(perm) = existing_mode {
        tmp.as_file()
            .set_permissions(perm)
            .map_err(|e| Error::io(path, e))?;
    }
    tmp.as_file().sync_all().map_err(|e| Error::io(path, e))?;
    Ok(Staged {
        tmp,
        target,
        path: path.to_path_buf(),
        guard,
    })
}

impl Staged {
    /// Put the staged file in place (a rename over the target).
    pub fn commit(self) -> Result<()> {
        let Staged {
            tmp,
            target,
            path,
            guard,
        } = self;
        guard.complete(|| {
            tmp.persist(&target)
                .map(|_| ())
                .map_err(|e| Error::io(&path, e.error))
        })
    }
}

/// Commit staged files in order (each was written in full before any is renamed): the record
/// that describes an output first, the output last, so that the output is never in place
/// without its record.
pub fn commit_together(files: Vec<Staged>) -> Result<()> {
    for f in files {
        f.commit()?;
    }
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

    /// A disk-full write of the second of two files that belong together leaves neither new.
    #[test]
    fn files_staged_together_land_together_or_not_at_all() {
        let dir = tempfile::tempdir().unwrap();
        let (rec, data) = (
            dir.path().join("d.provenance.json"),
            dir.path().join("d.csv"),
        );
        let both = |fail: bool| -> Result<()> {
            let first = stage(&rec, |w| w.write_all(b"{}\n"))?;
            let second = stage(&data, |w| {
                w.write_all(b"a,b\n")?;
                if fail {
                    return Err(std::io::Error::from_raw_os_error(28)); // ENOSPC
                }
                Ok(())
            })?;
            commit_together(vec![first, second])
        };
        assert!(both(true).is_err());
        assert!(!rec.exists() && !data.exists(), "one without the other");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        both(false).unwrap();
        assert!(rec.exists() && data.exists());
    }

    #[cfg(unix)]
    #[test]
    fn only_regular_files_are_replaced_and_modes_are_kept() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        // a FIFO, a device and a directory stay what they are
        let fifo = dir.path().join("pipe");
        assert!(std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success());
        let e = write_string_atomic(&fifo, "x").unwrap_err().to_string();
        assert!(e.contains("FIFO"), "{e}");
        assert!(!std::fs::metadata(&fifo).unwrap().is_file());
        let e = write_string_atomic(Path::new("/dev/null"), "x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("character device"), "{e}");
        let e = write_string_atomic(dir.path(), "x")
            .unwrap_err()
            .to_string();
        assert!(e.contains("a directory"), "{e}");
        // a replaced file keeps its mode
        let p = dir.path().join("law.json");
        std::fs::write(&p, "old").unwrap();
        std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_string_atomic(&p, "new").unwrap();
        assert_eq!(
            std::fs::metadata(&p).unwrap().permissions().mode() & 0o777,
            0o640
        );
        // a new file gets 0666 less the umask, like open(2) (not tempfile's private 0600)
        let q = dir.path().join("new.csv");
        write_string_atomic(&q, "x").unwrap();
        let mode = std::fs::metadata(&q).unwrap().permissions().mode() & 0o777;
        let mask = umask_now();
        assert_eq!(mode, 0o666 & !mask, "mode {mode:o}, umask {mask:o}");
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            3,
            "temp file left"
        );
    }

    #[cfg(unix)]
    #[test]
    fn a_link_at_the_output_path_is_refused_and_its_target_kept() {
        let dir = tempfile::tempdir().unwrap();
        let outside = dir.path().join("outside.txt");
        std::fs::write(&outside, "precious").unwrap();
        let inner = dir.path().join("study");
        std::fs::create_dir(&inner).unwrap();
        let link = inner.join("report.html");
        std::os::unix::fs::symlink(&outside, &link).unwrap();
        let e = write_string_atomic(&link, "page").unwrap_err().to_string();
        assert!(
            e.contains("symbolic link") && e.contains("report.html"),
            "{e}"
        );
        let e = create_output_file(&link).unwrap_err().to_string();
        assert!(e.contains("symbolic link"), "{e}");
        // a dangling link is refused too, and nothing is created where it points
        let dangling = inner.join("results.csv");
        let nowhere = dir.path().join("created-outside.csv");
        std::os::unix::fs::symlink(&nowhere, &dangling).unwrap();
        assert!(write_string_atomic(&dangling, "x").is_err());
        assert!(create_output_file(&dangling).is_err());
        assert!(!nowhere.exists());
        assert_eq!(std::fs::read_to_string(&outside).unwrap(), "precious");
        assert!(std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(
            std::fs::read_dir(&inner).unwrap().count(),
            2,
            "temp file left"
        );
        // a plain new file is created, and truncated when written again
        let log = inner.join("log.txt");
        std::io::Write::write_all(&mut create_output_file(&log).unwrap(), b"long text").unwrap();
        std::io::Write::write_all(&mut create_output_file(&log).unwrap(), b"short").unwrap();
        assert_eq!(std::fs::read_to_string(&log).unwrap(), "short");
    }

    /// The process umask, read from /proc (Linux) without changing it.
    #[cfg(unix)]
    fn umask_now() -> u32 {
        std::fs::read_to_string("/proc/self/status")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find_map(|l| l.strip_prefix("Umask:"))
                    .and_then(|v| u32::from_str_radix(v.trim(), 8).ok())
            })
            .unwrap_or(0o022)
    }
}
