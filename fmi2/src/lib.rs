//! The FMI 2.0 Co-Simulation C binding, written once for the exporter (`fmi-export`), the
//! importer (`fmi-import`) and the misuse harness.
//!
//! | module | what |
//! |---|---|
//! | [`types`] (re-exported here) | the `fmi2…` C types and constants, [`Status`] |
//! | [`functions`] | the 34 functions listed once: [`Function`], the `fmi2…TYPE` typedefs, the pointer table [`Functions`] (loaded with feature `load`) |
//! | [`uri`] | `fmuResourceLocation` ↔ path |
//! | `logger` (feature `logger`) | the variadic `fmi2CallbackLogger` as a C shim forwarding text to a Rust [`LogReceiver`](logger::LogReceiver) |

#![deny(unsafe_op_in_unsafe_fn)]

pub mod functions;
#[cfg(feature = "logger")]
pub mod logger;
pub mod types;
pub mod uri;

pub use functions::{Function, Functions};
pub use types::*;
