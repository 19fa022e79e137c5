//! How a case starts in a process of its own: the program that runs the sweep hands in a
//! [`CaseCommand`], so the sweep composes no command line of a particular binary. The local
//! pool starts it once per case; the Slurm executor writes it into the array script with the
//! task id as the index.
//!
//! ```
//! use greybox_sweep::launch::{CaseArg, CaseCommand};
//! use std::path::Path;
//! // what the `greybox` binary hands in: `greybox --quiet sweep run-case OUT --index N`
//! let c = CaseCommand::greybox("/opt/greybox/bin/greybox");
//! assert_eq!(c.args[0], CaseArg::text("--quiet"));
//! let args = c.args_for(Path::new("/scratch/s1"), "7");
//! assert_eq!(args, ["--quiet", "sweep", "run-case", "/scratch/s1", "--index", "7"]);
//! ```

use anyhow::{Context, Result};
use greybox_core::shell;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// One argument of a case's command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CaseArg {
    /// Passed as it is.
    Text(String),
    /// The sweep's output directory (absolute on Slurm).
    OutDir,
    /// The case's index in the plan (the array task id on Slurm).
    Index,
}

impl CaseArg {
    /// A literal argument.
    pub fn text(s: &str) -> CaseArg {
        CaseArg::Text(s.to_string())
    }
}

/// The program and arguments that run one case of a written plan (the case then runs
/// [`crate::run_case`] in that process).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CaseCommand {
    pub program: PathBuf,
    pub args: Vec<CaseArg>,
}

impl CaseCommand {
    pub fn new(program: impl Into<PathBuf>, args: impl IntoIterator<Item = CaseArg>) -> Self {
        CaseCommand {
            program: program.into(),
            args: args.into_iter().collect(),
        }
    }

    /// How the `greybox` program at `program` runs a case:
    /// `greybox --quiet sweep run-case OUT --index N`.
    pub fn greybox(program: impl Into<PathBuf>) -> CaseCommand {
        CaseCommand::new(
            program,
            [
                CaseArg::text("--quiet"),
                CaseArg::text("sweep"),
                CaseArg::text("run-case"),
                CaseArg::OutDir,
                CaseArg::text("--index"),
                CaseArg::Index,
            ],
        )
    }

    /// The same command with its program made absolute (a Slurm node starts elsewhere).
    pub fn absolute(&self) -> Result<CaseCommand> {
        Ok(CaseCommand {
            program: std::path::absolute(&self.program)?,
            args: self.args.clone(),
        })
    }

    /// The arguments for the plan in `out` and case `index` (a number, or a shell
    /// expression where the caller quotes it).
    pub fn args_for(&self, out: &Path, index: &str) -> Vec<OsString> {
        self.args
            .iter()
            .map(|a| match a {
                CaseArg::Text(t) => OsString::from(t),
                CaseArg::OutDir => out.as_os_str().to_owned(),
                CaseArg::Index => OsString::from(index),
            })
            .collect()
    }

    /// The command as one shell line for the plan in `out` (UTF-8 text), the index given as
    /// the shell expression `index_expr` (e.g. `"$SLURM_ARRAY_TASK_ID"`, written as it is):
    /// the program and the output directory quoted, every other argument quoted where it
    /// needs to be ([`shell::word`]).
    pub fn shell_line(&self, out: &str, index_expr: &str) -> Result<String> {
        let program = self
            .program
            .to_str()
            .with_context(|| format!("the case program {}: not UTF-8", self.program.display()))?;
        let mut words = vec![shell::quote(program)?];
        for a in &self.args {
            words.push(match a {
                CaseArg::Text(t) => shell::word(t)?,
                CaseArg::OutDir => shell::quote(out)?,
                CaseArg::Index => index_expr.to_string(),
            });
        }
        Ok(words.join(" "))
    }
}

/// The program `name` on `PATH` (what a library caller without a `greybox` executable of
/// its own, e.g. Python, hands in to start cases).
pub fn program_on_path(name: &str) -> Result<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| p.is_file())
        .with_context(|| {
            format!("cases run by the '{name}' program, but none is on PATH (install greybox's command line, the crate greybox-cli, e.g. with cargo install)")
        })
}
