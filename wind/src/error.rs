//! Error type of the crate.

/// Everything that can go wrong when generating or reading a wind field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WindError {
    /// A parameter out of its valid range: `field` as written in a scenario (e.g.
    /// `intensity_u`), `value` the offending value.
    #[error("invalid {field} = {value}: {reason}")]
    Invalid {
        field: &'static str,
        value: String,
        reason: String,
    },
    /// A spectrum name that is not one of [`crate::Spectrum::NAMES`].
    #[error("unknown spectrum \"{name}\"; expected one of {}", crate::Spectrum::NAMES.join(", "))]
    UnknownSpectrum { name: String },
    /// A problem on one line of a record (1-based line number).
    #[error("{file}:{line}: {problem}")]
    RecordLine {
        file: String,
        line: usize,
        problem: String,
    },
    /// A problem with a record as a whole.
    #[error("{file}: {problem}")]
    RecordFile { file: String, problem: String },
}

impl WindError {
    pub(crate) fn invalid(field: &'static str, value: f64, reason: &str) -> WindError {
        WindError::Invalid {
            field,
            value: format!("{value}"),
            reason: reason.into(),
        }
    }
}
