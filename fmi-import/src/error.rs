//! Status codes and errors of the importer.

use crate::logger::LogMessage;
use std::fmt;

pub use fmi2::Status;

/// What an FMI function returned when it failed: a known status or an out-of-range code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CallStatus {
    Status(Status),
    Illegal(i32),
}

impl fmt::Display for CallStatus {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CallStatus::Status(s) => s.fmt(f),
            CallStatus::Illegal(raw) => write!(f, "the illegal status code {raw}"),
        }
    }
}

/// Every failure of the importer. Each message names the FMU (its file name) and, where
/// it applies, the archive entry, the FMI call with its arguments, the returned status,
/// the messages the FMU logged during that call, or the variable concerned.
#[derive(Debug, thiserror::Error)]
pub enum FmiError {
    /// The archive is unreadable or unsafe to unpack.
    #[error("{fmu}: {}{message}", entry.as_ref().map(|e| format!("entry \"{e}\": ")).unwrap_or_default())]
    Archive {
        fmu: String,
        entry: Option<String>,
        message: String,
    },
    /// `modelDescription.xml` cannot be read (the inner error names the file).
    #[error("{0}")]
    ModelDescription(#[from] model_description::Error),
    /// The FMU cannot be used by this importer (no Co-Simulation interface, no binary for
    /// this platform, wrong FMI version, invalid argument to a wrapper, …).
    #[error("{fmu}: {message}")]
    Unsupported { fmu: String, message: String },
    /// The shared library cannot be loaded.
    #[error("{fmu}: cannot load {library}: {message}")]
    Library {
        fmu: String,
        library: String,
        message: String,
    },
    /// The shared library lacks FMI functions.
    #[error("{fmu}: {library} does not export the required FMI 2.0 function{} {}", if symbols.len() == 1 { "" } else { "s" }, symbols.join(", "))]
    MissingSymbols {
        fmu: String,
        library: String,
        symbols: Vec<String>,
    },
    /// An FMI function returned a status that is a failure for that call.
    #[error(
        "{fmu}: {call} returned {status} (instance \"{instance}\"){}",
        format_log(messages)
    )]
    Call {
        fmu: String,
        instance: String,
        call: String,
        status: CallStatus,
        messages: Vec<LogMessage>,
    },
    /// An FMI 3.0 call failed: the message names the call, the status and what the FMU
    /// logged.
    #[error("{fmu}: {message}")]
    Call3 { fmu: String, message: String },
    /// `fmi2Instantiate` returned NULL.
    #[error(
        "{fmu}: fmi2Instantiate(instanceName=\"{instance}\") failed (returned NULL){}",
        format_log(messages)
    )]
    Instantiate {
        fmu: String,
        instance: String,
        messages: Vec<LogMessage>,
    },
    /// A value returned by the FMU is NaN or infinite.
    #[error("{fmu}: {call} returned the non-finite value {value} for variable \"{variable}\" (value reference {value_reference}){}", format_log(messages))]
    NonFinite {
        fmu: String,
        call: String,
        variable: String,
        value_reference: u32,
        value: f64,
        messages: Vec<LogMessage>,
    },
}

fn format_log(messages: &[LogMessage]) -> String {
    if messages.is_empty() {
        return String::new();
    }
    let mut text = String::from("; the FMU logged:");
    for m in messages {
        text.push_str("\n  ");
        text.push_str(&m.to_string());
    }
    text
}
