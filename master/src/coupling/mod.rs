//! Co-simulation coupling algorithms.
pub mod system;
pub use system::{Connection, CouplingError, Participant, StepStatus, System};
