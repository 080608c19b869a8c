//! Pass 3 for `<ModelExchange>` and `<CoSimulation>`: capability flags and source files.

use super::raw::{RawInterface, RawSourceFiles};
use super::values::{flag, opt_u32, required, R};
use crate::types::{CoSimulation, ModelExchange};

fn source_files(raw: Option<RawSourceFiles>, element: &str) -> R<Vec<String>> {
    raw.map(|s| s.files)
        .unwrap_or_default()
        .into_iter()
        .map(|f| required(f.name, "name", &format!("{element}/SourceFiles/File")))
        .collect()
}

/// `<ModelExchange>` with its capability flags and source files.
pub(super) fn convert_model_exchange(me: RawInterface) -> R<ModelExchange> {
    let el = "<ModelExchange>";
    Ok(ModelExchange {
        model_identifier: required(me.model_identifier.clone(), "modelIdentifier", el)?,
        needs_execution_tool: flag(&me.needs_execution_tool, "needsExecutionTool", el)?,
        completed_integrator_step_not_needed: flag(
            &me.completed_integrator_step_not_needed,
            "completedIntegratorStepNotNeeded",
            el,
        )?,
        can_be_instantiated_only_once_per_process: flag(
            &me.can_be_instantiated_only_once_per_process,
            "canBeInstantiatedOnlyOncePerProcess",
            el,
        )?,
        can_not_use_memory_management_functions: flag(
            &me.can_not_use_memory_management_functions,
            "canNotUseMemoryManagementFunctions",
            el,
        )?,
        can_get_and_set_fmu_state: flag(&me.can_get_and_set_fmu_state, "canGetAndSetFMUstate", el)?,
        can_serialize_fmu_state: flag(&me.can_serialize_fmu_state, "canSerializeFMUstate", el)?,
        provides_directional_derivative: flag(
            &me.provides_directional_derivative,
            "providesDirectionalDerivative",
            el,
        )?,
        source_files: source_files(me.source_files, el)?,
    })
}

/// `<CoSimulation>` with its capability flags and source files.
pub(super) fn convert_co_simulation(cs: RawInterface) -> R<CoSimulation> {
    let el = "<CoSimulation>";
    Ok(CoSimulation {
        model_identifier: required(cs.model_identifier.clone(), "modelIdentifier", el)?,
        needs_execution_tool: flag(&cs.needs_execution_tool, "needsExecutionTool", el)?,
        can_handle_variable_communication_step_size: flag(
            &cs.can_handle_variable_communication_step_size,
            "canHandleVariableCommunicationStepSize",
            el,
        )?,
        can_interpolate_inputs: flag(&cs.can_interpolate_inputs, "canInterpolateInputs", el)?,
        max_output_derivative_order: opt_u32(
            &cs.max_output_derivative_order,
            "maxOutputDerivativeOrder",
            el,
        )?
        .unwrap_or(0),
        can_run_asynchronuously: flag(&cs.can_run_asynchronuously, "canRunAsynchronuously", el)?,
        can_be_instantiated_only_once_per_process: flag(
            &cs.can_be_instantiated_only_once_per_process,
            "canBeInstantiatedOnlyOncePerProcess",
            el,
        )?,
        can_not_use_memory_management_functions: flag(
            &cs.can_not_use_memory_management_functions,
            "canNotUseMemoryManagementFunctions",
            el,
        )?,
        can_get_and_set_fmu_state: flag(&cs.can_get_and_set_fmu_state, "canGetAndSetFMUstate", el)?,
        can_serialize_fmu_state: flag(&cs.can_serialize_fmu_state, "canSerializeFMUstate", el)?,
        provides_directional_derivative: flag(
            &cs.provides_directional_derivative,
            "providesDirectionalDerivative",
            el,
        )?,
        source_files: source_files(cs.source_files, el)?,
    })
}
