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

/// A failure inside a participant or the algorithm, with enough context to act on. Each
/// variant's message names the participant, the call, the time or the key concerned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CouplingError {
    /// A configuration value out of its range.
    #[error("{key} = {value}: {rule}")]
    Config {
        key: String,
        value: String,
        rule: String,
    },
    /// A configuration keyword that is not one of the accepted ones.
    #[error("{key} = {value:?} is not one of {expected}")]
    Keyword {
        key: &'static str,
        value: String,
        expected: String,
    },
    /// Connections that do not fit the participants, or a scheme that cannot drive them.
    #[error("{0}")]
    Wiring(String),
    /// A participant's call failed.
    #[error("{participant}: {call} failed: {message}")]
    Call {
        participant: String,
        call: String,
        message: String,
    },
    /// A participant returned an output that is not finite.
    #[error("{participant}: output vr {vr} is not finite ({value})")]
    NonFinite {
        participant: String,
        vr: u32,
        value: f64,
    },
    /// A participant discarded a step that cannot be retried.
    #[error("{0}")]
    Discarded(String),
    /// A step that did not converge (or a step size that is not valid) under the configured
    /// policy.
    #[error("{0}")]
    Step(String),
    /// What a participant's own implementation reports.
    #[error("{0}")]
    Participant(String),
}

impl CouplingError {
    /// A participant's own failure, in its words.
    pub fn new(message: impl Into<String>) -> Self {
        Self::Participant(message.into())
    }

    /// The participant's call `call` failed with `e`.
    pub fn call(participant: &str, call: impl Into<String>, e: impl fmt::Display) -> Self {
        Self::Call {
            participant: participant.to_owned(),
            call: call.into(),
            message: e.to_string(),
        }
    }
}

/// One simulator in the loop. Value references are the participant's own.
pub trait Participant {
    fn name(&self) -> &str;
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError>;
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError>;
    /// Whether [`Participant::get_real`] itself refuses a NaN or infinite value (an error
    /// naming the variable), so that the exchange need not look at the values again.
    /// Default: no, the exchange checks them.
    fn get_real_refuses_non_finite(&self) -> bool {
        false
    }
    /// Advance from `t` to `t + h`.
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepStatus, CouplingError>;
    /// Start [`Participant::do_step`]: `Some(status)` when the step is done now (the
    /// default), `None` when it runs on while the master starts the others (a participant in
    /// a process of its own), to be ended by [`Participant::finish_step`] before any other
    /// call. The schemes that step participants on the same inputs start them all first.
    fn start_step(&mut self, t: f64, h: f64) -> Result<Option<StepStatus>, CouplingError> {
        self.do_step(t, h).map(Some)
    }
    /// End a step that [`Participant::start_step`] left running.
    fn finish_step(&mut self) -> Result<StepStatus, CouplingError> {
        Err(CouplingError::new(format!(
            "{}: finish_step without a running step",
            self.name()
        )))
    }
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
    /// The name of variable `vr`, for messages. Default: none known.
    fn variable_name(&self, _vr: u32) -> Option<String> {
        None
    }
    /// Leave initialisation mode (FMI `fmi2ExitInitializationMode`), after the initial
    /// inputs are set. Default: nothing to do.
    fn exit_initialization(&mut self) -> Result<(), CouplingError> {
        Ok(())
    }
    /// Read Integer or Boolean (as 0/1) variables, for [`DiscreteConnection`]s. Default: the
    /// participant has none.
    fn get_discrete(
        &mut self,
        kind: Discrete,
        _vrs: &[u32],
        _values: &mut [i32],
    ) -> Result<(), CouplingError> {
        Err(CouplingError::Wiring(format!(
            "{}: has no {kind} variables",
            self.name()
        )))
    }
    /// Write Integer or Boolean (0/1) inputs. Default: the participant has none.
    fn set_discrete(
        &mut self,
        kind: Discrete,
        _vrs: &[u32],
        _values: &[i32],
    ) -> Result<(), CouplingError> {
        Err(CouplingError::Wiring(format!(
            "{}: has no {kind} variables",
            self.name()
        )))
    }
}

/// The FMI type of a [`DiscreteConnection`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Discrete {
    Integer,
    Boolean,
}

impl fmt::Display for Discrete {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Discrete::Integer => "Integer",
            Discrete::Boolean => "Boolean",
        })
    }
}

/// `to.to_vr := from.from_vr` for an Integer or Boolean variable. The explicit schemes pass
/// these values once per step with the same timing as their Real connections (Jacobi: all
/// from `t`; Gauss–Seidel: from `t + h` when the source stepped earlier in the sweep); they
/// are never iterated, so the implicit scheme refuses a system that has any.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DiscreteConnection {
    pub kind: Discrete,
    pub from: usize,
    pub from_vr: u32,
    pub to: usize,
    pub to_vr: u32,
    /// `component.variable → component.variable`, for messages.
    pub name: String,
}

impl DiscreteConnection {
    /// Pass the source's current value to the input.
    pub fn pass(&self, sys: &mut System) -> Result<(), CouplingError> {
        let mut v = [0];
        sys.participants[self.from].get_discrete(self.kind, &[self.from_vr], &mut v)?;
        sys.participants[self.to].set_discrete(self.kind, &[self.to_vr], &v)
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
    /// Integer and Boolean connections (explicit schemes only).
    pub discrete: Vec<DiscreteConnection>,
}

impl System {
    /// A system of Real connections only.
    pub fn new(participants: Vec<Box<dyn Participant>>, connections: Vec<Connection>) -> Self {
        Self {
            participants,
            connections,
            discrete: Vec::new(),
        }
    }

    /// Pass every discrete connection into participant `to` (all when `None`).
    pub fn pass_discrete(&mut self, to: Option<usize>) -> Result<(), CouplingError> {
        let connections = std::mem::take(&mut self.discrete);
        let result = connections
            .iter()
            .filter(|c| to.is_none_or(|p| c.to == p))
            .try_for_each(|c| c.pass(self));
        self.discrete = connections;
        result
    }
}
