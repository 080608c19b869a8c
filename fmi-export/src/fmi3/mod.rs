//! FMI 3.0 Co-Simulation export: the same instances, models and checks as FMI 2.0, behind
//! the `fmi3…` functions.
//!
//! An FMI 3.0 function runs as the FMI 2.0 function with the same meaning and states
//! (`fmi3GetFloat64` as `fmi2GetReal`, `fmi3EnterInitializationMode` as
//! `fmi2SetupExperiment` then `fmi2EnterInitializationMode`, …), so the state table of
//! [`crate::state`], the argument checks of [`crate::api`] and the FMU states of
//! [`crate::snapshot`] hold for both; an instance made by `fmi3InstantiateCoSimulation`
//! names the FMI 3.0 functions in its messages ([`name_of`]). What FMI 3.0 adds:
//!
//! * `fmi3InstantiateCoSimulation` takes the resources folder as a native path
//!   (`resourcePath`) and the GUID as `instantiationToken`; it refuses `eventModeUsed`
//!   (the FMU declares `hasEventMode="false"`); `earlyReturnAllowed` and intermediate
//!   variables are accepted and unused (the FMU never returns early).
//! * `fmi3DoStep` reports `eventHandlingNeeded = false`, `earlyReturn = false`,
//!   `lastSuccessfulTime` (the instance's time after the call) and `terminateSimulation`
//!   (true with a discarded step the model asked to end on).
//! * The independent variable `time` ([`TIME_VALUE_REFERENCE`]) reads as the instance's
//!   time.
//! * Array variables do not exist: `nValues` must equal `nValueReferences`.
//! * Functions of types, interfaces and modes the FMU does not declare (Float32, the
//!   8/16/64-bit and unsigned integers, Binary, Clock, event and configuration mode, Model
//!   Exchange, Scheduled Execution, adjoint derivatives, variable dependencies) return
//!   `fmi3Error` with a message naming them; the two other `fmi3Instantiate…` return NULL.
//!
//! [`crate::export_fmi3!`] emits every symbol of `fmi3Functions.h`, each forwarding to a
//! function of [`api`].

pub mod api;
mod export;

pub use ::fmi3::TIME_VALUE_REFERENCE;

use crate::state::Function;

/// The FMI 3.0 function that runs as the FMI 2.0 `function` (for messages).
pub fn name_of(function: Function) -> &'static str {
    use Function as F;
    match function {
        F::GetTypesPlatform | F::GetVersion => "fmi3GetVersion",
        F::SetDebugLogging => "fmi3SetDebugLogging",
        F::Instantiate => "fmi3InstantiateCoSimulation",
        F::FreeInstance => "fmi3FreeInstance",
        F::SetupExperiment | F::EnterInitializationMode => "fmi3EnterInitializationMode",
        F::ExitInitializationMode => "fmi3ExitInitializationMode",
        F::Terminate => "fmi3Terminate",
        F::Reset => "fmi3Reset",
        F::GetReal => "fmi3GetFloat64",
        F::GetInteger => "fmi3GetInt32",
        F::GetBoolean => "fmi3GetBoolean",
        F::GetString => "fmi3GetString",
        F::SetReal => "fmi3SetFloat64",
        F::SetInteger => "fmi3SetInt32",
        F::SetBoolean => "fmi3SetBoolean",
        F::SetString => "fmi3SetString",
        F::GetFmuState => "fmi3GetFMUState",
        F::SetFmuState => "fmi3SetFMUState",
        F::FreeFmuState => "fmi3FreeFMUState",
        F::SerializedFmuStateSize => "fmi3SerializedFMUStateSize",
        F::SerializeFmuState => "fmi3SerializeFMUState",
        F::DeSerializeFmuState => "fmi3DeserializeFMUState",
        F::GetDirectionalDerivative => "fmi3GetDirectionalDerivative",
        F::GetRealOutputDerivatives => "fmi3GetOutputDerivatives",
        F::DoStep => "fmi3DoStep",
        // no FMI 3.0 counterpart: never called on an FMI 3.0 instance
        other => other.symbol(),
    }
}
