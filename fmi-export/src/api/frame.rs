//! The frame every FMI function of [`crate::api`] runs in: resolving the component
//! pointer, catching panics, the state-table check, logging and reporting a refused or
//! failed call, and turning C arrays and strings into Rust slices and `&str`.
//!
//! The safety contract of these functions is the safety section of [`crate::api`].

use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::instance::{type_tag, Instance, INSTANCE_MAGIC};
use crate::model::FmuModel;
use crate::state::{Allowed, Function, State};
use crate::types::*;

/// The message of a panic payload.
pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string panic payload)".to_owned()
    }
}

/// Resolve a component pointer (see the safety section of [`crate::api`]).
pub(crate) unsafe fn instance<'a, M: FmuModel>(c: fmi2Component) -> Option<&'a mut Instance<M>> {
    if c.is_null() {
        return None;
    }
    let header = c as *const u64;
    // SAFETY: a non-NULL component points to at least an Instance header (caller).
    let (magic, tag) = unsafe { (header.read_unaligned(), header.add(1).read_unaligned()) };
    if magic != INSTANCE_MAGIC || tag != type_tag::<M>() {
        return None;
    }
    // SAFETY: header matches: a live Instance<M> created by `instantiate`.
    Some(unsafe { &mut *(c as *mut Instance<M>) })
}

impl<M: FmuModel> Instance<M> {
    /// Log `message` as an error of the function `name` and enter the `Error` state.
    fn fail(&mut self, name: &str, message: &str) {
        self.logger
            .log_status(Status::Error, &format!("{name}: {message}"));
        if self.frame.state != State::Fatal {
            self.frame.state = State::Error;
        }
    }
}

/// The common frame of every function taking a component (steps 1–5 of the docs of
/// [`crate::api`]).
/// Only the checks and the call of `body` are made for each function; what a refused or
/// failed call reports is in [`refused`], one copy per model, out of the way of the
/// functions' code.
pub(crate) unsafe fn call<M: FmuModel>(
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Instance<M>) -> Result<Status, String>,
) -> fmi2Status {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded contract of the caller.
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
            return Status::Error;
        };
        if !function.is_allowed_in(inst.frame.state) {
            return refused(inst, function, Refusal::State);
        }
        match catch_unwind(AssertUnwindSafe(|| body(&mut *inst))) {
            Ok(Ok(status)) if status < Status::Error => status,
            Ok(Ok(status)) => refused(inst, function, Refusal::Status(status)),
            Ok(Err(message)) => refused(inst, function, Refusal::Message(message)),
            Err(payload) => refused(inst, function, Refusal::Panic(payload)),
        }
    }));
    outcome.unwrap_or(Status::Error).raw()
}

/// Why [`call`] refuses a call.
enum Refusal {
    /// Not allowed in the instance's state.
    State,
    /// The model returned an error or fatal status.
    Status(Status),
    /// The model returned an error message.
    Message(String),
    /// The model panicked.
    Panic(Box<dyn std::any::Any + Send>),
}

/// Logs `why` as an error of `function`, enters the `Error` state and returns the error
/// status.
#[cold]
#[inline(never)]
fn refused<M: FmuModel>(inst: &mut Instance<M>, function: Function, why: Refusal) -> Status {
    // the message names the function the importer called: an FMI 3.0 function runs as the
    // FMI 2.0 function with the same states (crate::fmi3)
    let name = match inst.prefix {
        "fmi3" => crate::fmi3::name_of(function),
        _ => function.symbol(),
    };
    let message = match why {
        Refusal::State => format!(
            "illegal call in state {} (allowed in: {})",
            inst.frame.state,
            function.allowed()
        ),
        Refusal::Status(status) => format!("failed with {}", status.name()),
        Refusal::Message(message) => message,
        Refusal::Panic(payload) => format!("panic in the model: {}", panic_message(&*payload)),
    };
    inst.fail(name, &message);
    Status::Error
}

/// `&[T]` from a C array, refusing NULL with `n > 0` and impossible lengths.
pub(crate) unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL while its length is {n}"));
    }
    if n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} has an impossible length {n}"));
    }
    // SAFETY: non-NULL, length plausible; the caller guarantees n readable elements.
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// `&mut [T]` from a C array (see [`slice`]).
pub(crate) unsafe fn slice_mut<'a, T>(
    ptr: *mut T,
    n: usize,
    what: &str,
) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL while its length is {n}"));
    }
    if n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} has an impossible length {n}"));
    }
    // SAFETY: as in `slice`, writable.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// A `&str` from a NUL-terminated C string.
pub(crate) unsafe fn string<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, String> {
    if ptr.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: non-NULL and NUL-terminated (caller).
    unsafe { CStr::from_ptr(ptr) }
        .to_str()
        .map_err(|_| format!("{what} is not valid UTF-8"))
}

/// A function the FMU does not provide: logs `{name}: {why}` as an error of the instance
/// (which enters the `Error` state) and returns the error status; a NULL or foreign
/// instance gets the error status alone.
///
/// # Safety
/// `c` must be NULL or a pointer the importer got from this FMU (see [`crate::api`]).
pub unsafe fn unsupported<M: FmuModel>(c: fmi2Component, name: &str, why: &str) -> fmi2Status {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded contract of the caller.
        if let Some(inst) = unsafe { instance::<M>(c) } {
            inst.fail(name, why);
        }
    }));
    Status::Error.raw()
}
