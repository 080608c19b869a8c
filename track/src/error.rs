//! Error type of the crate.

use std::fmt;

/// Everything that can go wrong when building or reading a track irregularity.
#[derive(Debug, thiserror::Error)]
pub enum TrackError {
    /// A parameter is out of its valid range. `field` is the parameter's name as written in a
    /// scenario file (e.g. `lambda_min_m`), `value` its offending value.
    #[error("invalid {field} = {value}: {reason}")]
    Invalid {
        /// Name of the parameter.
        field: &'static str,
        /// The offending value, formatted.
        value: String,
        /// Why it is invalid.
        reason: String,
    },
    /// A spectrum name that is not one of [`crate::Spectrum::NAMES`].
    #[error("unknown spectrum {name:?}; valid names: {}", crate::Spectrum::NAMES.join(", "))]
    UnknownSpectrum {
        /// The name that was given.
        name: String,
    },
    /// A problem on one line of a record file.
    #[error("{file}:{line}: {problem}")]
    RecordLine {
        /// File name (or the source name given to [`crate::Record::parse`]).
        file: String,
        /// 1-based line number (comment and blank lines count).
        line: usize,
        /// What is wrong.
        problem: RecordProblem,
    },
    /// A problem with a record file as a whole.
    #[error("{file}: {problem}")]
    RecordFile {
        /// File name (or the source name given to [`crate::Record::parse`]).
        file: String,
        /// What is wrong.
        problem: RecordProblem,
    },
    /// The file could not be read or written.
    #[error("{file}: {source}")]
    Io {
        /// File name.
        file: String,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
}

/// What is wrong with a record file (see [`crate::record`] for the format).
#[derive(Debug, Clone, PartialEq)]
pub enum RecordProblem {
    /// The first line that is neither blank nor a comment is not a valid header.
    BadHeader {
        /// The line as found.
        found: String,
    },
    /// The file has no header line.
    MissingHeader,
    /// A data row has the wrong number of comma-separated fields.
    ColumnCount {
        /// Number of columns of the header.
        expected: usize,
        /// Number of fields found.
        found: usize,
    },
    /// A field is not a number.
    NotANumber {
        /// Column name.
        column: &'static str,
        /// The field text.
        text: String,
    },
    /// A field is NaN or infinite.
    NotFinite {
        /// Column name.
        column: &'static str,
        /// The field text.
        text: String,
    },
    /// `x_m` does not increase strictly.
    NonIncreasingX {
        /// `x_m` on this line, m.
        x: f64,
        /// `x_m` on the previous data row, m.
        previous: f64,
    },
    /// Fewer than two data rows.
    TooFewRows {
        /// Number of data rows found.
        found: usize,
    },
    /// A record declared periodic whose last row does not repeat the first row.
    PeriodicNotClosed,
}

impl fmt::Display for RecordProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RecordProblem::BadHeader { found } => write!(
                f,
                "expected the header `{}` (optionally followed by `,{}`), found `{found}`",
                crate::record_format::HEADER.join(","),
                crate::record_format::SLOPE_HEADER.join(",")
            ),
            RecordProblem::MissingHeader => write!(f, "no header line"),
            RecordProblem::ColumnCount { expected, found } => {
                write!(f, "wrong column count: expected {expected}, found {found}")
            }
            RecordProblem::NotANumber { column, text } => {
                write!(f, "column {column}: not a number: `{text}`")
            }
            RecordProblem::NotFinite { column, text } => {
                write!(f, "column {column}: NaN or infinite value `{text}`")
            }
            RecordProblem::NonIncreasingX { x, previous } => {
                write!(f, "x_m must increase strictly: {x} follows {previous}")
            }
            RecordProblem::TooFewRows { found } => {
                write!(f, "at least 2 data rows needed, found {found}")
            }
            RecordProblem::PeriodicNotClosed => write!(
                f,
                "record declared periodic, but its last row does not repeat the first row \
                 (all columns except x_m must be equal)"
            ),
        }
    }
}
