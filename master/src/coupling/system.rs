//! The coupled system as the coupling algorithms see it: participants (FMU instances or
//! in-process test models) and the scalar connections between them.

use std::fmt;

/// Outcome of one participant's `do_step`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepStatus {
    Ok,
    /// The participant could not complete the step (FMI `fmi2Discard`).
    Discard,
}

/// A failure inside a participant or the algorithm, with enough context to act on.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingError {
    pub message: String,
}

impl CouplingError {
    pub fn new(message: impl Into<String>) -> Self {
        Self {
            message: message.into(),
        }
    }
}

impl fmt::Display for CouplingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CouplingError {}

/// One simulator in the loop. Value references are the participant's own.
pub trait Participant {
    fn name(&self) -> &str;
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError>;
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError>;
    /// Advance from `t` to `t + h`.
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepStatus, CouplingError>;
    /// Save the complete state into the participant's single rollback slot (overwriting).
    fn save_state(&mut self) -> Result<(), CouplingError>;
    /// Restore the state saved last by [`Participant::save_state`].
    fn restore_state(&mut self) -> Result<(), CouplingError>;
    /// Unit of output `vr` (e.g. `"N"`), if declared. Feedback values of one source with the
    /// same unit are measured together by the convergence test (see
    /// [`WeightedRms`](super::convergence::WeightedRms)). Default: none declared.
    fn unit(&self, _vr: u32) -> Option<&str> {
        None
    }
}

/// `to.to_vr := from.from_vr` (indices into [`System::participants`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Connection {
    pub from: usize,
    pub from_vr: u32,
    pub to: usize,
    pub to_vr: u32,
}

/// Participants in their sweep order (Gauss–Seidel order) and the connections.
pub struct System {
    pub participants: Vec<Box<dyn Participant>>,
    pub connections: Vec<Connection>,
}
