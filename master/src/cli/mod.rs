//! The commands, one file each: the command line's arguments turned into library calls and
//! what is printed. No command calls another's `main`; `workers` holds the FMU worker
//! options `cosim` and `simulate` share.

pub mod bench;
pub mod cosim;
pub mod export;
pub mod modes;
pub mod run;
pub mod simulate;
pub mod sweep;
pub mod validate;
pub mod workers;
