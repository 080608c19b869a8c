//! Comparing return codes and log records with what a check expects.

use super::Outcome;
use crate::harness::LogMessage;
use fmi2::types::*;

pub(super) fn status_name(s: fmi2Status) -> String {
    Status::from_raw(s).map_or_else(|| format!("invalid status {s}"), |s| s.name().to_owned())
}

pub(super) fn expect(got: fmi2Status, want: &[Status], what: &str) -> Outcome {
    if want.iter().any(|w| w.raw() == got) {
        Ok(())
    } else {
        let want: Vec<&str> = want.iter().map(|w| w.name()).collect();
        Err(format!(
            "{what} returned {} (expected {})",
            status_name(got),
            want.join(" or ")
        ))
    }
}

pub(super) fn expect_ok(got: fmi2Status, what: &str) -> Outcome {
    expect(got, &[Status::Ok], what)
}

/// An error (or worse) message must have been logged.
pub(super) fn expect_logged_error(records: &[LogMessage], what: &str) -> Outcome {
    match records.iter().find(|r| r.is_error()) {
        Some(r) if !r.message.trim().is_empty() => Ok(()),
        Some(_) => Err(format!("{what}: an empty error message was logged")),
        None => Err(format!(
            "{what}: no fmi2Error message was logged (got {} other messages)",
            records.len()
        )),
    }
}

pub(super) fn describe(records: &[LogMessage]) -> String {
    records
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(" | ")
}
