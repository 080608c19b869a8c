//! The FMI 2.0 Co-Simulation state machine as bit masks per function.
//!
//! Every instance is in exactly one [`State`]; every FMI function has a [`StateMask`] of
//! the states in which it may be called ([`Function::allowed`]). The table follows the
//! Co-Simulation state table of the standard (FMI 2.0.4, section 4.2.4) and the masks of
//! modelica/Reference-FMUs, with these decisions:
//!
//! * `fmi2Terminate` is also allowed in `StepCanceled` (the standard's state chart has a
//!   `fmi2Terminate` transition out of it).
//! * `fmi2FreeInstance` is also allowed in `Fatal` so the memory can always be released.
//! * `StepInProgress` and `StepCanceled` are never entered: the plumbing does not run
//!   asynchronously (`canRunAsynchronuously = false`), so `fmi2DoStep` never returns
//!   `fmi2Pending`. They are kept so the table reads like the standard's.
//! * `Fatal` is never entered either: a Rust panic is contained per instance (it cannot
//!   corrupt other instances), so it is reported as `fmi2Error` and the instance moves to
//!   `Error`, from which `fmi2Reset` or `fmi2SetFMUstate` can recover.
//!
//! Any call returning `fmi2Error` (an illegal call sequence included) moves the instance
//! to `Error` — the standard: "the simulation cannot be continued with this FMU instance".
//! In `Error` only the functions whose mask contains `ERROR` are accepted: getters (values
//! for debugging only), FMU-state functions (so a saved state can be restored),
//! `fmi2Reset`, `fmi2SetDebugLogging` and `fmi2FreeInstance`.
//!
//! | function | allowed in |
//! |---|---|
//! | GetTypesPlatform, GetVersion | always (no instance) |
//! | Instantiate | StartAndEnd |
//! | SetDebugLogging | Instantiated, InitializationMode, StepComplete, StepInProgress, StepFailed, StepCanceled, Terminated, Error |
//! | FreeInstance | Instantiated, InitializationMode, StepComplete, StepFailed, StepCanceled, Terminated, Error, Fatal |
//! | SetupExperiment, EnterInitializationMode | Instantiated |
//! | ExitInitializationMode | InitializationMode |
//! | Terminate | StepComplete, StepFailed, StepCanceled |
//! | Reset | Instantiated, InitializationMode, StepComplete, StepFailed, StepCanceled, Terminated, Error |
//! | GetReal/Integer/Boolean/String | InitializationMode, StepComplete, StepFailed, StepCanceled, Terminated, Error |
//! | SetReal/Integer/Boolean/String | Instantiated, InitializationMode, StepComplete |
//! | Get/Set/FreeFMUstate, SerializedFMUstateSize, (De)SerializeFMUstate | Instantiated, InitializationMode, StepComplete, StepFailed, StepCanceled, Terminated, Error |
//! | GetDirectionalDerivative | InitializationMode, StepComplete, StepFailed, StepCanceled, Terminated, Error |
//! | SetRealInputDerivatives | Instantiated, InitializationMode, StepComplete |
//! | GetRealOutputDerivatives | StepComplete, StepFailed, StepCanceled, Terminated, Error |
//! | DoStep | StepComplete |
//! | CancelStep | StepInProgress |
//! | GetStatus, Get{Real,Integer,Boolean,String}Status | StepComplete, StepInProgress, StepFailed, StepCanceled, Terminated |
//!
//! Functions the FMU does not provide (`GetDirectionalDerivative`, `SetRealInputDerivatives`,
//! `GetRealOutputDerivatives`, `CancelStep`) first pass the state check and then return
//! `fmi2Error` with a "not supported" message.

use std::fmt;

/// A state of the Co-Simulation state machine (one bit each).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u16)]
pub enum State {
    StartAndEnd = 1 << 0,
    Instantiated = 1 << 1,
    InitializationMode = 1 << 2,
    StepComplete = 1 << 3,
    StepInProgress = 1 << 4,
    StepFailed = 1 << 5,
    StepCanceled = 1 << 6,
    Terminated = 1 << 7,
    Error = 1 << 8,
    Fatal = 1 << 9,
}

impl State {
    /// All states, in the order of the standard's table.
    pub const ALL: [State; 10] = [
        State::StartAndEnd,
        State::Instantiated,
        State::InitializationMode,
        State::StepComplete,
        State::StepInProgress,
        State::StepFailed,
        State::StepCanceled,
        State::Terminated,
        State::Error,
        State::Fatal,
    ];

    /// The state's bit.
    pub const fn bit(self) -> u16 {
        self as u16
    }

    /// Decode a single bit (used when a serialized FMU state is read back).
    pub fn from_bit(bit: u16) -> Option<State> {
        State::ALL.into_iter().find(|s| s.bit() == bit)
    }

    /// The state's name as used in log messages.
    pub const fn name(self) -> &'static str {
        match self {
            State::StartAndEnd => "StartAndEnd",
            State::Instantiated => "Instantiated",
            State::InitializationMode => "InitializationMode",
            State::StepComplete => "StepComplete",
            State::StepInProgress => "StepInProgress",
            State::StepFailed => "StepFailed",
            State::StepCanceled => "StepCanceled",
            State::Terminated => "Terminated",
            State::Error => "Error",
            State::Fatal => "Fatal",
        }
    }
}

impl fmt::Display for State {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A set of [`State`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct StateMask(pub u16);

impl StateMask {
    pub const START_AND_END: StateMask = StateMask(State::StartAndEnd.bit());
    pub const INSTANTIATED: StateMask = StateMask(State::Instantiated.bit());
    pub const INITIALIZATION_MODE: StateMask = StateMask(State::InitializationMode.bit());
    pub const STEP_COMPLETE: StateMask = StateMask(State::StepComplete.bit());
    pub const STEP_IN_PROGRESS: StateMask = StateMask(State::StepInProgress.bit());
    pub const STEP_FAILED: StateMask = StateMask(State::StepFailed.bit());
    pub const STEP_CANCELED: StateMask = StateMask(State::StepCanceled.bit());
    pub const TERMINATED: StateMask = StateMask(State::Terminated.bit());
    pub const ERROR: StateMask = StateMask(State::Error.bit());
    pub const FATAL: StateMask = StateMask(State::Fatal.bit());
    /// Every state.
    pub const ALL: StateMask = StateMask((1 << 10) - 1);

    /// Union of two masks (usable in constants).
    pub const fn or(self, other: StateMask) -> StateMask {
        StateMask(self.0 | other.0)
    }

    /// Whether `state` is in the set.
    pub const fn contains(self, state: State) -> bool {
        self.0 & state.bit() != 0
    }

    /// The states in the set, in table order.
    pub fn states(self) -> impl Iterator<Item = State> {
        State::ALL.into_iter().filter(move |s| self.contains(*s))
    }
}

impl fmt::Display for StateMask {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for s in self.states() {
            if !first {
                f.write_str(", ")?;
            }
            first = false;
            f.write_str(s.name())?;
        }
        if first {
            f.write_str("(none)")?;
        }
        Ok(())
    }
}

use StateMask as M;

const SET_DEBUG_LOGGING: M = M::INSTANTIATED
    .or(M::INITIALIZATION_MODE)
    .or(M::STEP_COMPLETE)
    .or(M::STEP_IN_PROGRESS)
    .or(M::STEP_FAILED)
    .or(M::STEP_CANCELED)
    .or(M::TERMINATED)
    .or(M::ERROR);
/// Reset, FMU-state functions (and FreeInstance without `FATAL`).
const ANY_INSTANCE_NOT_IN_PROGRESS: M = M::INSTANTIATED
    .or(M::INITIALIZATION_MODE)
    .or(M::STEP_COMPLETE)
    .or(M::STEP_FAILED)
    .or(M::STEP_CANCELED)
    .or(M::TERMINATED)
    .or(M::ERROR);
const GETTERS: M = M::INITIALIZATION_MODE
    .or(M::STEP_COMPLETE)
    .or(M::STEP_FAILED)
    .or(M::STEP_CANCELED)
    .or(M::TERMINATED)
    .or(M::ERROR);
const SETTERS: M = M::INSTANTIATED
    .or(M::INITIALIZATION_MODE)
    .or(M::STEP_COMPLETE);
const STATUS: M = M::STEP_COMPLETE
    .or(M::STEP_IN_PROGRESS)
    .or(M::STEP_FAILED)
    .or(M::STEP_CANCELED)
    .or(M::TERMINATED);

pub use fmi2::Function;

/// The states in which each FMI function may be called (the table in the module docs).
pub trait Allowed {
    /// The states in which the function may be called.
    fn allowed(&self) -> StateMask;
    /// Whether the function may be called in `state`.
    fn is_allowed_in(&self, state: State) -> bool;
}

impl Allowed for Function {
    /// The states in which the function may be called.
    fn allowed(&self) -> StateMask {
        match self {
            Function::GetTypesPlatform | Function::GetVersion => M::ALL,
            Function::SetDebugLogging => SET_DEBUG_LOGGING,
            Function::Instantiate => M::START_AND_END,
            Function::FreeInstance => ANY_INSTANCE_NOT_IN_PROGRESS.or(M::FATAL),
            Function::SetupExperiment | Function::EnterInitializationMode => M::INSTANTIATED,
            Function::ExitInitializationMode => M::INITIALIZATION_MODE,
            Function::Terminate => M::STEP_COMPLETE.or(M::STEP_FAILED).or(M::STEP_CANCELED),
            Function::Reset
            | Function::GetFmuState
            | Function::SetFmuState
            | Function::FreeFmuState
            | Function::SerializedFmuStateSize
            | Function::SerializeFmuState
            | Function::DeSerializeFmuState => ANY_INSTANCE_NOT_IN_PROGRESS,
            Function::GetReal
            | Function::GetInteger
            | Function::GetBoolean
            | Function::GetString
            | Function::GetDirectionalDerivative => GETTERS,
            Function::SetReal
            | Function::SetInteger
            | Function::SetBoolean
            | Function::SetString
            | Function::SetRealInputDerivatives => SETTERS,
            Function::GetRealOutputDerivatives => M::STEP_COMPLETE
                .or(M::STEP_FAILED)
                .or(M::STEP_CANCELED)
                .or(M::TERMINATED)
                .or(M::ERROR),
            Function::DoStep => M::STEP_COMPLETE,
            Function::CancelStep => M::STEP_IN_PROGRESS,
            Function::GetStatus
            | Function::GetRealStatus
            | Function::GetIntegerStatus
            | Function::GetBooleanStatus
            | Function::GetStringStatus => STATUS,
        }
    }

    fn is_allowed_in(&self, state: State) -> bool {
        self.allowed().contains(state)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use State::*;

    fn allowed(f: Function) -> Vec<State> {
        f.allowed().states().collect()
    }

    #[test]
    fn do_step_only_in_step_complete() {
        assert_eq!(allowed(Function::DoStep), vec![StepComplete]);
    }

    #[test]
    fn set_real_in_instantiated_initialization_and_step_complete() {
        assert_eq!(
            allowed(Function::SetReal),
            vec![Instantiated, InitializationMode, StepComplete]
        );
        for f in [
            Function::SetInteger,
            Function::SetBoolean,
            Function::SetString,
        ] {
            assert_eq!(f.allowed(), Function::SetReal.allowed(), "{f}");
        }
        assert!(!Function::SetReal.is_allowed_in(Terminated));
        assert!(!Function::SetReal.is_allowed_in(StepFailed));
        assert!(!Function::SetReal.is_allowed_in(Error));
    }

    #[test]
    fn get_real_not_in_instantiated_but_in_error_for_debugging() {
        assert!(!Function::GetReal.is_allowed_in(Instantiated));
        assert!(!Function::GetReal.is_allowed_in(StartAndEnd));
        assert!(!Function::GetReal.is_allowed_in(StepInProgress));
        for s in [
            InitializationMode,
            StepComplete,
            StepFailed,
            StepCanceled,
            Terminated,
            Error,
        ] {
            assert!(Function::GetReal.is_allowed_in(s), "{s}");
        }
    }

    #[test]
    fn fmu_state_functions_everywhere_but_start_end_in_progress_and_fatal() {
        for f in [
            Function::GetFmuState,
            Function::SetFmuState,
            Function::FreeFmuState,
            Function::SerializedFmuStateSize,
            Function::SerializeFmuState,
            Function::DeSerializeFmuState,
        ] {
            for s in State::ALL {
                let expected = !matches!(s, StartAndEnd | StepInProgress | Fatal);
                assert_eq!(f.is_allowed_in(s), expected, "{f} in {s}");
            }
        }
    }

    #[test]
    fn terminate_from_step_states_only() {
        assert_eq!(
            allowed(Function::Terminate),
            vec![StepComplete, StepFailed, StepCanceled]
        );
    }

    #[test]
    fn error_state_allows_only_recovery_debugging_and_cleanup() {
        let in_error: Vec<Function> = Function::ALL
            .into_iter()
            .filter(|f| f.is_allowed_in(Error))
            .collect();
        assert_eq!(
            in_error,
            vec![
                Function::GetTypesPlatform,
                Function::GetVersion,
                Function::SetDebugLogging,
                Function::FreeInstance,
                Function::Reset,
                Function::GetReal,
                Function::GetInteger,
                Function::GetBoolean,
                Function::GetString,
                Function::GetFmuState,
                Function::SetFmuState,
                Function::FreeFmuState,
                Function::SerializedFmuStateSize,
                Function::SerializeFmuState,
                Function::DeSerializeFmuState,
                Function::GetDirectionalDerivative,
                Function::GetRealOutputDerivatives,
            ]
        );
        let in_fatal: Vec<Function> = Function::ALL
            .into_iter()
            .filter(|f| f.is_allowed_in(Fatal))
            .collect();
        assert_eq!(
            in_fatal,
            vec![
                Function::GetTypesPlatform,
                Function::GetVersion,
                Function::FreeInstance
            ]
        );
    }

    #[test]
    fn life_cycle_functions() {
        assert_eq!(allowed(Function::Instantiate), vec![StartAndEnd]);
        assert_eq!(allowed(Function::SetupExperiment), vec![Instantiated]);
        assert_eq!(
            allowed(Function::EnterInitializationMode),
            vec![Instantiated]
        );
        assert_eq!(
            allowed(Function::ExitInitializationMode),
            vec![InitializationMode]
        );
        assert!(!Function::Reset.is_allowed_in(StartAndEnd));
        assert!(Function::Reset.is_allowed_in(Error));
        assert!(Function::FreeInstance.is_allowed_in(Fatal));
        assert!(!Function::FreeInstance.is_allowed_in(StartAndEnd));
        assert_eq!(allowed(Function::CancelStep), vec![StepInProgress]);
        assert_eq!(
            allowed(Function::GetBooleanStatus),
            vec![
                StepComplete,
                StepInProgress,
                StepFailed,
                StepCanceled,
                Terminated
            ]
        );
    }

    #[test]
    fn state_bits_round_trip_and_masks_print() {
        for s in State::ALL {
            assert_eq!(State::from_bit(s.bit()), Some(s));
        }
        assert_eq!(State::from_bit(0), None);
        assert_eq!(State::from_bit(3), None);
        assert_eq!(
            Function::Terminate.allowed().to_string(),
            "StepComplete, StepFailed, StepCanceled"
        );
        assert_eq!(StateMask(0).to_string(), "(none)");
    }
}
