//! Output paths that cannot destroy inputs, and output directories replaced whole.
//!
//! * [`check_file_output`]: a file output must not be one of the command's inputs (same
//!   canonical path or same file identity: a hard link or a bind mount counts) and must be a
//!   regular file if it exists.
//! * [`check_dir_output`]: a directory output, which is replaced whole, must not hold an input.
//! * [`StagedDir`]: a directory output is written into a fresh staging directory beside it and
//!   swapped in whole when complete, so the directory holds one complete run or the previous
//!   one, never a mix; an existing non-empty directory is replaced only when asked
//!   ([`Existing::Replace`], the CLI's `--force`). Never the working directory, one of its
//!   ancestors, the user's home or `/` ([`refuse_enclosing_dir`]): replacing it would delete
//!   the files the user is working among.
//! * [`path_component`]: a name read from a file (a sweep case id) that becomes a path
//!   component is one plain component, so that it never leads out of its directory;
//!   [`output_subdir`]: a directory written into is a directory, never a planted link.

use crate::atomic::{describe_kind, replaceable_target};
use crate::cleanup::{self, CleanupGuard};
use crate::{Error, Result, SourcePos};
use std::path::{Path, PathBuf};

/// A command's input: the setting it came from (its field name, `data`, shown in backticks;
/// the command line shows its flag) or a role in words, and its path.
pub type Input<'a> = (&'a str, &'a Path);

fn canonical_or_lexical(p: &Path) -> PathBuf {
    if let Ok(c) = std::fs::canonicalize(p) {
        return c;
    }
    // not there yet: canonical parent + name
    match (p.parent(), p.file_name()) {
        (Some(parent), Some(name)) => {
            let parent = if parent.as_os_str().is_empty() {
                Path::new(".")
            } else {
                parent
            };
            std::fs::canonicalize(parent).map_or_else(|_| p.to_path_buf(), |c| c.join(name))
        }
        _ => p.to_path_buf(),
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    same_file::is_same_file(a, b).unwrap_or(false)
        || canonical_or_lexical(a) == canonical_or_lexical(b)
}

/// A setting's name as messages show it: a field (`out`, `recordings`) in backticks, which
/// the command line shows as its flag; a description ("a file the law reads") as it is.
fn named(name: &str) -> String {
    if !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        format!("`{name}`")
    } else {
        name.to_string()
    }
}

/// Refuse a file output (the setting `out_flag`, e.g. `out`) that is one of `inputs` or is not a regular
/// file.
///
/// The provenance record written beside it (`<out>.provenance.json`) is an output too: it
/// must not be an input either (`--data y.csv.provenance.json --out y.csv`).
pub fn check_file_output(out: &Path, out_flag: &str, inputs: &[Input]) -> Result<()> {
    replaceable_target(out)?;
    let sidecar = crate::provenance::Provenance::path_beside(out);
    for (flag, input) in inputs {
        let written = if same_file(out, input) {
            named(out_flag)
        } else if same_file(&sidecar, input) {
            format!(
                "the provenance record beside {} ({})",
                named(out_flag),
                sidecar.display()
            )
        } else {
            continue;
        };
        return Err(Error::input(
            SourcePos::path(out),
            format!(
                "{written} is the input {} ({}): writing it would destroy the input; choose another output path",
                named(flag),
                input.display()
            ),
        ));
    }
    Ok(())
}

/// Refuse a directory output that is not a directory, or that is or holds one of `inputs`
/// (replacing it would delete them).
pub fn check_dir_output(out: &Path, out_flag: &str, inputs: &[Input]) -> Result<()> {
    match std::fs::metadata(out) {
        Ok(m) if !m.is_dir() => {
            return Err(Error::input(
                SourcePos::path(out),
                format!(
                    "{} must be a directory, but the path is {}",
                    named(out_flag),
                    describe_kind(&m)
                ),
            ))
        }
        Ok(_) => {}
        Err(_) => return Ok(()),
    }
    let dir = canonical_or_lexical(out);
    for (flag, input) in inputs {
        if canonical_or_lexical(input).starts_with(&dir) {
            return Err(Error::input(
                SourcePos::path(out),
                format!(
                    "{} would be replaced whole, but it holds the input {} ({}); choose another output directory",
                    named(out_flag),
                    named(flag),
                    input.display()
                ),
            ));
        }
    }
    Ok(())
}

/// What to do with an existing, non-empty output directory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Existing {
    /// Refuse with an error that names `--force`.
    Refuse,
    /// Replace it whole once the new run is complete.
    Replace,
}

impl Existing {
    pub fn from_force(force: bool) -> Self {
        if force {
            Existing::Replace
        } else {
            Existing::Refuse
        }
    }
}

/// A directory output under construction: write into [`StagedDir::path`], then
/// [`StagedDir::commit`]. Dropped without a commit (an error, a panic), the staging directory
/// is removed; on SIGINT/SIGTERM the program's handler removes it ([`crate::cleanup`]).
#[derive(Debug)]
pub struct StagedDir {
    target: PathBuf,
    staging: PathBuf,
    guard: Option<CleanupGuard>,
    /// A resumable run's staging directory (`<target>.partial`) outlives an interruption.
    resumable: bool,
    /// The lock that keeps a second run off the same output while this one writes it.
    _lock: OutputLock,
}

/// An existing `target` must be a directory, and empty unless `existing` allows replacing it.
fn check_replaceable_dir(target: &Path, flag: &str, existing: Existing) -> Result<()> {
    let Ok(m) = std::fs::metadata(target) else {
        return Ok(());
    };
    if !m.is_dir() {
        return Err(Error::input(
            SourcePos::path(target),
            format!(
                "{} must be a directory, but the path is {}",
                named(flag),
                describe_kind(&m)
            ),
        ));
    }
    if existing == Existing::Refuse && non_empty_dir(target) {
        return Err(Error::input(
            SourcePos::path(target),
            format!(
                "{name} already holds files (an earlier run?): give `force` to replace the directory whole, or choose another {name}",
                name = named(flag)
            ),
        ));
    }
    Ok(())
}

fn non_empty_dir(p: &Path) -> bool {
    std::fs::read_dir(p).is_ok_and(|mut d| d.next().is_some())
}

/// Refuse a directory output that is (once links and `..` are resolved) the working
/// directory or one of its ancestors, the user's home or one of its ancestors, or `/`: it is
/// replaced whole, and with it everything the user is working among (`--out "$PWD"
/// --force`, `--out ..`, `--out ~`).
pub fn refuse_enclosing_dir(target: &Path, flag: &str) -> Result<()> {
    let Ok(dir) = std::fs::canonicalize(target) else {
        // nothing there yet (or unreadable: the write fails later, naming it)
        return Ok(());
    };
    let canon = |p: PathBuf| std::fs::canonicalize(&p).unwrap_or(p);
    let cwd = std::env::current_dir().ok().map(canon);
    let home = std::env::var_os("HOME")
        .filter(|h| !h.is_empty())
        .map(|h| canon(PathBuf::from(h)));
    let why = if cwd.as_ref().is_some_and(|c| c.starts_with(&dir)) {
        "the working directory or one of its ancestors"
    } else if home.as_ref().is_some_and(|h| h.starts_with(&dir)) {
        "the home directory or one of its ancestors"
    } else if dir.parent().is_none() {
        "the root directory"
    } else {
        return Ok(());
    };
    Err(Error::input(
        SourcePos::path(target),
        format!(
            "{} is {why} ({}): an output directory is replaced whole, which would delete the files there; choose a new directory for the output",
            named(flag),
            dir.display()
        ),
    ))
}

/// The longest name [`path_component`] lets through, in bytes (a file name's limit on
/// common file systems is 255).
pub const MAX_COMPONENT_BYTES: usize = 200;

/// `name`, read from `file`'s `field`, if it is one plain path component: not empty, not `.`
/// or `..`, no `/` or `\`, no NUL or other control character, at most
/// [`MAX_COMPONENT_BYTES`] bytes. Otherwise an error naming the file and the field: joined
/// to a directory, such a name could lead outside it (`../../victim`).
pub fn path_component<'a>(name: &'a str, file: &Path, field: &str) -> Result<&'a str> {
    let problem = if name.is_empty() {
        Some("is empty")
    } else if name == "." || name == ".." {
        Some("is `.` or `..`")
    } else if name.contains(['/', '\\']) {
        Some("holds a path separator (`/` or `\\`)")
    } else if name.chars().any(char::is_control) {
        Some("holds a control character")
    } else if name.len() > MAX_COMPONENT_BYTES {
        Some("is too long")
    } else {
        None
    };
    match problem {
        None => Ok(name),
        Some(p) => Err(Error::input(
            SourcePos::path(file).field(field),
            format!(
                "the name {:?} {p}: it becomes a file or directory name, and must be one plain name (at most {MAX_COMPONENT_BYTES} bytes) that stays inside its directory",
                name.chars().take(80).collect::<String>()
            ),
        )),
    }
}

/// The directory `parent/name` (`name` a fixed name or one checked by [`path_component`]),
/// created if missing: what is there must be a real directory, never a symbolic link, which
/// a hostile directory could plant to lead the files written there outside it.
pub fn output_subdir(parent: &Path, name: &str) -> Result<PathBuf> {
    let dir = parent.join(name);
    match std::fs::symlink_metadata(&dir) {
        Ok(m) if m.is_dir() => Ok(dir),
        Ok(m) => {
            let what = if m.file_type().is_symlink() {
                "a symbolic link: greybox writes into a directory only when it is one, never through a link, which could lead outside"
            } else {
                describe_kind(&m)
            };
            Err(Error::input(
                SourcePos::path(&dir),
                format!("expected an output directory, but the path is {what}"),
            ))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
            Ok(dir)
        }
        Err(e) => Err(Error::io(&dir, e)),
    }
}

impl StagedDir {
    /// Start writing the directory `target` (`flag` names it in errors).
    pub fn begin(target: &Path, flag: &str, existing: Existing) -> Result<Self> {
        let target = &lexical(target);
        refuse_enclosing_dir(target, flag)?;
        check_replaceable_dir(target, flag, existing)?;
        let (parent, name) = split(target)?;
        std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
        let lock = OutputLock::take(&parent, &name, target)?;
        remove_stale_staging(&parent, &name);
        let mut b = tempfile::Builder::new();
        // the owner's process id in the name: a later run removes the staging directories
        // of runs that were killed ([`remove_stale_staging`])
        let prefix = format!("{}{}-", staging_prefix(&name), std::process::id());
        b.prefix(&prefix);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            b.permissions(std::fs::Permissions::from_mode(0o777));
        }
        let staging = b
            .tempdir_in(&parent)
            .map_err(|e| Error::io(&parent, e))?
            .keep();
        let guard = cleanup::register(&staging, true);
        Ok(StagedDir {
            target: target.to_path_buf(),
            staging,
            guard: Some(guard),
            resumable: false,
            _lock: lock,
        })
    }

    /// The staging directory of a resumable run (one that writes checkpoints): the fixed path
    /// `<target>.partial`, kept when the run fails or is interrupted so that it can be resumed
    /// there, and swapped in whole when complete. `resume`: continue the run found there (or,
    /// when there is none, start one there from a checkpoint taken elsewhere); otherwise start
    /// afresh, refusing a left-over partial run unless `existing` is [`Existing::Replace`].
    pub fn resumable(target: &Path, flag: &str, existing: Existing, resume: bool) -> Result<Self> {
        let target = &lexical(target);
        refuse_enclosing_dir(target, flag)?;
        let (parent, name) = split(target)?;
        std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
        let lock = OutputLock::take(&parent, &name, target)?;
        let staging = parent.join(format!("{name}.partial"));
        let there = staging.is_dir();
        if there && !resume {
            if existing == Existing::Refuse {
                return Err(Error::input(
                    SourcePos::path(&staging),
                    "an interrupted run is here: give `resume` with its checkpoint to continue it, or `force` to start afresh",
                ));
            }
            std::fs::remove_dir_all(&staging).map_err(|e| Error::io(&staging, e))?;
        }
        if !(there && resume) {
            // a new run (possibly continuing from a checkpoint taken elsewhere)
            check_replaceable_dir(target, flag, existing)?;
            std::fs::create_dir_all(&staging).map_err(|e| Error::io(&staging, e))?;
        }
        Ok(StagedDir {
            target: target.to_path_buf(),
            staging,
            guard: None,
            resumable: true,
            _lock: lock,
        })
    }

    /// Where the run writes its files.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The directory the run will become.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Where a path written under [`StagedDir::path`] will be once committed (for messages
    /// and summaries); other paths are returned unchanged.
    pub fn shown(&self, p: impl AsRef<Path>) -> PathBuf {
        let p = p.as_ref();
        p.strip_prefix(&self.staging)
            .map_or_else(|_| p.to_path_buf(), |rel| self.target.join(rel))
    }

    /// [`StagedDir::shown`] for a path given as text.
    pub fn shown_str(&self, p: &str) -> String {
        self.shown(Path::new(p)).display().to_string()
    }

    /// Swap the complete run in: atomically where the system can exchange two paths (Linux
    /// `renameat2(RENAME_EXCHANGE)`), else by two renames; the previous directory, if any, is
    /// then deleted. The final path.
    pub fn commit(mut self) -> Result<PathBuf> {
        let old = match self.guard.take() {
            Some(guard) => guard.complete(|| swap_in(&self.staging, &self.target))?,
            None => swap_in(&self.staging, &self.target)?,
        };
        self.resumable = false;
        if let Some(old) = old {
            // the previous run; losing it now is what --force asked for
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(self.target.clone())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if self.guard.take().is_some() {
            let _ = std::fs::remove_dir_all(&self.staging);
        } else if self.resumable && !non_empty_dir(&self.staging) {
            // nothing to resume: no clutter
            let _ = std::fs::remove_dir(&self.staging);
        }
    }
}

/// `path` with its `.` components dropped (`proj/.` is `proj`): the directory a user means,
/// which can be renamed into place (a path ending in `.` cannot).
fn lexical(path: &Path) -> PathBuf {
    let p: PathBuf = path.components().collect();
    if p.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        p
    }
}

/// An exclusive lock on one output path for the life of a run: `.NAME.greybox-lock` beside it,
/// locked with `flock` (released by the system when the process ends, however it ends, so a
/// killed run never blocks the next) and removed when the run is done. A second run that
/// would write the same output while the first does is refused, instead of the two leaving a
/// mix of both.
#[derive(Debug)]
struct OutputLock {
    path: PathBuf,
    _file: std::fs::File,
    /// Removes the lock file when the run is interrupted (SIGINT, SIGTERM) too.
    _cleanup: CleanupGuard,
}

impl OutputLock {
    fn take(parent: &Path, name: &str, target: &Path) -> Result<OutputLock> {
        let path = parent.join(format!(".{name}.greybox-lock"));
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| Error::io(&path, e))?;
        match file.try_lock() {
            Ok(()) => Ok(OutputLock {
                _cleanup: cleanup::register(&path, false),
                path,
                _file: file,
            }),
            Err(std::fs::TryLockError::WouldBlock) => Err(Error::input(
                SourcePos::path(target),
                "another greybox run is writing this output now: wait for it to finish, or give another output directory",
            )),
            Err(std::fs::TryLockError::Error(e)) => Err(Error::io(&path, e)),
        }
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}

/// The start of the names of `name`'s staging directories, before the owner's process id.
fn staging_prefix(name: &str) -> String {
    format!(".{name}.greybox-staging-")
}

/// Removes the staging directories of `name` in `parent` left by runs that were killed (a
/// `SIGKILL`, a power cut: no clean-up ran), so that they do not pile up beside the output:
/// those whose owner process (the id in the name) no longer runs. A directory of a running
/// process (another run writing the same output) or one whose owner cannot be told is left.
fn remove_stale_staging(parent: &Path, name: &str) {
    let prefix = staging_prefix(name);
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    for e in entries.flatten() {
        let file_name = e.file_name();
        let Some(rest) = file_name.to_str().and_then(|n| n.strip_prefix(&prefix)) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
        if is_dir && pid != std::process::id() && process_gone(pid) {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

/// Whether no process `pid` runs (only where the system says so: `/proc` on Linux).
fn process_gone(pid: u32) -> bool {
    #[cfg(target_os = "linux")]
    {
        Path::new("/proc/self").exists() && !Path::new(&format!("/proc/{pid}")).exists()
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = pid;
        false
    }
}

fn split(target: &Path) -> Result<(PathBuf, String)> {
    let name = target
        .file_name()
        .ok_or_else(|| Error::input(SourcePos::path(target), "an output directory needs a name"))?
        .to_string_lossy()
        .to_string();
    let parent = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    Ok((parent, name))
}

/// Put `staging` at `target`; the path where the previous `target` now is, if there was one.
fn swap_in(staging: &Path, target: &Path) -> Result<Option<PathBuf>> {
    if std::fs::symlink_metadata(target).is_err() {
        std::fs::rename(staging, target).map_err(|e| Error::io(target, e))?;
        return Ok(None);
    }
    // an existing empty or replaceable directory
    #[cfg(target_os = "linux")]
    if exchange(staging, target).is_ok() {
        return Ok(Some(staging.to_path_buf()));
    }
    let old = staging.with_file_name(format!(
        "{}.old",
        staging
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default()
    ));
    std::fs::rename(target, &old).map_err(|e| Error::io(target, e))?;
    std::fs::rename(staging, target).map_err(|e| Error::io(target, e))?;
    Ok(Some(old))
}

#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::ffi::CString;
    use std::os::unix::ffi::OsStrExt;
    let ca = CString::new(a.as_os_str().as_bytes())?;
    let cb = CString::new(b.as_os_str().as_bytes())?;
    // SAFETY: two valid NUL-terminated paths, relative to the working directory.
    let r = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            ca.as_ptr(),
            libc::AT_FDCWD,
            cb.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if r == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two runs on one output: the second is refused while the first writes, and runs once the
    /// first is done; `proj/.` is the directory `proj`; no lock file or staging is left.
    #[test]
    fn one_run_at_a_time_per_output_and_a_dotted_path_is_its_directory() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("proj");
        let first = StagedDir::begin(&out, "out", Existing::Refuse).unwrap();
        let e = StagedDir::begin(&out, "out", Existing::Refuse)
            .expect_err("a second run refused")
            .to_string();
        assert!(
            e.contains("proj") && e.contains("another greybox run"),
            "{e}"
        );
        let e = StagedDir::resumable(&out, "out", Existing::Refuse, false)
            .expect_err("a resumable run refused too")
            .to_string();
        assert!(e.contains("another greybox run"), "{e}");
        std::fs::write(first.path().join("a.txt"), "1").unwrap();
        first.commit().unwrap();
        let dotted = d.path().join("proj").join(".");
        let second = StagedDir::begin(&dotted, "out", Existing::Replace).unwrap();
        std::fs::write(second.path().join("b.txt"), "2").unwrap();
        assert_eq!(second.commit().unwrap(), out);
        assert_eq!(std::fs::read_to_string(out.join("b.txt")).unwrap(), "2");
        let left: Vec<String> = std::fs::read_dir(d.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(left, ["proj"]);
    }

    #[test]
    fn output_equal_to_an_input_is_refused_also_through_a_hard_link() {
        let d = tempfile::tempdir().unwrap();
        let raw = d.path().join("pin01.csv");
        std::fs::write(&raw, "raw").unwrap();
        let e = check_file_output(&raw, "out", &[("recordings", &raw)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("`out` is the input `recordings`"), "{e}");
        let dotted = d.path().join(".").join("pin01.csv");
        assert!(check_file_output(&dotted, "out", &[("recordings", &raw)]).is_err());
        let link = d.path().join("hard.csv");
        std::fs::hard_link(&raw, &link).unwrap();
        assert!(check_file_output(&link, "out", &[("data", &raw)]).is_err());
        let other = d.path().join("dataset.csv");
        check_file_output(&other, "out", &[("recordings", &raw)]).unwrap();
        assert_eq!(std::fs::read_to_string(&raw).unwrap(), "raw");
    }

    #[test]
    fn directory_output_holding_an_input_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("run");
        std::fs::create_dir(&out).unwrap();
        let data = out.join("dataset.csv");
        std::fs::write(&data, "x").unwrap();
        let e = check_dir_output(&out, "out", &[("data", &data)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("holds the input `data`"), "{e}");
        check_dir_output(&d.path().join("elsewhere"), "out", &[("data", &data)]).unwrap();
        let e = check_dir_output(&data, "out", &[]).unwrap_err().to_string();
        assert!(e.contains("must be a directory"), "{e}");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_killed_runs_staging_is_removed_by_the_next_run() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("fit");
        // a run killed before its commit: no process has this id (above pid_max)
        let dead = d.path().join(".fit.greybox-staging-4294967295-abc123");
        std::fs::create_dir(&dead).unwrap();
        std::fs::write(dead.join("half.json"), "{").unwrap();
        // a staging directory of a running process (this one's parent shell, pid 1) stays
        let alive = d.path().join(".fit.greybox-staging-1-def456");
        std::fs::create_dir(&alive).unwrap();
        let s = StagedDir::begin(&out, "out", Existing::Refuse).unwrap();
        std::fs::write(s.path().join("report.json"), "ok").unwrap();
        s.commit().unwrap();
        assert!(!dead.exists(), "the killed run's staging survived");
        assert!(alive.exists(), "a running process's staging was removed");
        assert_eq!(
            std::fs::read_to_string(out.join("report.json")).unwrap(),
            "ok"
        );
    }

    #[test]
    fn staged_directory_is_one_run_or_the_other() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("fit");
        // first run
        let s = StagedDir::begin(&out, "out", Existing::Refuse).unwrap();
        std::fs::write(s.path().join("svr.json"), "old").unwrap();
        std::fs::write(s.path().join("report.json"), "old").unwrap();
        assert!(!out.exists(), "nothing visible before the commit");
        s.commit().unwrap();
        // second run refused without --force
        let e = StagedDir::begin(&out, "out", Existing::Refuse)
            .unwrap_err()
            .to_string();
        assert!(e.contains("give `force`"), "{e}");
        // a failed second run leaves the first one untouched and no staging behind
        {
            let s = StagedDir::begin(&out, "out", Existing::Replace).unwrap();
            std::fs::write(s.path().join("report.json"), "new").unwrap();
            // dropped: the run failed
        }
        assert_eq!(
            std::fs::read_to_string(out.join("report.json")).unwrap(),
            "old"
        );
        assert_eq!(
            std::fs::read_dir(d.path()).unwrap().count(),
            1,
            "staging left behind"
        );
        // a complete second run replaces the first whole: no stale svr.json
        let s = StagedDir::begin(&out, "out", Existing::Replace).unwrap();
        std::fs::write(s.path().join("report.json"), "new").unwrap();
        s.commit().unwrap();
        assert_eq!(
            std::fs::read_to_string(out.join("report.json")).unwrap(),
            "new"
        );
        assert!(
            !out.join("svr.json").exists(),
            "stale file from the previous run"
        );
        assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 1);
        // an existing empty directory needs no --force
        let empty = d.path().join("empty");
        std::fs::create_dir(&empty).unwrap();
        StagedDir::begin(&empty, "out", Existing::Refuse)
            .unwrap()
            .commit()
            .unwrap();
    }

    #[test]
    fn a_resumable_run_survives_failure_and_is_swapped_in_when_complete() {
        let d = tempfile::tempdir().unwrap();
        let out = d.path().join("sim");
        {
            let s = StagedDir::resumable(&out, "out", Existing::Refuse, false).unwrap();
            assert!(s.path().ends_with("sim.partial"));
            std::fs::write(s.path().join("checkpoint.json"), "step 500").unwrap();
            // the run fails or is killed here
        }
        assert!(
            d.path().join("sim.partial/checkpoint.json").exists(),
            "checkpoint lost"
        );
        let e = StagedDir::resumable(&out, "out", Existing::Refuse, false)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`resume`") && e.contains("`force`"), "{e}");
        let s = StagedDir::resumable(&out, "out", Existing::Refuse, true).unwrap();
        std::fs::write(s.path().join("forces.csv"), "done").unwrap();
        s.commit().unwrap();
        assert!(out.join("checkpoint.json").exists() && out.join("forces.csv").exists());
        assert!(!d.path().join("sim.partial").exists());
    }

    #[test]
    fn the_working_directory_and_its_ancestors_are_never_replaced() {
        let d = tempfile::tempdir().unwrap();
        let cwd = std::env::current_dir().unwrap();
        for p in [
            cwd.clone(),
            cwd.join(".."),
            PathBuf::from("/"),
            PathBuf::from(".."),
        ] {
            let e = refuse_enclosing_dir(&p, "out").unwrap_err().to_string();
            assert!(
                e.contains("`out` is the") && e.contains("replaced whole"),
                "{e}"
            );
            let e = StagedDir::begin(&p, "out", Existing::Replace)
                .unwrap_err()
                .to_string();
            assert!(e.contains("working directory"), "{e}");
            assert!(StagedDir::resumable(&p, "out", Existing::Replace, false).is_err());
        }
        if let Some(home) = std::env::var_os("HOME").filter(|h| !h.is_empty()) {
            assert!(refuse_enclosing_dir(Path::new(&home), "out").is_err());
        }
        // a directory beside the working directory, or a new one, is fine
        refuse_enclosing_dir(d.path(), "out").unwrap();
        refuse_enclosing_dir(&d.path().join("new"), "out").unwrap();
    }

    #[test]
    fn a_name_from_a_file_is_one_plain_component() {
        let f = Path::new("sweep/plan.json");
        for ok in ["c0007-1a2b3c4d", "a.b", "x..y", "ünïcode"] {
            assert_eq!(path_component(ok, f, "cases[0].id").unwrap(), ok);
        }
        let long = "a".repeat(MAX_COMPONENT_BYTES + 1);
        for bad in [
            "",
            ".",
            "..",
            "../../victim",
            "/etc",
            "a/b",
            "a\\b",
            "a\0b",
            "a\nb",
            &long,
        ] {
            let e = path_component(bad, f, "cases[3].id")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("sweep/plan.json") && e.contains("cases[3].id"),
                "{e}"
            );
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_link_planted_as_an_output_subdirectory_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let outside = d.path().join("outside");
        std::fs::create_dir(&outside).unwrap();
        let sweep = d.path().join("sweep");
        std::fs::create_dir(&sweep).unwrap();
        std::os::unix::fs::symlink(&outside, sweep.join("plots")).unwrap();
        let e = output_subdir(&sweep, "plots").unwrap_err().to_string();
        assert!(e.contains("plots") && e.contains("symbolic link"), "{e}");
        std::fs::write(sweep.join("cases"), "a file").unwrap();
        let e = output_subdir(&sweep, "cases").unwrap_err().to_string();
        assert!(e.contains("a regular file"), "{e}");
        let made = output_subdir(&sweep, "result").unwrap();
        assert!(made.is_dir());
        assert_eq!(output_subdir(&sweep, "result").unwrap(), made);
        assert_eq!(std::fs::read_dir(&outside).unwrap().count(), 0);
    }
}
