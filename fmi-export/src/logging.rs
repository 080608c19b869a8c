//! Logging through the importer's `fmi2CallbackLogger`, with FMI log categories.
//!
//! # Categories
//!
//! The plumbing logs with the categories the standard suggests (list them in
//! `<LogCategories>` of `modelDescription.xml`; [`LOG_CATEGORIES`] has names and
//! descriptions, a model adds its own through [`crate::FmuModel::LOG_CATEGORIES`]):
//!
//! | category | status | what |
//! |---|---|---|
//! | `logEvents` | fmi2OK | life-cycle events: instantiated, initialization, terminate, reset, FMU-state operations |
//! | `logStatusWarning` | fmi2Warning | e.g. unknown categories in `fmi2SetDebugLogging` |
//! | `logStatusDiscard` | fmi2Discard | why `fmi2DoStep` was discarded, unsupported status kinds |
//! | `logStatusError` | fmi2Error | every error: illegal call sequence, bad arguments, model errors, panics |
//! | `logStatusFatal` | fmi2Fatal | reserved (the plumbing never returns fmi2Fatal) |
//! | `logAll` | — | pseudo category for `fmi2SetDebugLogging`: all categories |
//!
//! # Filtering
//!
//! Messages with status fmi2Warning or worse are always delivered: the importer needs the
//! reason for a non-OK return even when debug logging is off. fmi2OK messages (events and
//! the model's own informational messages) are delivered only when debug logging is on
//! for their category:
//!
//! * `fmi2Instantiate(…, loggingOn)` switches all categories on or off;
//! * `fmi2SetDebugLogging(c, on, 0, NULL)` switches all categories on or off;
//! * `fmi2SetDebugLogging(c, on, n, cats)` switches the listed categories (`logAll` means
//!   all of them); names that are neither the plumbing's nor the model's are applied all
//!   the same and answered with fmi2Warning naming the known categories.
//!
//! The message is passed as the single variadic argument of the format `"%s"`, so `%`
//! in messages is never interpreted. Interior NUL bytes are written as `\0`.

use std::collections::BTreeMap;
use std::ffi::{c_char, c_int, c_void, CString};

use crate::types::{fmi2CallbackLogger, fmi2ComponentEnvironment, Status};

pub const LOG_EVENTS: &str = "logEvents";
pub const LOG_STATUS_WARNING: &str = "logStatusWarning";
pub const LOG_STATUS_DISCARD: &str = "logStatusDiscard";
pub const LOG_STATUS_ERROR: &str = "logStatusError";
pub const LOG_STATUS_FATAL: &str = "logStatusFatal";
pub const LOG_ALL: &str = "logAll";

/// The plumbing's log categories with descriptions, for `<LogCategories>`.
pub const LOG_CATEGORIES: &[(&str, &str)] = &[
    (LOG_EVENTS, "Life-cycle events and FMU-state operations"),
    (LOG_STATUS_WARNING, "Messages returned with fmi2Warning"),
    (LOG_STATUS_DISCARD, "Messages returned with fmi2Discard"),
    (LOG_STATUS_ERROR, "Messages returned with fmi2Error"),
    (LOG_STATUS_FATAL, "Messages returned with fmi2Fatal"),
    (LOG_ALL, "All categories"),
];

/// The status a message of `category` is reported with.
pub fn status_of_category(category: &str) -> Status {
    match category {
        LOG_STATUS_WARNING => Status::Warning,
        LOG_STATUS_DISCARD => Status::Discard,
        LOG_STATUS_ERROR => Status::Error,
        LOG_STATUS_FATAL => Status::Fatal,
        _ => Status::Ok,
    }
}

/// The category the plumbing logs a message of `status` with.
pub fn category_of_status(status: Status) -> &'static str {
    match status {
        Status::Ok | Status::Pending => LOG_EVENTS,
        Status::Warning => LOG_STATUS_WARNING,
        Status::Discard => LOG_STATUS_DISCARD,
        Status::Error => LOG_STATUS_ERROR,
        Status::Fatal => LOG_STATUS_FATAL,
    }
}

/// Which categories deliver fmi2OK messages (see the module documentation).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogFilter {
    default_on: bool,
    overrides: BTreeMap<String, bool>,
}

impl LogFilter {
    /// All categories on or off.
    pub fn new(logging_on: bool) -> Self {
        LogFilter {
            default_on: logging_on,
            overrides: BTreeMap::new(),
        }
    }

    /// Apply `fmi2SetDebugLogging`. Returns the categories that are not in `known`
    /// (they are applied nonetheless).
    pub fn set<'a>(
        &mut self,
        logging_on: bool,
        categories: impl IntoIterator<Item = &'a str>,
        known: &[&str],
    ) -> Vec<String> {
        let mut unknown = Vec::new();
        let mut any = false;
        for category in categories {
            any = true;
            if category == LOG_ALL {
                *self = LogFilter::new(logging_on);
                continue;
            }
            if !known.contains(&category) {
                unknown.push(category.to_owned());
            }
            self.overrides.insert(category.to_owned(), logging_on);
        }
        if !any {
            *self = LogFilter::new(logging_on);
        }
        unknown
    }

    /// Whether a message of `status` and `category` is delivered.
    pub fn delivers(&self, status: Status, category: &str) -> bool {
        (status >= Status::Warning && status != Status::Pending)
            || self
                .overrides
                .get(category)
                .copied()
                .unwrap_or(self.default_on)
    }
}

/// The importer's logger: FMI 2.0's variadic `fmi2CallbackLogger` or FMI 3.0's
/// `fmi3LogMessageCallback`.
#[derive(Debug, Clone, Copy)]
enum Callback {
    Fmi2(fmi2CallbackLogger),
    /// Non-NULL (checked by `fmi3InstantiateCoSimulation`).
    Fmi3(unsafe extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char)),
}

/// The importer's logger callback plus what is needed to call it.
///
/// Invariant: the callback was non-NULL when the instance was created and stays callable
/// for the instance's lifetime (both standards require the importer to keep it valid until
/// the instance is freed).
#[derive(Debug, Clone)]
pub struct Logger {
    callback: Callback,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    pub filter: LogFilter,
}

impl Logger {
    pub fn new(
        callback: fmi2CallbackLogger,
        environment: fmi2ComponentEnvironment,
        instance_name: &str,
        logging_on: bool,
    ) -> Self {
        Logger {
            callback: Callback::Fmi2(callback),
            environment,
            instance_name: to_cstring(instance_name),
            filter: LogFilter::new(logging_on),
        }
    }

    /// The logger of an FMI 3.0 instance (`fmi3LogMessageCallback`, which takes no
    /// instance name: the importer knows it from its environment pointer).
    pub fn new_fmi3(
        callback: unsafe extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char),
        environment: *mut c_void,
        instance_name: &str,
        logging_on: bool,
    ) -> Self {
        Logger {
            callback: Callback::Fmi3(callback),
            environment,
            instance_name: to_cstring(instance_name),
            filter: LogFilter::new(logging_on),
        }
    }

    /// Deliver `message` if the filter lets it through.
    pub fn log(&self, status: Status, category: &str, message: &str) {
        if self.filter.delivers(status, category) {
            self.emit(status, category, message);
        }
    }

    /// Deliver `message` with the category that belongs to `status`.
    pub fn log_status(&self, status: Status, message: &str) {
        self.log(status, category_of_status(status), message);
    }

    fn emit(&self, status: Status, category: &str, message: &str) {
        let category = to_cstring(category);
        let message = to_cstring(message);
        match self.callback {
            Callback::Fmi2(callback) => {
                let format: *const c_char = c"%s".as_ptr();
                // SAFETY: `callback` is the importer's non-NULL logger (type invariant);
                // all strings are NUL-terminated and outlive the call; "%s" consumes
                // exactly the one `const char*` variadic argument passed.
                unsafe {
                    callback(
                        self.environment,
                        self.instance_name.as_ptr(),
                        status.raw(),
                        category.as_ptr(),
                        format,
                        message.as_ptr(),
                    );
                }
            }
            // SAFETY: as above; the FMI 3.0 logger takes the message as it is.
            Callback::Fmi3(callback) => unsafe {
                callback(
                    self.environment,
                    status.raw(),
                    category.as_ptr(),
                    message.as_ptr(),
                )
            },
        }
    }
}

impl crate::model::Log for Logger {
    fn log(&self, category: &str, message: &str) {
        Logger::log(self, status_of_category(category), category, message);
    }
}

fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).expect("interior NUL bytes were replaced")
}

#[cfg(test)]
mod tests {
    use super::*;

    const KNOWN: &[&str] = &[LOG_EVENTS, LOG_STATUS_ERROR];

    #[test]
    fn warnings_and_worse_are_always_delivered() {
        let f = LogFilter::new(false);
        assert!(f.delivers(Status::Error, LOG_STATUS_ERROR));
        assert!(f.delivers(Status::Discard, LOG_STATUS_DISCARD));
        assert!(f.delivers(Status::Warning, "anything"));
        assert!(f.delivers(Status::Fatal, LOG_STATUS_FATAL));
        assert!(!f.delivers(Status::Ok, LOG_EVENTS));
        assert!(LogFilter::new(true).delivers(Status::Ok, LOG_EVENTS));
    }

    #[test]
    fn set_debug_logging_without_categories_switches_all() {
        let mut f = LogFilter::new(false);
        assert!(f.set(true, [], KNOWN).is_empty());
        assert!(f.delivers(Status::Ok, LOG_EVENTS));
        assert!(f.delivers(Status::Ok, "modelCategory"));
        f.set(false, [], KNOWN);
        assert!(!f.delivers(Status::Ok, LOG_EVENTS));
    }

    #[test]
    fn set_debug_logging_with_categories_switches_only_those() {
        let mut f = LogFilter::new(false);
        assert!(f.set(true, [LOG_EVENTS], KNOWN).is_empty());
        assert!(f.delivers(Status::Ok, LOG_EVENTS));
        assert!(!f.delivers(Status::Ok, "other"));

        let mut g = LogFilter::new(true);
        g.set(false, [LOG_EVENTS], KNOWN);
        assert!(!g.delivers(Status::Ok, LOG_EVENTS));
        assert!(g.delivers(Status::Ok, "other"));
    }

    #[test]
    fn log_all_and_unknown_categories() {
        let mut f = LogFilter::new(false);
        assert!(f.set(true, [LOG_ALL], KNOWN).is_empty());
        assert!(f.delivers(Status::Ok, "whatever"));
        let unknown = f.set(false, ["logTypo", LOG_EVENTS], KNOWN);
        assert_eq!(unknown, vec!["logTypo".to_owned()]);
        assert!(!f.delivers(Status::Ok, "logTypo"));
        assert!(!f.delivers(Status::Ok, LOG_EVENTS));
        assert!(f.delivers(Status::Ok, "whatever"));
    }

    #[test]
    fn categories_map_to_statuses_and_back() {
        for s in [
            Status::Warning,
            Status::Discard,
            Status::Error,
            Status::Fatal,
        ] {
            assert_eq!(status_of_category(category_of_status(s)), s);
        }
        assert_eq!(status_of_category(LOG_EVENTS), Status::Ok);
        assert_eq!(status_of_category("modelInfo"), Status::Ok);
    }

    #[test]
    fn interior_nul_is_escaped() {
        assert_eq!(to_cstring("a\0b").as_bytes(), b"a\\0b");
    }
}
