//! The per-instance receiver of an FMU's log messages.
//!
//! The variadic `fmi2CallbackLogger` itself is the binding's C shim
//! ([`fmi2::logger`]); the instance boxes a [`LogSink`] and a [`LogEnv`] pointing to it
//! and keeps both until after `fmi2FreeInstance`, so the pointers the FMU keeps stay
//! valid for as long as it may call the logger.
//!
//! The sink keeps the messages of the FMI call in progress (they are attached to the
//! error if the call fails) and optionally echoes every message to standard error.

pub use fmi2::logger::{LogEnv, LogMessage, LogReceiver};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// At most this many messages are kept per FMI call (later ones are counted, not kept).
const MAX_MESSAGES_PER_CALL: usize = 1000;

/// Collects the messages of one instance.
#[derive(Debug)]
pub struct LogSink {
    current: Mutex<CallLog>,
    echo: AtomicBool,
    /// Messages may be held (set with each message kept or dropped, cleared with the
    /// log): a call that starts with none held leaves the lock alone, as almost every
    /// call of a run does.
    held: AtomicBool,
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
            held: AtomicBool::new(false),
        }
    }

    /// Whether messages are also printed to standard error as they arrive.
    pub fn set_echo(&self, echo: bool) {
        self.echo.store(echo, Ordering::Relaxed);
    }

    /// Start collecting the messages of a new call (drops those of the previous one).
    pub fn begin_call(&self) {
        if !self.held.load(Ordering::Acquire) {
            return;
        }
        let mut log = self.lock();
        log.messages.clear();
        log.dropped = 0;
        self.held.store(false, Ordering::Release);
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
                fmi_version: messages.last().map_or(2, |m| m.fmi_version),
            });
        }
        log.dropped = 0;
        self.held.store(false, Ordering::Release);
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
        self.held.store(true, Ordering::Release);
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, CallLog> {
        // A poisoned lock only means a panic while pushing; the data is still usable.
        self.current.lock().unwrap_or_else(|p| p.into_inner())
    }
}

impl LogReceiver for LogSink {
    fn receive(&self, message: LogMessage) {
        self.push(message);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmi2::Status;

    #[test]
    fn messages_per_call_are_bounded() {
        let sink = LogSink::new(false);
        for i in 0..MAX_MESSAGES_PER_CALL + 5 {
            sink.receive(LogMessage {
                instance: "i".into(),
                status: Some(Status::Ok),
                category: "c".into(),
                message: i.to_string(),
                fmi_version: 2,
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
