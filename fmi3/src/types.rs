//! The FMI 3.0 C types, spelled as in `fmi3PlatformTypes.h` / `fmi3FunctionTypes.h`.
//!
//! Enumerations that cross the C boundary (`fmi3Status`, `fmi3DependencyKind`,
//! `fmi3IntervalQualifier`) are plain `c_int`s with named constants, as for FMI 2.0: a C
//! caller can pass any integer.

#![allow(non_camel_case_types, non_upper_case_globals)]

use std::ffi::{c_char, c_int, c_void};

/// Opaque pointer to an FMU instance (`void*`).
pub type fmi3Instance = *mut c_void;
/// Opaque pointer handed back to the importer's callbacks (`void*`).
pub type fmi3InstanceEnvironment = *mut c_void;
/// Opaque pointer to a saved FMU state (`void*`).
pub type fmi3FMUState = *mut c_void;
/// Value reference (`uint32_t`).
pub type fmi3ValueReference = u32;
pub type fmi3Float32 = f32;
pub type fmi3Float64 = f64;
pub type fmi3Int8 = i8;
pub type fmi3UInt8 = u8;
pub type fmi3Int16 = i16;
pub type fmi3UInt16 = u16;
pub type fmi3Int32 = i32;
pub type fmi3UInt32 = u32;
pub type fmi3Int64 = i64;
pub type fmi3UInt64 = u64;
/// C `bool`, taken as a byte (see the crate docs): zero is false, anything else true.
pub type fmi3Boolean = u8;
pub type fmi3Char = c_char;
/// `const char*`.
pub type fmi3String = *const c_char;
/// `uint8_t` (a byte of binary data or of a serialized FMU state).
pub type fmi3Byte = u8;
/// `const fmi3Byte*`.
pub type fmi3Binary = *const fmi3Byte;
/// C `bool`, as [`fmi3Boolean`].
pub type fmi3Clock = u8;

pub const fmi3True: fmi3Boolean = 1;
pub const fmi3False: fmi3Boolean = 0;

/// `fmi3Status` as passed over the C ABI.
pub type fmi3Status = c_int;
pub const fmi3OK: fmi3Status = 0;
pub const fmi3Warning: fmi3Status = 1;
pub const fmi3Discard: fmi3Status = 2;
pub const fmi3Error: fmi3Status = 3;
pub const fmi3Fatal: fmi3Status = 4;

/// `fmi3DependencyKind` as passed over the C ABI.
pub type fmi3DependencyKind = c_int;
pub const fmi3Independent: fmi3DependencyKind = 0;
pub const fmi3Constant: fmi3DependencyKind = 1;
pub const fmi3Fixed: fmi3DependencyKind = 2;
pub const fmi3Tunable: fmi3DependencyKind = 3;
pub const fmi3Discrete: fmi3DependencyKind = 4;
pub const fmi3Dependent: fmi3DependencyKind = 5;

/// `fmi3IntervalQualifier` as passed over the C ABI.
pub type fmi3IntervalQualifier = c_int;
pub const fmi3IntervalNotYetKnown: fmi3IntervalQualifier = 0;
pub const fmi3IntervalUnchanged: fmi3IntervalQualifier = 1;
pub const fmi3IntervalChanged: fmi3IntervalQualifier = 2;

/// `fmi3LogMessageCallback`: `void (*)(fmi3InstanceEnvironment, fmi3Status, fmi3String
/// category, fmi3String message)`. `None` is NULL.
pub type fmi3LogMessageCallback = Option<
    unsafe extern "C" fn(
        instance_environment: fmi3InstanceEnvironment,
        status: fmi3Status,
        category: fmi3String,
        message: fmi3String,
    ),
>;

/// `fmi3ClockUpdateCallback`.
pub type fmi3ClockUpdateCallback =
    Option<unsafe extern "C" fn(instance_environment: fmi3InstanceEnvironment)>;

/// `fmi3IntermediateUpdateCallback`.
pub type fmi3IntermediateUpdateCallback = Option<
    unsafe extern "C" fn(
        instance_environment: fmi3InstanceEnvironment,
        intermediate_update_time: fmi3Float64,
        intermediate_variable_set_requested: fmi3Boolean,
        intermediate_variable_get_allowed: fmi3Boolean,
        intermediate_step_finished: fmi3Boolean,
        can_return_early: fmi3Boolean,
        early_return_requested: *mut fmi3Boolean,
        early_return_time: *mut fmi3Float64,
    ),
>;

/// `fmi3LockPreemptionCallback` / `fmi3UnlockPreemptionCallback`.
pub type fmi3PreemptionCallback = Option<unsafe extern "C" fn()>;

/// The version string `fmi3GetVersion` returns.
pub const fmi3Version: &std::ffi::CStr = c"3.0";

/// An opaque `void*`, for the typedefs.
pub type Opaque = *mut c_void;
