//! FMI 2.0 Co-Simulation export plumbing.
pub mod model;
pub use model::{FmuModel, Log, Phase, StepOutcome};
