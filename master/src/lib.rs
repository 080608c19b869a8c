//! The `tbi` tool: scenarios, solvers and the co-simulation master (FMI import is the
//! `fmi-import` crate).
pub mod bench;
pub mod cosim;
pub mod coupling;
pub mod export;
pub mod model;
pub mod modes;
pub mod package;
pub mod plots;
pub mod progress;
pub mod run;
pub mod scenario;
pub mod simulate;
pub mod summary;
pub mod suspension;
pub mod sweep;
