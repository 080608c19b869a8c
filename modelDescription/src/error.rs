//! The error of reading or writing a model description.

use std::fmt;

/// Reading a model description failed. The message names where the description came from
/// (a file path, or the name the caller gave) and what is wrong with it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    origin: String,
    message: String,
}

impl Error {
    pub(crate) fn new(origin: &str, message: impl Into<String>) -> Self {
        Self {
            origin: origin.to_owned(),
            message: message.into(),
        }
    }

    /// Where the description came from (file path or caller-chosen name).
    pub fn origin(&self) -> &str {
        &self.origin
    }

    /// What is wrong, without the origin.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.origin, self.message)
    }
}

impl std::error::Error for Error {}
