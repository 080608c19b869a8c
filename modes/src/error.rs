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

/// Most characters of a value a message repeats.
pub const MAX_ECHOED_CHARS: usize = 120;

/// `value`, or its first [`MAX_ECHOED_CHARS`] characters and how long it was: a message
/// never repeats a value of megabytes.
fn shortened(value: String) -> String {
    let n = value.chars().count();
    if n <= MAX_ECHOED_CHARS {
        return value;
    }
    let head: String = value.chars().take(MAX_ECHOED_CHARS).collect();
    format!("{head}… ({n} characters)")
}

impl InputError {
    /// A field's value is not allowed; a long value is shortened in the message.
    pub fn field(
        file: impl Into<String>,
        field: impl Into<String>,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        InputError::Field {
            file: file.into(),
            field: field.into(),
            value: shortened(value.to_string()),
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

#[cfg(test)]
mod tests {
    use super::InputError;

    #[test]
    fn a_long_value_is_shortened_in_the_message() {
        let long = "x".repeat(10 << 20);
        let e = InputError::field("s.toml", "name", &long, "too long").to_string();
        assert!(e.len() < 300, "{} bytes", e.len());
        assert!(
            e.contains(&format!("{}… ({} characters)", "x".repeat(120), 10 << 20)),
            "{e}"
        );
        let short = InputError::field("s.toml", "name", "\"a b\"", "bad").to_string();
        assert_eq!(short, "s.toml: field `name` = \"a b\": bad");
    }
}
