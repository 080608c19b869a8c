//! A model run to its history and summary: monolithically (eq. (14) in one system) or
//! through its FMUs with the coupling library.

pub mod compare;
pub mod cosim;
pub mod run;

pub use run::{layout, run_maxima, run_monolithic, run_scenario};
pub mod system;
