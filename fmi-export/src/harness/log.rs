//! Capturing an FMU's log messages from Rust.
//!
//! The FMU calls the importer's logger as a C-variadic function, which stable Rust cannot
//! define. `csrc/logger_shim.c` (compiled by build.rs with the `harness` feature) is that
//! function: it formats the message with `vsnprintf` and calls [`sink`] with the plain
//! string. `componentEnvironment` points to a [`LogEnv`] whose `context` is the record
//! list of one [`LogCapture`].

use std::ffi::{c_char, c_int, c_void, CStr};
use std::sync::{Arc, Mutex, PoisonError};

use crate::types::{fmi2CallbackFunctions, fmi2CallbackLogger, Status};

unsafe extern "C" {
    /// `void fmi_export_harness_logger(void *env, const char *instance, int status,
    /// const char *category, const char *format, ...)` from `csrc/logger_shim.c`.
    fn fmi_export_harness_logger(
        env: *mut c_void,
        instance_name: *const c_char,
        status: c_int,
        category: *const c_char,
        format: *const c_char,
        ...
    );
    fn calloc(n: usize, size: usize) -> *mut c_void;
    fn free(p: *mut c_void);
}

/// One message the FMU passed to the logger.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogRecord {
    pub instance_name: String,
    /// The raw `fmi2Status` (kept raw so a bogus value is visible, see [`Self::status`]).
    pub status: c_int,
    pub category: String,
    pub message: String,
}

impl LogRecord {
    /// The status, if it is a valid `fmi2Status`.
    pub fn status(&self) -> Option<Status> {
        Status::from_raw(self.status)
    }

    /// Whether the status is fmi2Error or fmi2Fatal.
    pub fn is_error(&self) -> bool {
        matches!(self.status(), Some(Status::Error | Status::Fatal))
    }
}

impl std::fmt::Display for LogRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let status = self.status().map_or("(invalid status)", Status::name);
        write!(
            f,
            "[{}] {} {}: {}",
            self.instance_name, status, self.category, self.message
        )
    }
}

type Records = Mutex<Vec<LogRecord>>;

/// What `componentEnvironment` points to (layout shared with the C shim).
#[repr(C)]
pub struct LogEnv {
    sink: unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char),
    context: *mut c_void,
}

/// Called by the C shim with the formatted message.
///
/// # Safety
/// `context` is the `Records` of a live [`LogCapture`]; the strings are NULL or
/// NUL-terminated.
unsafe extern "C" fn sink(
    context: *mut c_void,
    instance_name: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    let text = |p: *const c_char| {
        if p.is_null() {
            String::from("(NULL)")
        } else {
            // SAFETY: NUL-terminated (contract).
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let record = LogRecord {
            instance_name: text(instance_name),
            status,
            category: text(category),
            message: text(message),
        };
        // SAFETY: context is the Records of a live LogCapture (contract).
        let records = unsafe { &*(context as *const Records) };
        records
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(record);
    }));
}

/// A logger for `fmi2CallbackFunctions` that records every message.
///
/// The capture must outlive every instance created with its [`callbacks`](Self::callbacks).
pub struct LogCapture {
    env: Box<LogEnv>,
    records: Arc<Records>,
}

impl Default for LogCapture {
    fn default() -> Self {
        Self::new()
    }
}

impl LogCapture {
    pub fn new() -> LogCapture {
        let records: Arc<Records> = Arc::new(Mutex::new(Vec::new()));
        let env = Box::new(LogEnv {
            sink,
            context: Arc::as_ptr(&records) as *mut c_void,
        });
        LogCapture { env, records }
    }

    /// The variadic C logger (usable with any `componentEnvironment` pointing to a
    /// [`LogEnv`]).
    pub fn logger() -> fmi2CallbackLogger {
        fmi_export_harness_logger
    }

    /// Callback functions: this capture's logger, `calloc`/`free` as memory functions,
    /// no `stepFinished`.
    pub fn callbacks(&self) -> fmi2CallbackFunctions {
        fmi2CallbackFunctions {
            logger: Some(Self::logger()),
            allocateMemory: Some(calloc),
            freeMemory: Some(free),
            stepFinished: None,
            componentEnvironment: &*self.env as *const LogEnv as *mut c_void,
        }
    }

    /// A copy of the messages so far.
    pub fn records(&self) -> Vec<LogRecord> {
        self.records
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .clone()
    }

    /// Remove and return the messages so far.
    pub fn take(&self) -> Vec<LogRecord> {
        std::mem::take(&mut *self.records.lock().unwrap_or_else(PoisonError::into_inner))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::types::{fmi2Error, fmi2OK};

    #[test]
    fn shim_formats_and_forwards_messages() {
        let capture = LogCapture::new();
        let cb = capture.callbacks();
        let logger = cb.logger.unwrap();
        let long = "x".repeat(5000);
        let long_c = std::ffi::CString::new(long.clone()).unwrap();
        unsafe {
            logger(
                cb.componentEnvironment,
                c"inst".as_ptr(),
                fmi2Error,
                c"logStatusError".as_ptr(),
                c"%s = %d%%".as_ptr(),
                c"answer".as_ptr(),
                42 as c_int,
            );
            logger(
                cb.componentEnvironment,
                c"inst".as_ptr(),
                fmi2OK,
                c"logEvents".as_ptr(),
                c"%s".as_ptr(),
                long_c.as_ptr(),
            );
            // NULL environment: dropped, no crash.
            logger(
                std::ptr::null_mut(),
                c"inst".as_ptr(),
                fmi2OK,
                c"logEvents".as_ptr(),
                c"%s".as_ptr(),
                c"lost".as_ptr(),
            );
        }
        let records = capture.take();
        assert_eq!(records.len(), 2);
        assert_eq!(records[0].message, "answer = 42%");
        assert_eq!(records[0].category, "logStatusError");
        assert!(records[0].is_error());
        assert_eq!(records[1].message, long, "heap path of the shim");
        assert!(capture.records().is_empty());
    }
}
