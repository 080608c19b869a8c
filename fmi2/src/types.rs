//! The FMI 2.0 C types, spelled as in `fmi2TypesPlatform.h` / `fmi2FunctionTypes.h`.
//!
//! Enumerations that cross the C boundary (`fmi2Status`, `fmi2Type`, `fmi2StatusKind`)
//! are plain `c_int`s with named constants: a C caller can pass any integer, and turning
//! an unexpected one into a Rust `enum` would be undefined behaviour. Inside the crate the
//! typed [`Status`] is used and converted at the boundary.

#![allow(non_camel_case_types, non_upper_case_globals)]

use std::ffi::{c_char, c_int, c_uint, c_void};

/// Opaque pointer to an FMU instance (`void*`).
pub type fmi2Component = *mut c_void;
/// Opaque pointer handed back to the importer's callbacks (`void*`).
pub type fmi2ComponentEnvironment = *mut c_void;
/// Opaque pointer to a saved FMU state (`void*`).
pub type fmi2FMUstate = *mut c_void;
/// Value reference (`unsigned int`).
pub type fmi2ValueReference = c_uint;
/// `double`.
pub type fmi2Real = f64;
/// `int`.
pub type fmi2Integer = c_int;
/// `int`; zero is false, anything else true.
pub type fmi2Boolean = c_int;
/// `char`.
pub type fmi2Char = c_char;
/// `const char*`.
pub type fmi2String = *const c_char;
/// `char` (byte of a serialized FMU state).
pub type fmi2Byte = c_char;

/// `fmi2True`.
pub const fmi2True: fmi2Boolean = 1;
/// `fmi2False`.
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2Status` as passed over the C ABI.
pub type fmi2Status = c_int;
pub const fmi2OK: fmi2Status = 0;
pub const fmi2Warning: fmi2Status = 1;
pub const fmi2Discard: fmi2Status = 2;
pub const fmi2Error: fmi2Status = 3;
pub const fmi2Fatal: fmi2Status = 4;
pub const fmi2Pending: fmi2Status = 5;

/// `fmi2Type` as passed over the C ABI.
pub type fmi2Type = c_int;
pub const fmi2ModelExchange: fmi2Type = 0;
pub const fmi2CoSimulation: fmi2Type = 1;

/// `fmi2StatusKind` as passed over the C ABI.
pub type fmi2StatusKind = c_int;
pub const fmi2DoStepStatus: fmi2StatusKind = 0;
pub const fmi2PendingStatus: fmi2StatusKind = 1;
pub const fmi2LastSuccessfulTime: fmi2StatusKind = 2;
pub const fmi2Terminated: fmi2StatusKind = 3;

/// `fmi2CallbackLogger`: `void (*)(fmi2ComponentEnvironment, fmi2String instanceName,
/// fmi2Status, fmi2String category, fmi2String message, ...)`. The message is a printf
/// format; this crate always passes `"%s"` and the text as the single variadic argument.
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    fmi2ComponentEnvironment,
    fmi2String,
    fmi2Status,
    fmi2String,
    fmi2String,
    ...
);
/// `fmi2CallbackAllocateMemory`: `void* (*)(size_t nobj, size_t size)`.
pub type fmi2CallbackAllocateMemory = unsafe extern "C" fn(usize, usize) -> *mut c_void;
/// `fmi2CallbackFreeMemory`: `void (*)(void*)`.
pub type fmi2CallbackFreeMemory = unsafe extern "C" fn(*mut c_void);
/// `fmi2StepFinished`: `void (*)(fmi2ComponentEnvironment, fmi2Status)`.
pub type fmi2StepFinished = unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status);

/// `fmi2CallbackFunctions`. Every function pointer may be NULL on the C side, hence
/// `Option` (same layout as a nullable pointer).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
#[allow(non_snake_case)]
pub struct fmi2CallbackFunctions {
    pub logger: Option<fmi2CallbackLogger>,
    pub allocateMemory: Option<fmi2CallbackAllocateMemory>,
    pub freeMemory: Option<fmi2CallbackFreeMemory>,
    pub stepFinished: Option<fmi2StepFinished>,
    pub componentEnvironment: fmi2ComponentEnvironment,
}

/// `fmi2Status` as a Rust enum, ordered by severity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Status {
    Ok,
    Warning,
    Discard,
    Error,
    Fatal,
    Pending,
}

impl Status {
    /// The C value.
    pub const fn raw(self) -> fmi2Status {
        match self {
            Status::Ok => fmi2OK,
            Status::Warning => fmi2Warning,
            Status::Discard => fmi2Discard,
            Status::Error => fmi2Error,
            Status::Fatal => fmi2Fatal,
            Status::Pending => fmi2Pending,
        }
    }

    /// Decode a C value; `None` for integers outside the enumeration.
    pub const fn from_raw(raw: fmi2Status) -> Option<Status> {
        match raw {
            fmi2OK => Some(Status::Ok),
            fmi2Warning => Some(Status::Warning),
            fmi2Discard => Some(Status::Discard),
            fmi2Error => Some(Status::Error),
            fmi2Fatal => Some(Status::Fatal),
            fmi2Pending => Some(Status::Pending),
            _ => None,
        }
    }

    /// The name used in the standard (`"fmi2OK"` …).
    pub const fn name(self) -> &'static str {
        match self {
            Status::Ok => "fmi2OK",
            Status::Warning => "fmi2Warning",
            Status::Discard => "fmi2Discard",
            Status::Error => "fmi2Error",
            Status::Fatal => "fmi2Fatal",
            Status::Pending => "fmi2Pending",
        }
    }
}

impl std::fmt::Display for Status {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// `fmi2GetTypesPlatform()` result.
pub const TYPES_PLATFORM: &std::ffi::CStr = c"default";
/// `fmi2GetVersion()` result.
pub const VERSION: &std::ffi::CStr = c"2.0";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_round_trips_and_rejects_unknown_values() {
        for s in [
            Status::Ok,
            Status::Warning,
            Status::Discard,
            Status::Error,
            Status::Fatal,
            Status::Pending,
        ] {
            assert_eq!(Status::from_raw(s.raw()), Some(s));
        }
        assert_eq!(Status::from_raw(6), None);
        assert_eq!(Status::from_raw(-1), None);
        assert!(Status::Discard > Status::Warning && Status::Error > Status::Discard);
    }

    #[test]
    fn callback_struct_has_the_c_layout() {
        let p = std::mem::size_of::<*const c_void>();
        assert_eq!(std::mem::size_of::<fmi2CallbackFunctions>(), 5 * p);
        assert_eq!(std::mem::size_of::<Option<fmi2CallbackLogger>>(), p);
    }
}
