//! FMI 2.0 Co-Simulation export plumbing.
//!
//! The project's FMUs (bridge, train) are `cdylib` crates that contain only their model:
//! a type implementing [`FmuModel`] and one line, [`export_fmi2!`]`(Model)`. Everything
//! else an FMU must get right lives here once, in the style of modelica/Reference-FMUs'
//! shared framework:
//!
//! | module | what |
//! |---|---|
//! | [`model`] | the contract with models ([`FmuModel`], [`Phase`], [`StepOutcome`], [`Log`]) |
//! | [`export`] | [`export_fmi2!`]: the 34 `extern "C"` symbols, each a one-line forward |
//! | [`api`] | the FMI functions as generic Rust functions: `catch_unwind`, NULL checks, state checks, argument checks |
//! | [`state`] | the Co-Simulation state machine as bit masks per function (table in its docs) |
//! | [`instance`] | the object behind `fmi2Component` and the body of each function |
//! | [`snapshot`] | `fmi2FMUstate` objects and the serialized-state format |
//! | [`logging`] | the importer's logger, log categories and filtering |
//! | [`mod@guid`] | deterministic GUIDs shared by the packager and the model |
//! | [`types`], [`uri`] | the fmi2 C types and `fmuResourceLocation` decoding, from the one binding in the `fmi2` crate |
//!
//! # Life of a call
//!
//! `fmi2DoStep(c, t, h, …)` in an FMU's shared object is
//! `api::do_step::<Model>(c, t, h, …)`, which catches panics, resolves `c` (NULL →
//! `fmi2Error`), checks that `fmi2DoStep` is allowed in the instance's [`state::State`]
//! (else logs "illegal call in state …" and returns `fmi2Error`), checks `t` and `h`, and
//! calls [`FmuModel::do_step`]. Every `fmi2Error` is logged with a reason (category
//! `logStatusError`, delivered even when debug logging is off) and puts the instance into
//! the `Error` state, from which `fmi2Reset`, `fmi2SetFMUstate` or `fmi2FreeInstance` lead
//! out. See [`api`] for ownership of the component pointer and the safety invariants.
//!
//! # What the FMU declares
//!
//! [`CAPABILITIES`] lists the `<CoSimulation>` attributes that match this plumbing, and
//! [`logging::LOG_CATEGORIES`] the `<LogCategories>`; the `modelDescription.xml` writer
//! should take them from there rather than restate them.

#![deny(unsafe_op_in_unsafe_fn)]

pub mod api;
pub mod dependencies;
pub mod export;
pub mod fmi3;
pub mod guid;
pub mod instance;
pub mod logging;
pub mod model;
pub mod snapshot;
pub mod state;

/// The FMI 3.0 C types, for [`export_fmi3!`].
pub use ::fmi3::types as fmi3_types;
pub use fmi2::{functions, types, uri};

pub use guid::guid;
pub use model::{FmuModel, Log, ModelError, Phase, StepOutcome};

/// The `<CoSimulation>` capability flags that describe FMUs built with this plumbing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CoSimulationCapabilities {
    /// `needsExecutionTool`: false (self-contained shared object).
    pub needs_execution_tool: bool,
    /// `canHandleVariableCommunicationStepSize`: true (any positive `h` per step).
    pub can_handle_variable_communication_step_size: bool,
    /// `canInterpolateInputs`: false (`fmi2SetRealInputDerivatives` → fmi2Error).
    pub can_interpolate_inputs: bool,
    /// `maxOutputDerivativeOrder`: 0 (`fmi2GetRealOutputDerivatives` → fmi2Error).
    pub max_output_derivative_order: u32,
    /// `canRunAsynchronuously` (sic): false (`fmi2CancelStep` is never legal).
    pub can_run_asynchronuously: bool,
    /// `canBeInstantiatedOnlyOncePerProcess`: false (instances share nothing).
    pub can_be_instantiated_only_once_per_process: bool,
    /// `canNotUseMemoryManagementFunctions`: true (Rust's allocator is used).
    pub can_not_use_memory_management_functions: bool,
    /// `canGetAndSetFMUstate`: true.
    pub can_get_and_set_fmu_state: bool,
    /// `canSerializeFMUstate`: true.
    pub can_serialize_fmu_state: bool,
    /// `providesDirectionalDerivative`: the model's
    /// [`FmuModel::PROVIDES_DIRECTIONAL_DERIVATIVE`] ([`capabilities_of`]); false in
    /// [`CAPABILITIES`].
    pub provides_directional_derivative: bool,
}

/// The capabilities of an FMU exported with [`export_fmi2!`] around the model `M`.
pub const fn capabilities_of<M: FmuModel>() -> CoSimulationCapabilities {
    CoSimulationCapabilities {
        provides_directional_derivative: M::PROVIDES_DIRECTIONAL_DERIVATIVE,
        ..CAPABILITIES
    }
}

/// The capabilities of every FMU exported with [`export_fmi2!`] whose model provides no
/// directional derivatives.
pub const CAPABILITIES: CoSimulationCapabilities = CoSimulationCapabilities {
    needs_execution_tool: false,
    can_handle_variable_communication_step_size: true,
    can_interpolate_inputs: false,
    max_output_derivative_order: 0,
    can_run_asynchronuously: false,
    can_be_instantiated_only_once_per_process: false,
    can_not_use_memory_management_functions: true,
    can_get_and_set_fmu_state: true,
    can_serialize_fmu_state: true,
    provides_directional_derivative: false,
};
