//! Typed errors of the library. Messages tell the user what to change.

use std::path::PathBuf;

/// Where in a text file something went wrong (1-based line and column).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    pub file: PathBuf,
    pub line: usize,
    pub column: usize,
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}:{}", self.file.display(), self.line, self.column)
    }
}

/// Every error the library returns.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// Malformed input text: where and what was expected.
    #[error("{at}: {message}")]
    Parse { at: Location, message: String },

    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// A valid file that describes something articula cannot model, or an option that does not
    /// fit the data (e.g. a stature outside 1.0–2.3 m). The message says which option fixes it.
    #[error("{0}")]
    Invalid(String),

    /// A numerical failure, e.g. a singular mass matrix; the message names the joint.
    #[error("{0}")]
    Numerical(String),

    /// A computation stopped because its caller asked it to (a user interface's cancel).
    #[error("cancelled")]
    Cancelled,
}

pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    pub fn parse(
        file: impl Into<PathBuf>,
        line: usize,
        column: usize,
        message: impl Into<String>,
    ) -> Self {
        Error::Parse {
            at: Location {
                file: file.into(),
                line,
                column,
            },
            message: message.into(),
        }
    }
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io {
            path: path.into(),
            source,
        }
    }
}
