//! The logger handed to FMU instances.
//!
//! `fmi2CallbackLogger` is variadic; the C shim `logger_shim.c` (built by `build.rs`)
//! defines `tbi_fmi2_logger`, expands the message with `vsnprintf` and calls
//! [`forward`] with the finished text. The FMU gets a pointer to a [`LogEnv`] as its
//! `componentEnvironment`; the `LogEnv` holds `forward` and a pointer to the instance's
//! [`LogSink`]. Both are boxed by the instance and live until after `fmi2FreeInstance`,
//! so the pointers the FMU keeps stay valid for as long as it may call the logger.
//!
//! The sink keeps the messages of the FMI call in progress (they are attached to the
//! error if the call fails) and optionally echoes every message to standard error.
//! [`forward`] never unwinds into C: a panic inside it is caught and dropped.

use super::error::Status;
use super::ffi::Fmi2Status;
use std::ffi::{c_char, c_int, c_void, CStr};
use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// At most this many messages are kept per FMI call (later ones are counted, not kept).
const MAX_MESSAGES_PER_CALL: usize = 1000;

/// One message an FMU logged.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogMessage {
    pub instance: String,
    /// The status the FMU gave the message; `None` for a code outside `fmi2Status`.
    pub status: Option<Status>,
    pub category: String,
    pub message: String,
}

impl fmt::Display for LogMessage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let status = self.status.map_or("fmi2<illegal status>", Status::name);
        write!(
            f,
            "[{}] {status} [{}] {}",
            self.instance, self.category, self.message
        )
    }
}

/// Collects the messages of one instance.
#[derive(Debug)]
pub struct LogSink {
    current: Mutex<CallLog>,
    echo: AtomicBool,
}

#[derive(Debug, Default)]
struct CallLog {
    messages: Vec<LogMessage>,
    dropped: usize,
}

impl LogSink {
    pub fn new(echo: bool) -> Self {
        Self {
            current: Mutex::new(CallLog::default()),
            echo: AtomicBool::new(echo),
        }
    }

    /// Whether messages are also printed to standard error as they arrive.
    pub fn set_echo(&self, echo: bool) {
        self.echo.store(echo, Ordering::Relaxed);
    }

    /// Start collecting the messages of a new call (drops those of the previous one).
    pub fn begin_call(&self) {
        let mut log = self.lock();
        log.messages.clear();
        log.dropped = 0;
    }

    /// The messages logged since [`LogSink::begin_call`] (a final line says how many
    /// were not kept, if any).
    pub fn take_call_messages(&self) -> Vec<LogMessage> {
        let mut log = self.lock();
        let mut messages = std::mem::take(&mut log.messages);
        if log.dropped > 0 {
            messages.push(LogMessage {
                instance: messages
                    .last()
                    .map(|m| m.instance.clone())
                    .unwrap_or_default(),
                status: None,
                category: "tbi".into(),
                message: format!("{} further messages were not kept", log.dropped),
            });
        }
        log.dropped = 0;
        messages
    }

    fn push(&self, message: LogMessage) {
        if self.echo.load(Ordering::Relaxed) {
            eprintln!("{message}");
        }
        let mut log = self.lock();
        if log.messages.len() < MAX_MESSAGES_PER_CALL {
            log.messages.push(message);
        } else {
            log.dropped += 1;
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, CallLog> {
        // A poisoned lock only means a panic while pushing; the data is still usable.
        self.current.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// The non-variadic callback the C shim forwards to.
pub type ForwardFn = unsafe extern "C" fn(
    sink: *mut c_void,
    instance_name: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
);

/// What `componentEnvironment` points at (layout shared with `tbi_fmi2_log_env` in C).
#[repr(C)]
pub struct LogEnv {
    pub forward: Option<ForwardFn>,
    pub sink: *const LogSink,
}

unsafe extern "C" {
    /// The variadic `fmi2CallbackLogger` defined in `logger_shim.c`.
    pub fn tbi_fmi2_logger(
        component_environment: *mut c_void,
        instance_name: *const c_char,
        status: c_int,
        category: *const c_char,
        message: *const c_char,
        ...
    );
}

fn text(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: the FMU passes NUL-terminated strings (FMI 2.0 fmi2String), valid for
        // the duration of the callback; the shim passes its own NUL-terminated buffer.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

/// Receives every expanded message from the shim.
///
/// # Safety
/// `sink` is the `LogSink` pointer of a live [`LogEnv`] (the instance guarantees this);
/// the strings are NUL-terminated or NULL.
pub unsafe extern "C" fn forward(
    sink: *mut c_void,
    instance_name: *const c_char,
    status: Fmi2Status,
    category: *const c_char,
    message: *const c_char,
) {
    let _ = std::panic::catch_unwind(|| {
        if sink.is_null() {
            return;
        }
        // SAFETY: see the function's safety section.
        let sink = unsafe { &*(sink as *const LogSink) };
        sink.push(LogMessage {
            instance: text(instance_name),
            status: Status::from_raw(status),
            category: text(category),
            message: text(message),
        });
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CString;

    #[test]
    fn shim_expands_printf_formats_and_forwards() {
        let sink = LogSink::new(false);
        let env = LogEnv {
            forward: Some(forward),
            sink: &sink,
        };
        let name = CString::new("inst").unwrap();
        let category = CString::new("logStatusError").unwrap();
        let format = CString::new("t=%g h=%.3f n=%d s=%s").unwrap();
        let word = CString::new("word").unwrap();
        sink.begin_call();
        unsafe {
            tbi_fmi2_logger(
                &env as *const LogEnv as *mut c_void,
                name.as_ptr(),
                3,
                category.as_ptr(),
                format.as_ptr(),
                0.5f64,
                0.25f64,
                42 as c_int,
                word.as_ptr(),
            );
        }
        let messages = sink.take_call_messages();
        assert_eq!(
            messages,
            [LogMessage {
                instance: "inst".into(),
                status: Some(Status::Error),
                category: "logStatusError".into(),
                message: "t=0.5 h=0.250 n=42 s=word".into(),
            }]
        );
        assert_eq!(
            messages[0].to_string(),
            "[inst] fmi2Error [logStatusError] t=0.5 h=0.250 n=42 s=word"
        );
    }

    #[test]
    fn long_messages_are_expanded_completely() {
        let sink = LogSink::new(false);
        let env = LogEnv {
            forward: Some(forward),
            sink: &sink,
        };
        let long = "x".repeat(5000);
        let arg = CString::new(long.clone()).unwrap();
        let format = CString::new("<%s>").unwrap();
        unsafe {
            tbi_fmi2_logger(
                &env as *const LogEnv as *mut c_void,
                std::ptr::null(),
                0,
                std::ptr::null(),
                format.as_ptr(),
                arg.as_ptr(),
            );
        }
        let messages = sink.take_call_messages();
        assert_eq!(messages[0].message, format!("<{long}>"));
        assert_eq!(messages[0].instance, "");
    }

    #[test]
    fn null_environment_and_null_message_are_harmless() {
        let format = CString::new("%s").unwrap();
        unsafe {
            tbi_fmi2_logger(
                std::ptr::null_mut(),
                std::ptr::null(),
                0,
                std::ptr::null(),
                format.as_ptr(),
                std::ptr::null::<c_char>(),
            );
        }
        let sink = LogSink::new(false);
        let env = LogEnv {
            forward: Some(forward),
            sink: &sink,
        };
        unsafe {
            tbi_fmi2_logger(
                &env as *const LogEnv as *mut c_void,
                std::ptr::null(),
                7,
                std::ptr::null(),
                std::ptr::null(),
            );
        }
        let messages = sink.take_call_messages();
        assert_eq!(messages.len(), 1);
        assert_eq!(messages[0].status, None);
        assert_eq!(messages[0].message, "");
    }

    #[test]
    fn messages_per_call_are_bounded() {
        let sink = LogSink::new(false);
        for i in 0..MAX_MESSAGES_PER_CALL + 5 {
            sink.push(LogMessage {
                instance: "i".into(),
                status: Some(Status::Ok),
                category: "c".into(),
                message: i.to_string(),
            });
        }
        let messages = sink.take_call_messages();
        assert_eq!(messages.len(), MAX_MESSAGES_PER_CALL + 1);
        assert_eq!(
            messages.last().unwrap().message,
            "5 further messages were not kept"
        );
        sink.begin_call();
        assert!(sink.take_call_messages().is_empty());
    }
}
