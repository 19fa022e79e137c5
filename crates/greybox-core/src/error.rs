//! Errors. Every error caused by user input names where it happened.

use std::fmt;
use std::path::{Path, PathBuf};

/// Where in an input something went wrong: file (or other source), and as much of
/// line / field / byte offset as the reader knows.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SourcePos {
    /// File name or other description of the source.
    pub source: String,
    /// 1-based line number (text formats).
    pub line: Option<u64>,
    /// Column or field name.
    pub field: Option<String>,
    /// Byte offset from the start of the file (binary formats).
    pub byte: Option<u64>,
}

impl SourcePos {
    pub fn file(source: impl Into<String>) -> Self {
        SourcePos {
            source: source.into(),
            ..Default::default()
        }
    }
    pub fn path(path: &Path) -> Self {
        Self::file(path.display().to_string())
    }
    pub fn line(mut self, line: u64) -> Self {
        self.line = Some(line);
        self
    }
    pub fn field(mut self, field: impl Into<String>) -> Self {
        self.field = Some(field.into());
        self
    }
    pub fn byte(mut self, byte: u64) -> Self {
        self.byte = Some(byte);
        self
    }
}

impl fmt::Display for SourcePos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.source)?;
        if let Some(l) = self.line {
            write!(f, ", line {l}")?;
        }
        if let Some(b) = self.byte {
            write!(f, ", byte {b}")?;
        }
        if let Some(c) = &self.field {
            write!(f, ", field '{c}'")?;
        }
        Ok(())
    }
}

/// The one error type of the greybox library crates.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Malformed or physically impossible input data, with its position.
    #[error("{pos}: {message}")]
    Input { pos: SourcePos, message: String },
    /// An invalid parameter (plan, configuration, function argument).
    #[error("invalid {what}: {message}")]
    Invalid { what: String, message: String },
    /// An I/O failure on a named path. The I/O error is part of the message, not a separate
    /// cause, so that a report of the whole chain (`{:#}`) names it once; a missing file says
    /// "not found" first.
    #[error("{}: {}{error}", path.display(), if error.kind() == std::io::ErrorKind::NotFound { "not found: " } else { "" })]
    Io {
        path: PathBuf,
        error: std::io::Error,
    },
    /// A setting refused, named by its typed path ([`crate::setting`]), so that each surface
    /// words it its own way.
    #[error("{0}")]
    Setting(Box<crate::setting::SettingError>),
    /// The call was stopped on request ([`crate::interrupt`]).
    #[error("interrupted")]
    Interrupted,
}

impl From<crate::interrupt::Interrupted> for Error {
    fn from(_: crate::interrupt::Interrupted) -> Self {
        Error::Interrupted
    }
}

impl Error {
    pub fn input(pos: SourcePos, message: impl Into<String>) -> Self {
        Error::Input {
            pos,
            message: message.into(),
        }
    }
    pub fn invalid(what: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Invalid {
            what: what.into(),
            message: message.into(),
        }
    }
    /// The setting `path` refused for `message`.
    pub fn setting(path: crate::setting::SettingPath, message: impl Into<String>) -> Self {
        Error::Setting(Box::new(crate::setting::SettingError::new(path, message)))
    }
    pub fn io(path: impl Into<PathBuf>, error: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            error,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

impl From<crate::setting::SettingError> for Error {
    fn from(e: crate::setting::SettingError) -> Self {
        Error::Setting(Box::new(e))
    }
}

/// The [`crate::setting::SettingError`] an error is or wraps (a library [`Error::Setting`]), if any:
/// for a surface that words settings its own way.
pub fn as_setting<'a>(
    e: &'a (dyn std::error::Error + 'static),
) -> Option<&'a crate::setting::SettingError> {
    e.downcast_ref::<crate::setting::SettingError>()
        .or_else(|| match e.downcast_ref::<Error>() {
            Some(Error::Setting(s)) => Some(s),
            _ => None,
        })
}
