//! What produced an output: the program and version, the command, every input with its
//! SHA-256, and the seed. Written beside a file output (`dataset.csv` →
//! `dataset.csv.provenance.json`) or into a directory output (`provenance.json`), so a result
//! can be traced to, and checked against, the exact inputs that made it.

use crate::atomic::write_string_atomic;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::io::Read;
use std::path::{Path, PathBuf};

/// One input of a run.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct InputDigest {
    /// The flag or role it came in by (`--data`, `--recordings`).
    pub role: String,
    pub path: String,
    /// Hex SHA-256 of the file's bytes.
    pub sha256: String,
    pub bytes: u64,
}

/// The record of a run.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Provenance {
    pub program: String,
    pub version: String,
    /// The command line, program name first.
    pub command: Vec<String>,
    pub inputs: Vec<InputDigest>,
    /// The seed of every random choice, where the run made any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
}

/// The command to record: the current call's ([`crate::call_scope`]; a host library such as
/// the Python package names its function and options there), else the process's command line.
pub fn command() -> Vec<String> {
    crate::call_scope::CallScope::with_current(|s| s.command.clone())
        .unwrap_or_else(|| std::env::args().collect())
}

/// Hex digits of a SHA-256 digest.
fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// Hex SHA-256 of bytes already in memory.
pub fn sha256_bytes(bytes: &[u8]) -> String {
    hex(&Sha256::digest(bytes))
}

/// Hex SHA-256 of a value's compact JSON (`serde_json::to_vec`), serialised straight into
/// the hasher: no copy of the text is held, whatever its size.
pub fn sha256_json<T: Serialize + ?Sized>(value: &T) -> serde_json::Result<String> {
    struct Hasher(Sha256);
    impl std::io::Write for Hasher {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.0.update(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    let mut h = Hasher(Sha256::new());
    serde_json::to_writer(&mut h, value)?;
    Ok(hex(&h.0.finalize()))
}

/// Hex SHA-256 of a file, streamed.
pub fn sha256_file(path: &Path) -> Result<(String, u64)> {
    let mut f = crate::input::open_regular(path, "input")?;
    let mut h = Sha256::new();
    let mut buf = vec![0u8; 1 << 20];
    let mut total = 0u64;
    loop {
        let n = f.read(&mut buf).map_err(|e| Error::io(path, e))?;
        if n == 0 {
            break;
        }
        h.update(&buf[..n]);
        total += n as u64;
    }
    Ok((hex(&h.finalize()), total))
}

impl Provenance {
    /// A record for `program` `version` run as `command`.
    pub fn new(program: &str, version: &str, command: Vec<String>) -> Self {
        Provenance {
            program: program.into(),
            version: version.into(),
            command,
            inputs: Vec::new(),
            seed: None,
        }
    }

    /// Add an input file (hashed now).
    pub fn input(mut self, role: &str, path: &Path) -> Result<Self> {
        let (sha256, bytes) = sha256_file(path)?;
        self.inputs.push(InputDigest {
            role: role.into(),
            path: path.display().to_string(),
            sha256,
            bytes,
        });
        Ok(self)
    }

    /// Add every input of a list of (role, path).
    pub fn inputs(self, inputs: &[(&str, &Path)]) -> Result<Self> {
        inputs
            .iter()
            .try_fold(self, |p, (role, path)| p.input(role, path))
    }

    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = Some(seed);
        self
    }

    /// The record with every input path that lies under `root` rewritten relative to `root`
    /// (`root` itself becomes `.`); other paths (relative ones, absolute ones elsewhere) are
    /// kept as they are. A tree of outputs written with absolute paths under one directory
    /// then records its inputs relative to that directory, and stays valid wherever the
    /// directory is moved.
    pub fn relative_to(mut self, root: &Path) -> Self {
        for input in &mut self.inputs {
            if let Ok(rel) = Path::new(&input.path).strip_prefix(root) {
                input.path = if rel.as_os_str().is_empty() {
                    ".".into()
                } else {
                    rel.display().to_string()
                };
            }
        }
        self
    }

    /// The record's path for a file output.
    pub fn path_beside(output: &Path) -> PathBuf {
        let mut name = output
            .file_name()
            .map(|n| n.to_os_string())
            .unwrap_or_default();
        name.push(".provenance.json");
        output.with_file_name(name)
    }

    /// Write the record beside a file output.
    pub fn write_beside(&self, output: &Path) -> Result<PathBuf> {
        let p = Self::path_beside(output);
        self.write_to(&p)?;
        Ok(p)
    }

    /// Write the record as `provenance.json` into a directory output.
    pub fn write_into(&self, dir: &Path) -> Result<PathBuf> {
        let p = dir.join("provenance.json");
        self.write_to(&p)?;
        Ok(p)
    }

    /// The record `provenance.json`-beside-`output` written in full but not yet in place
    /// ([`crate::atomic::Staged`]): committed before the output it describes, after both are
    /// written, so that a full disk leaves neither new.
    pub fn stage_beside(&self, output: &Path) -> Result<crate::atomic::Staged> {
        let text = self.text()?;
        crate::atomic::stage(&Self::path_beside(output), |w| w.write_all(text.as_bytes()))
    }

    fn text(&self) -> Result<String> {
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| Error::invalid("provenance", e.to_string()))?;
        Ok(text + "\n")
    }

    fn write_to(&self, p: &Path) -> Result<()> {
        write_string_atomic(p, &self.text()?)
    }

    /// Read a record.
    pub fn read(p: &Path) -> Result<Self> {
        let text = crate::input::read_text(p, "provenance record", crate::budget::Cap::InputBytes)?;
        serde_json::from_str(&text)
            .map_err(|e| Error::input(crate::SourcePos::path(p), e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FIPS 180-2 test vector: SHA-256("abc").
    #[test]
    fn digests_and_round_trip() {
        let d = tempfile::tempdir().unwrap();
        let f = d.path().join("abc.txt");
        std::fs::write(&f, "abc").unwrap();
        let (h, n) = sha256_file(&f).unwrap();
        assert_eq!(
            h,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(n, 3);
        let p = Provenance::new("greybox", "0.1.0", vec!["greybox".into(), "fit".into()])
            .input("data", &f)
            .unwrap()
            .with_seed(7);
        let out = d.path().join("dataset.csv");
        let written = p.write_beside(&out).unwrap();
        assert!(written.ends_with("dataset.csv.provenance.json"));
        assert_eq!(Provenance::read(&written).unwrap(), p);
    }

    #[test]
    fn inputs_under_a_root_become_relative_to_it() {
        let d = tempfile::tempdir().unwrap();
        let sub = d.path().join("recordings");
        std::fs::create_dir_all(&sub).unwrap();
        let (inside, outside) = (sub.join("pin01.csv"), d.path().join("elsewhere.csv"));
        std::fs::write(&inside, "a").unwrap();
        std::fs::write(&outside, "b").unwrap();
        let p = Provenance::new("greybox", "0.1.0", vec!["greybox".into()])
            .input("recordings", &inside)
            .unwrap()
            .input("study", &outside)
            .unwrap();
        let rel = p.clone().relative_to(&sub);
        assert_eq!(rel.inputs[0].path, "pin01.csv");
        // outside the root: unchanged, and so are digests and sizes
        assert_eq!(rel.inputs[1].path, outside.display().to_string());
        assert_eq!(rel.inputs[0].sha256, p.inputs[0].sha256);
        assert_eq!(rel.inputs[0].bytes, 1);
        // a relative path is left as given; the root itself becomes "."
        let mut q = p.clone();
        q.inputs[0].path = "recordings/pin01.csv".into();
        q.inputs[1].path = sub.display().to_string();
        let q = q.relative_to(&sub);
        assert_eq!(q.inputs[0].path, "recordings/pin01.csv");
        assert_eq!(q.inputs[1].path, ".");
    }
}

/// The peak resident memory of this process so far, MB (`getrusage`; `None` where the
/// platform does not say).
pub fn peak_memory_mb() -> Option<f64> {
    #[cfg(target_os = "linux")]
    {
        let mut u = std::mem::MaybeUninit::<libc::rusage>::zeroed();
        // SAFETY: getrusage writes a rusage into the pointer it is given.
        let rc = unsafe { libc::getrusage(libc::RUSAGE_SELF, u.as_mut_ptr()) };
        if rc == 0 {
            // SAFETY: initialised by the successful call above
            let kb = unsafe { u.assume_init() }.ru_maxrss;
            return Some(kb as f64 / 1024.0);
        }
    }
    None
}

#[cfg(test)]
mod peak_memory_tests {
    #[test]
    fn peak_memory_is_a_plausible_non_decreasing_size() {
        let Some(before) = super::peak_memory_mb() else {
            return;
        };
        let mut v = vec![0u8; 64 << 20];
        for (i, b) in v.iter_mut().enumerate().step_by(1024) {
            *b = i as u8 | 1;
        }
        let touched: u64 = v.iter().step_by(1024).map(|b| *b as u64).sum();
        std::hint::black_box(touched);
        let after = super::peak_memory_mb().unwrap();
        // a peak never falls; how much 64 MB touched adds depends on the kernel (or a
        // sandbox's) page accounting and on what other tests in this process touched
        // before (+19 MB under gVisor when run alone), so only plausibility is checked
        assert!(
            before > 1.0 && after.is_finite() && after >= before,
            "{before} → {after}"
        );
    }
}
