//! The functions of `fmi3Functions.h`: every name ([`FUNCTION_NAMES`], which a shared
//! object of an FMI 3.0 FMU exports whatever interfaces it declares) and the typedefs of
//! the calls an importer of Co-Simulation FMUs makes.

#![allow(non_camel_case_types)]

use crate::types::*;

/// Every function of `fmi3Functions.h`, in its order (75 names).
pub const FUNCTION_NAMES: [&str; 75] = [
    "fmi3GetVersion",
    "fmi3SetDebugLogging",
    "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation",
    "fmi3InstantiateScheduledExecution",
    "fmi3FreeInstance",
    "fmi3EnterInitializationMode",
    "fmi3ExitInitializationMode",
    "fmi3EnterEventMode",
    "fmi3Terminate",
    "fmi3Reset",
    "fmi3GetFloat32",
    "fmi3GetFloat64",
    "fmi3GetInt8",
    "fmi3GetUInt8",
    "fmi3GetInt16",
    "fmi3GetUInt16",
    "fmi3GetInt32",
    "fmi3GetUInt32",
    "fmi3GetInt64",
    "fmi3GetUInt64",
    "fmi3GetBoolean",
    "fmi3GetString",
    "fmi3GetBinary",
    "fmi3GetClock",
    "fmi3SetFloat32",
    "fmi3SetFloat64",
    "fmi3SetInt8",
    "fmi3SetUInt8",
    "fmi3SetInt16",
    "fmi3SetUInt16",
    "fmi3SetInt32",
    "fmi3SetUInt32",
    "fmi3SetInt64",
    "fmi3SetUInt64",
    "fmi3SetBoolean",
    "fmi3SetString",
    "fmi3SetBinary",
    "fmi3SetClock",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3GetVariableDependencies",
    "fmi3GetFMUState",
    "fmi3SetFMUState",
    "fmi3FreeFMUState",
    "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState",
    "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative",
    "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode",
    "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal",
    "fmi3GetIntervalFraction",
    "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction",
    "fmi3SetIntervalDecimal",
    "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction",
    "fmi3EvaluateDiscreteStates",
    "fmi3UpdateDiscreteStates",
    "fmi3EnterContinuousTimeMode",
    "fmi3CompletedIntegratorStep",
    "fmi3SetTime",
    "fmi3SetContinuousStates",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetEventIndicators",
    "fmi3GetContinuousStates",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfContinuousStates",
    "fmi3EnterStepMode",
    "fmi3GetOutputDerivatives",
    "fmi3DoStep",
    "fmi3ActivateModelPartition",
];

pub type fmi3GetVersionTYPE = unsafe extern "C" fn() -> fmi3String;
pub type fmi3SetDebugLoggingTYPE = unsafe extern "C" fn(
    instance: fmi3Instance,
    logging_on: fmi3Boolean,
    n_categories: usize,
    categories: *const fmi3String,
) -> fmi3Status;
pub type fmi3InstantiateCoSimulationTYPE = unsafe extern "C" fn(
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    visible: fmi3Boolean,
    logging_on: fmi3Boolean,
    event_mode_used: fmi3Boolean,
    early_return_allowed: fmi3Boolean,
    required_intermediate_variables: *const fmi3ValueReference,
    n_required_intermediate_variables: usize,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    intermediate_update: fmi3IntermediateUpdateCallback,
) -> fmi3Instance;
pub type fmi3FreeInstanceTYPE = unsafe extern "C" fn(instance: fmi3Instance);
pub type fmi3EnterInitializationModeTYPE = unsafe extern "C" fn(
    instance: fmi3Instance,
    tolerance_defined: fmi3Boolean,
    tolerance: fmi3Float64,
    start_time: fmi3Float64,
    stop_time_defined: fmi3Boolean,
    stop_time: fmi3Float64,
) -> fmi3Status;
/// `fmi3ExitInitializationMode`, `fmi3EnterEventMode`, `fmi3Terminate`, `fmi3Reset`,
/// `fmi3EnterStepMode`, …: the instance only.
pub type fmi3InstanceOnlyTYPE = unsafe extern "C" fn(instance: fmi3Instance) -> fmi3Status;
/// `fmi3Get<Type>`: value references, their count, the values and their count.
pub type fmi3GetTYPE<T> = unsafe extern "C" fn(
    instance: fmi3Instance,
    value_references: *const fmi3ValueReference,
    n_value_references: usize,
    values: *mut T,
    n_values: usize,
) -> fmi3Status;
/// `fmi3Set<Type>`: value references, their count, the values and their count.
pub type fmi3SetTYPE<T> = unsafe extern "C" fn(
    instance: fmi3Instance,
    value_references: *const fmi3ValueReference,
    n_value_references: usize,
    values: *const T,
    n_values: usize,
) -> fmi3Status;
pub type fmi3GetFMUStateTYPE =
    unsafe extern "C" fn(instance: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status;
pub type fmi3SetFMUStateTYPE =
    unsafe extern "C" fn(instance: fmi3Instance, state: fmi3FMUState) -> fmi3Status;
pub type fmi3FreeFMUStateTYPE =
    unsafe extern "C" fn(instance: fmi3Instance, state: *mut fmi3FMUState) -> fmi3Status;
pub type fmi3SerializedFMUStateSizeTYPE = unsafe extern "C" fn(
    instance: fmi3Instance,
    state: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status;
pub type fmi3SerializeFMUStateTYPE = unsafe extern "C" fn(
    instance: fmi3Instance,
    state: fmi3FMUState,
    serialized: *mut fmi3Byte,
    size: usize,
) -> fmi3Status;
pub type fmi3DeserializeFMUStateTYPE = unsafe extern "C" fn(
    instance: fmi3Instance,
    serialized: *const fmi3Byte,
    size: usize,
    state: *mut fmi3FMUState,
) -> fmi3Status;
pub type fmi3GetDirectionalDerivativeTYPE = unsafe extern "C" fn(
    instance: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const fmi3Float64,
    n_seed: usize,
    sensitivity: *mut fmi3Float64,
    n_sensitivity: usize,
) -> fmi3Status;
pub type fmi3DoStepTYPE = unsafe extern "C" fn(
    instance: fmi3Instance,
    current_communication_point: fmi3Float64,
    communication_step_size: fmi3Float64,
    no_set_fmu_state_prior_to_current_point: fmi3Boolean,
    event_handling_needed: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    early_return: *mut fmi3Boolean,
    last_successful_time: *mut fmi3Float64,
) -> fmi3Status;

#[cfg(test)]
mod tests {
    #[test]
    fn the_names_are_unique_and_all_fmi3() {
        let mut names = super::FUNCTION_NAMES.to_vec();
        assert!(names.iter().all(|n| n.starts_with("fmi3")));
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), super::FUNCTION_NAMES.len());
    }
}
