//! FMI 2.0 and FMI 3.0 Co-Simulation importer: load any FMU, call it safely, run it alone,
//! and check an exporter's C ABI. FMI 3.0 FMUs are [`fmi3::Fmu3`]s (the same unpacking and
//! description checks, their library under `binaries/x86_64-linux/`); [`AnyFmu`] loads an
//! FMU of either version, and both are called through [`FmiCalls`]. What follows describes
//! the FMI 2.0 path.
//!
//! [`Fmu::load`] takes an `.fmu` file through these steps, each failing with an
//! [`FmiError`] that names the FMU (its file name) and what went wrong:
//!
//! 1. **Unpack** ([`archive`]): extract into a private temporary directory, refusing
//!    absolute paths, `..` components, backslashes, duplicate entries, symbolic links
//!    and archives that inflate beyond [`UnpackLimits`]. The directory is deleted when
//!    the [`Fmu`] is dropped.
//! 2. **Describe**: read `modelDescription.xml` with the `model-description` crate; the
//!    FMU must offer `<CoSimulation>`.
//! 3. **Load** ([`library`]): `dlopen` `binaries/linux64/<modelIdentifier>.so` with
//!    `RTLD_NOW | RTLD_LOCAL` and resolve all 34 FMI 2.0 Co-Simulation functions up
//!    front, reporting every missing symbol at once; check `fmi2GetVersion` and
//!    `fmi2GetTypesPlatform`.
//!
//! [`Fmu::instantiate`] then creates an [`Instance`], passing
//!
//! - `fmuResourceLocation` as the `file:` URI of the unpacked `resources` directory,
//!   percent-encoded like Python's `pathlib` (see [`fmi2::uri::file_uri`]);
//! - the binding's logger shim ([`fmi2::logger`]), which expands the variadic
//!   `fmi2CallbackLogger` with `vsnprintf` and forwards the text to the instance's
//!   [`logger::LogSink`], where the messages of the call in progress are kept to be
//!   attached to its error.
//!
//! # Safety invariants
//!
//! - Instances hold an `Arc<Fmu>`: the library is never unloaded while an instance
//!   exists, and within [`Fmu`] the function table drops before the library, the library
//!   before its directory.
//! - The callback struct, the logger environment and the log sink are boxed and owned by
//!   the instance, so they stay at fixed addresses until after `fmi2FreeInstance`, which
//!   runs exactly once, on drop — and not at all after `fmi2Fatal`, as the standard asks.
//! - Every call goes through `&mut self`, so one instance is never called concurrently.
//! - No Rust panic can unwind into the FMU: the logger's Rust side catches panics.
//! - Values crossing the boundary are checked: slice lengths before the call, status codes
//!   (including out-of-range ones) after it, and `fmi2GetReal` results for NaN and
//!   infinity, which are errors naming the variable.

//!
//! Beside the importer: [`simulate`], the single-FMU runner behind `tbi simulate` (the
//! defaults and CSV of `fmpy simulate`), and [`harness`], a C-ABI conformance and misuse
//! harness for FMU shared objects, built on the same [`Library`] loader.

mod any;
pub mod archive;
mod error;
pub mod fmi3;
pub mod harness;
mod instance;
pub mod library;
pub mod logger;
pub mod names;
mod participant;
pub mod remote;
pub mod simulate;

pub use any::AnyFmu;
pub use archive::UnpackLimits;
pub use error::{CallStatus, FmiError, Status};
pub use fmi2::first_non_finite;
pub use fmi2::uri::file_uri;
pub use instance::{Fmu, FmuState, Instance, InstantiateOptions, StatusKind, StepResult, PLATFORM};
pub use library::{Library, LoadError};
pub use logger::LogMessage;
pub use participant::{FmiCalls, FmuParticipant, LocalInstance};
