//! The importer's `fmi2CallbackLogger` (feature `logger`).
//!
//! `fmi2CallbackLogger` is variadic (printf-style) and stable Rust cannot define a
//! C-variadic function. The C shim `csrc/logger_shim.c` (built by `build.rs`) defines it:
//! it expands the message with `vsnprintf` (messages above 1 MiB are cut) and calls a
//! non-variadic Rust function with the finished text. The FMU passes back the
//! `componentEnvironment` given at `fmi2Instantiate`; it points to a [`LogEnv`], whose
//! `forward` is [`LogEnv::new`]'s trampoline for one [`LogReceiver`] type and whose
//! `receiver` is that receiver.
//!
//! Who owns what: the importer boxes the receiver and the `LogEnv` and keeps both alive
//! until after `fmi2FreeInstance`, so the pointers the FMU keeps stay valid for as long as
//! it may call the logger. The trampoline never unwinds into C: a panic in a receiver is
//! caught and the message dropped.

use crate::types::{fmi2CallbackFunctions, fmi2CallbackLogger, fmi2Status, Status};
use std::ffi::{c_char, c_void, CStr};
use std::fmt;

/// One message an FMU logged.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogMessage {
    /// The instance name the FMU passed (empty for NULL).
    pub instance: String,
    /// The status the FMU gave the message; `None` for a code outside `fmi2Status`.
    pub status: Option<Status>,
    /// The log category (empty for NULL).
    pub category: String,
    /// The expanded message (empty for a NULL format).
    pub message: String,
    /// The FMI version of the FMU (2, or 3 for an FMI 3.0 FMU's `fmi3LogMessageCallback`):
    /// the status is shown with its name (`fmi2OK`, `fmi3OK`).
    pub fmi_version: u8,
}

impl LogMessage {
    /// Whether the status is `fmi2Error` or `fmi2Fatal`.
    pub fn is_error(&self) -> bool {
        matches!(self.status, Some(Status::Error | Status::Fatal))
    }
}

impl fmt::Display for LogMessage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let status = self.status.map_or("fmi2<illegal status>", Status::name);
        let status = match self.fmi_version {
            3 => status.replacen("fmi2", "fmi3", 1),
            _ => status.to_owned(),
        };
        write!(
            f,
            "[{}] {status} [{}] {}",
            self.instance, self.category, self.message
        )
    }
}

/// Where the messages of an instance go.
pub trait LogReceiver: Sync {
    /// Called once per message, on the thread that called into the FMU.
    fn receive(&self, message: LogMessage);
}

/// The non-variadic function the C shim forwards to.
pub type ForwardFn = unsafe extern "C" fn(
    receiver: *const c_void,
    instance_name: *const c_char,
    status: fmi2Status,
    category: *const c_char,
    message: *const c_char,
);

/// What `componentEnvironment` points at (layout shared with `fmi2_log_env` in C).
#[repr(C)]
#[derive(Debug)]
pub struct LogEnv {
    forward: Option<ForwardFn>,
    receiver: *const c_void,
}

// SAFETY: the receiver is `Sync` (bound on `LogEnv::new`) and only read through `&`.
unsafe impl Send for LogEnv {}
unsafe impl Sync for LogEnv {}

impl LogEnv {
    /// An environment delivering to `receiver`. The caller keeps `receiver` at its address
    /// (boxed) and alive for as long as any FMU may use this environment.
    pub fn new<R: LogReceiver>(receiver: &R) -> LogEnv {
        LogEnv {
            forward: Some(forward::<R>),
            receiver: receiver as *const R as *const c_void,
        }
    }

    /// An environment that drops every message.
    pub fn discard() -> LogEnv {
        LogEnv {
            forward: None,
            receiver: std::ptr::null(),
        }
    }

    /// The callback struct for `fmi2Instantiate`: the shim logger with this environment,
    /// `calloc`/`free` as memory functions, no `stepFinished`. The `LogEnv` must stay at
    /// its address (boxed) while an instance uses the struct.
    pub fn callbacks(&self) -> fmi2CallbackFunctions {
        fmi2CallbackFunctions {
            logger: Some(logger()),
            allocateMemory: Some(calloc),
            freeMemory: Some(free),
            stepFinished: None,
            componentEnvironment: self as *const LogEnv as *mut c_void,
        }
    }
}

/// The variadic C logger (for any `componentEnvironment` that points to a [`LogEnv`];
/// NULL drops the message).
pub fn logger() -> fmi2CallbackLogger {
    fmi2_shim_logger
}

unsafe extern "C" {
    /// The variadic `fmi2CallbackLogger` defined in `csrc/logger_shim.c`.
    fn fmi2_shim_logger(
        component_environment: *mut c_void,
        instance_name: *const c_char,
        status: fmi2Status,
        category: *const c_char,
        message: *const c_char,
        ...
    );
    fn calloc(count: usize, size: usize) -> *mut c_void;
    fn free(pointer: *mut c_void);
}

fn text(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: the FMU passes NUL-terminated strings (fmi2String), valid for the
        // duration of the callback; the shim passes its own NUL-terminated buffer.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

/// Receives every expanded message from the shim.
///
/// # Safety
/// `receiver` is the `R` of a live [`LogEnv`] made by [`LogEnv::new::<R>`]; the strings
/// are NUL-terminated or NULL.
unsafe extern "C" fn forward<R: LogReceiver>(
    receiver: *const c_void,
    instance_name: *const c_char,
    status: fmi2Status,
    category: *const c_char,
    message: *const c_char,
) {
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        if receiver.is_null() {
            return;
        }
        // SAFETY: see the function's safety section.
        let receiver = unsafe { &*(receiver as *const R) };
        receiver.receive(LogMessage {
            instance: text(instance_name),
            status: Status::from_raw(status),
            category: text(category),
            message: text(message),
            fmi_version: 2,
        });
    }));
}

/// A logger that keeps every message, for tests and the misuse harness: its
/// [`callbacks`](Self::callbacks) go to `fmi2Instantiate`, [`take`](Self::take) reads
/// what arrived. It must outlive every instance created with its callbacks.
pub struct LogCapture {
    // Drop order: the environment (which points into `records`) before the records.
    env: Box<LogEnv>,
    records: Box<Records>,
}

#[derive(Default)]
struct Records(std::sync::Mutex<Vec<LogMessage>>);

impl Records {
    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<LogMessage>> {
        // A poisoned lock only means a panic while pushing; the data is still usable.
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

impl LogReceiver for Records {
    fn receive(&self, message: LogMessage) {
        self.lock().push(message);
    }
}

impl Default for LogCapture {
    fn default() -> Self {
        Self::new()
    }
}

impl LogCapture {
    pub fn new() -> LogCapture {
        let records = Box::new(Records::default());
        let env = Box::new(LogEnv::new(&*records));
        LogCapture { env, records }
    }

    /// The callback struct for `fmi2Instantiate` (see [`LogEnv::callbacks`]).
    pub fn callbacks(&self) -> fmi2CallbackFunctions {
        self.env.callbacks()
    }

    /// A copy of the messages so far.
    pub fn records(&self) -> Vec<LogMessage> {
        self.records.lock().clone()
    }

    /// Remove and return the messages so far.
    pub fn take(&self) -> Vec<LogMessage> {
        std::mem::take(&mut *self.records.lock())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::{c_int, CString};
    use std::sync::Mutex;

    #[derive(Default)]
    struct Collect(Mutex<Vec<LogMessage>>);

    impl LogReceiver for Collect {
        fn receive(&self, message: LogMessage) {
            self.0.lock().unwrap().push(message);
        }
    }

    fn log(env: *mut c_void, status: fmi2Status, format: &CString, arg: &CString) {
        unsafe {
            fmi2_shim_logger(
                env,
                c"inst".as_ptr(),
                status,
                c"logStatusError".as_ptr(),
                format.as_ptr(),
                arg.as_ptr(),
            )
        }
    }

    #[test]
    fn shim_expands_printf_formats_and_forwards() {
        let sink = Collect::default();
        let env = Box::new(LogEnv::new(&sink));
        let cb = env.callbacks();
        let format = CString::new("t=%g h=%.3f n=%d s=%s").unwrap();
        let word = CString::new("word").unwrap();
        unsafe {
            (cb.logger.unwrap())(
                cb.componentEnvironment,
                c"inst".as_ptr(),
                3,
                c"logStatusError".as_ptr(),
                format.as_ptr(),
                0.5f64,
                0.25f64,
                42 as c_int,
                word.as_ptr(),
            );
        }
        let messages = sink.0.into_inner().unwrap();
        assert_eq!(
            messages,
            [LogMessage {
                instance: "inst".into(),
                status: Some(Status::Error),
                category: "logStatusError".into(),
                message: "t=0.5 h=0.250 n=42 s=word".into(),
                fmi_version: 2,
            }]
        );
        assert!(messages[0].is_error());
        assert_eq!(
            messages[0].to_string(),
            "[inst] fmi2Error [logStatusError] t=0.5 h=0.250 n=42 s=word"
        );
        // an FMI 3.0 FMU's message names its status as FMI 3.0 does
        let three = LogMessage {
            fmi_version: 3,
            ..messages[0].clone()
        };
        assert_eq!(
            three.to_string(),
            "[inst] fmi3Error [logStatusError] t=0.5 h=0.250 n=42 s=word"
        );
    }

    #[test]
    fn long_messages_are_expanded_completely_and_captured() {
        let capture = LogCapture::new();
        let long = "x".repeat(5000);
        let arg = CString::new(long.clone()).unwrap();
        let format = CString::new("<%s>").unwrap();
        log(capture.callbacks().componentEnvironment, 0, &format, &arg);
        assert_eq!(capture.records()[0].message, format!("<{long}>"));
        assert_eq!(capture.take().len(), 1);
        assert!(capture.take().is_empty());
    }

    #[test]
    fn null_environment_null_message_and_illegal_status_are_harmless() {
        let format = CString::new("%s").unwrap();
        let arg = CString::new("lost").unwrap();
        log(std::ptr::null_mut(), 0, &format, &arg);
        let discard = Box::new(LogEnv::discard());
        log(&*discard as *const LogEnv as *mut c_void, 0, &format, &arg);
        let sink = Collect::default();
        let env = Box::new(LogEnv::new(&sink));
        unsafe {
            fmi2_shim_logger(
                &*env as *const LogEnv as *mut c_void,
                std::ptr::null(),
                7,
                std::ptr::null(),
                std::ptr::null(),
            );
        }
        let messages = sink.0.into_inner().unwrap();
        assert_eq!(messages.len(), 1);
        assert_eq!(messages[0].status, None);
        assert_eq!(messages[0].message, "");
        assert_eq!(messages[0].instance, "");
    }
}
