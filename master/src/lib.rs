//! The `tbi` tool: scenarios, solvers, FMI import and the co-simulation master.
pub mod coupling;
pub mod simulate;
