//! The `tbi` tool: scenarios, solvers, FMI import and the co-simulation master.
pub mod bench;
pub mod coupling;
pub mod cosim;
pub mod export;
pub mod model;
pub mod modes;
pub mod plots;
pub mod run;
pub mod scenario;
pub mod suspension;
pub mod sweep;
pub mod fmi;
pub mod package;
pub mod simulate;
