//! The FMI 3.0 C binding, written once for the exporter (`fmi-export`) and, as they grow
//! FMI 3.0, the importer and the misuse harness: the C types and status of
//! `fmi3PlatformTypes.h` and `fmi3FunctionTypes.h` ([`types`]) and every function name of
//! `fmi3Functions.h` with the typedefs of those a Co-Simulation FMU serves ([`functions`]).
//!
//! Unlike FMI 2.0 the logger is an ordinary C function (no variadic arguments), so no C
//! shim is needed. `fmi3Boolean` is C's `bool`; it crosses the ABI here as `u8` (same size
//! and passing convention), so a caller that passes a byte other than 0 or 1 cannot cause
//! undefined behaviour: any non-zero byte is true.

#![deny(unsafe_op_in_unsafe_fn)]

pub mod functions;
pub mod types;

pub use functions::FUNCTION_NAMES;
pub use types::*;

/// The value reference this project's FMI 3.0 descriptions give the independent variable
/// `time` (whose value is the instance's current time): the largest `int32`, far from the
/// small value references of the models and representable in tools that store them signed.
pub const TIME_VALUE_REFERENCE: u32 = i32::MAX as u32;
