//! Input errors that name the file, the field (or line) and the offending value.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// A field holds a value that is not allowed.
    #[error("{file}: field `{field}` = {value}: {reason}")]
    Field {
        file: String,
        field: String,
        value: String,
        reason: String,
    },
    /// A data file is malformed at a given line (1-based).
    #[error("{}:{line}: {reason}", path.display())]
    Line {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    /// A file could not be read or parsed as a whole.
    #[error("{}: {reason}", path.display())]
    File { path: PathBuf, reason: String },
}

impl InputError {
    pub fn field(
        file: impl Into<String>,
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        InputError::Field {
            file: file.into(),
            field: field.into(),
            value: value.to_string(),
            reason: reason.into(),
        }
    }
    pub fn line(path: impl Into<PathBuf>, line: usize, reason: impl Into<String>) -> Self {
        InputError::Line {
            path: path.into(),
            line,
            reason: reason.into(),
        }
    }
    pub fn file(path: impl Into<PathBuf>, reason: impl Into<String>) -> Self {
        InputError::File {
            path: path.into(),
            reason: reason.into(),
        }
    }
}
