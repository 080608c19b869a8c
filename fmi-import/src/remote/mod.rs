//! FMUs in worker processes: an FMU that crashes, aborts, exits or hangs ends its worker,
//! not the master. [`RemoteInstance`] (the master's side) implements
//! [`crate::participant::FmiCalls`] as an in-process instance does, so the coupling runs
//! isolated FMUs unchanged, rollback included (the FMU state stays in the worker);
//! [`serve`] is the worker's side, run by a program's hidden command (`tbi fmu-worker`).
//! The messages are in [`protocol`].

mod client;
pub mod protocol;
mod worker;

pub use client::{round_trips, RemoteInstance, WorkerOptions};
pub use worker::serve;
