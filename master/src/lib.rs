//! The `tbi` application: scenarios, the two solvers, the FMUs and the co-simulation master.
//!
//! Rooms, each a folder:
//!
//! * [`scenario`]: the scenario file (TOML) read and checked into a typed [`Scenario`];
//! * [`model`]: the bridge, track and train built from a scenario ([`model::build`]);
//! * [`solve`]: a model run monolithically or through its FMUs ([`run_scenario`]);
//! * [`fmus`]: the scenario's FMUs exported and packaged, with the SSP system that couples them;
//! * [`design`]: design checks over many runs (the EN 1991-2 HSLM check, wind curves);
//! * [`output`]: summaries, histories, plots, HTML reports and the output folder;
//! * [`cli`]: one file per command, from its arguments to the library calls.
//!
//! The coupling algorithms are the `tbi-coupling` crate, SSP systems are read and wired by
//! `tbi-ssp`, and the FMI import is `fmi-import`.

pub mod cli;
pub mod design;
pub mod fmus;
pub mod interrupt;
pub mod model;
pub mod output;
pub mod scenario;
pub mod solve;
pub mod text;

pub use model::{build, Limits, Model};
pub use scenario::{load, Scenario, DEFAULT_SCENARIO};
