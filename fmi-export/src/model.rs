//! The contract between the FMI plumbing and a model.
//!
//! A model holds only its equations and data. The plumbing in this crate owns the FMI
//! state machine, the logger, `catch_unwind`, GUID and fmuType checks, resource lookup and
//! FMU-state handling, and calls into the model through [`FmuModel`].
//!
//! Value references are the model's own `u32` numbers (as listed in its
//! `modelDescription.xml`). Only `Real` variables are needed by the project's models; the
//! Integer/Boolean/String accessors default to "unknown value reference".

use std::path::Path;

/// Where the instance is in the FMI 2.0 Co-Simulation life cycle, as seen by the model
/// when a variable is set (so it can enforce causality/variability rules).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// After `fmi2Instantiate`, before `fmi2EnterInitializationMode`.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    Initialization,
    /// After `fmi2ExitInitializationMode` (step mode).
    Stepping,
}

/// Result of a successful communication step.
#[derive(Debug, Clone, PartialEq)]
pub enum StepOutcome {
    /// The step was completed; outputs are valid at `t + h`.
    Ok,
    /// The step could not be completed meaningfully (for example the model reached the end
    /// of its data); the message is logged and `fmi2DoStep` returns `fmi2Discard`.
    Discard(String),
}

/// Why a model refused a call. The plumbing logs the message (in the category the kind
/// suggests) and returns `fmi2Error` to the importer.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// No variable of this type has the value reference.
    #[error("unknown {kind} value reference {vr}")]
    UnknownVariable { kind: &'static str, vr: u32 },
    /// A value the model cannot take, or a variable it cannot set now (the message names
    /// the variable, the value and the rule).
    #[error("{0}")]
    Refused(String),
    /// The resources are missing or malformed (the message names the file).
    #[error("{0}")]
    Resources(String),
    /// What the model was asked cannot be done (a step, a state, a derivative it does not
    /// provide); the message says what.
    #[error("{0}")]
    Failed(String),
}

impl From<String> for ModelError {
    fn from(message: String) -> Self {
        ModelError::Failed(message)
    }
}

/// The plumbing logs a refusal as its message.
impl From<ModelError> for String {
    fn from(e: ModelError) -> String {
        e.to_string()
    }
}

impl From<&str> for ModelError {
    fn from(message: &str) -> Self {
        ModelError::Failed(message.to_owned())
    }
}

/// Messages a model wants logged (category, text). The plumbing forwards them to the
/// importer's logger callback with the `"%s"` format.
pub trait Log {
    fn log(&self, category: &str, message: &str);
}

/// A Co-Simulation model. `Clone` must produce an independent copy of the complete dynamic
/// state (used for `fmi2GetFMUstate`); keep large immutable data behind `Arc` so cloning
/// is cheap.
pub trait FmuModel: Clone + Send + 'static {
    /// Log categories the model uses in [`Log::log`] besides the plumbing's own
    /// (`crate::logging::LOG_CATEGORIES`), as (name, description) for `<LogCategories>`.
    /// `fmi2SetDebugLogging` accepts them without a warning.
    const LOG_CATEGORIES: &'static [(&'static str, &'static str)] = &[];

    /// Build the model from its resources folder (the `resources/` of the unpacked FMU,
    /// as given by `fmuResourceLocation`). Errors name the file and the problem.
    fn instantiate(resources: &Path, log: &dyn Log) -> Result<Self, ModelError>;

    /// The GUID this instance's binary and resources correspond to. The plumbing refuses
    /// to instantiate when it differs from the GUID passed to `fmi2Instantiate`.
    fn guid(&self) -> String;

    /// `fmi2SetupExperiment`: start time and optional stop time.
    fn setup_experiment(
        &mut self,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(), ModelError> {
        let _ = (start_time, stop_time);
        Ok(())
    }

    /// `fmi2EnterInitializationMode`.
    fn enter_initialization(&mut self) -> Result<(), ModelError> {
        Ok(())
    }

    /// `fmi2ExitInitializationMode`: parameters are final; compute the initial state.
    fn exit_initialization(&mut self) -> Result<(), ModelError>;

    /// Set a Real variable. The model rejects unknown references, values it cannot accept
    /// (non-finite, out of range) and variables that may not be set in `phase`.
    fn set_real(&mut self, vr: u32, value: f64, phase: Phase) -> Result<(), ModelError>;

    /// Get a Real variable (any phase but `Instantiated`).
    fn get_real(&mut self, vr: u32) -> Result<f64, ModelError>;

    /// Set several Real variables (one `fmi2SetReal`; the values are finite, checked before).
    /// Default: [`FmuModel::set_real`] for each in turn. A model may take runs of consecutive
    /// value references at once, with the same result.
    fn set_reals(&mut self, vr: &[u32], values: &[f64], phase: Phase) -> Result<(), ModelError> {
        set_each(self, vr, values, phase)
    }

    /// Get several Real variables (one `fmi2GetReal`). Default: [`FmuModel::get_real`] for
    /// each in turn; a model may copy runs of consecutive value references at once.
    fn get_reals(&mut self, vr: &[u32], values: &mut [f64]) -> Result<(), ModelError> {
        get_each(self, vr, values)
    }

    fn set_integer(&mut self, vr: u32, _value: i32, _phase: Phase) -> Result<(), ModelError> {
        Err(ModelError::UnknownVariable {
            kind: "Integer",
            vr,
        })
    }
    fn get_integer(&mut self, vr: u32) -> Result<i32, ModelError> {
        Err(ModelError::UnknownVariable {
            kind: "Integer",
            vr,
        })
    }
    fn set_boolean(&mut self, vr: u32, _value: bool, _phase: Phase) -> Result<(), ModelError> {
        Err(ModelError::UnknownVariable {
            kind: "Boolean",
            vr,
        })
    }
    fn get_boolean(&mut self, vr: u32) -> Result<bool, ModelError> {
        Err(ModelError::UnknownVariable {
            kind: "Boolean",
            vr,
        })
    }
    fn set_string(&mut self, vr: u32, _value: &str, _phase: Phase) -> Result<(), ModelError> {
        Err(ModelError::UnknownVariable { kind: "String", vr })
    }
    fn get_string(&mut self, vr: u32) -> Result<String, ModelError> {
        Err(ModelError::UnknownVariable { kind: "String", vr })
    }

    /// `providesDirectionalDerivative`: whether [`FmuModel::directional_derivative`] is
    /// implemented. Default: false (`fmi2GetDirectionalDerivative` → fmi2Error).
    const PROVIDES_DIRECTIONAL_DERIVATIVE: bool = false;

    /// `fmi2GetDirectionalDerivative`: `out = (∂unknowns/∂knowns) · seed`, the partial
    /// derivatives at the current point (in Co-Simulation, at the communication point: the
    /// direct feedthrough of the inputs to the outputs, not a sensitivity of a step). Called
    /// only when [`FmuModel::PROVIDES_DIRECTIONAL_DERIVATIVE`] is true; `unknowns` and `knowns`
    /// are value references as the importer gives them (the model refuses those that are not
    /// outputs, resp. inputs), `seed` has one value per known, `out` one per unknown.
    fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<(), ModelError> {
        let _ = (unknowns, knowns, seed, out);
        Err("directional derivatives are not provided".into())
    }

    /// Advance from `t` to `t + h` (one communication step). Inputs set before the call
    /// are the values at `t + h`.
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, ModelError>;

    /// `fmi2Reset`: back to the freshly instantiated state.
    fn reset(&mut self) -> Result<(), ModelError>;

    /// Serialize the complete dynamic state (including parameters that may have been set).
    fn serialize_state(&self) -> Vec<u8>;

    /// Restore a state written by [`FmuModel::serialize_state`] (possibly by another
    /// instance of the same FMU).
    fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), ModelError>;
}

/// [`FmuModel::set_real`] for each value in turn: the default of [`FmuModel::set_reals`], and
/// what a model's own `set_reals` falls back to for value references it does not take at once.
pub fn set_each<M: FmuModel>(
    model: &mut M,
    vr: &[u32],
    values: &[f64],
    phase: Phase,
) -> Result<(), ModelError> {
    vr.iter()
        .zip(values)
        .try_for_each(|(&r, &v)| model.set_real(r, v, phase))
}

/// [`FmuModel::get_real`] for each value in turn (see [`set_each`]).
pub fn get_each<M: FmuModel>(
    model: &mut M,
    vr: &[u32],
    values: &mut [f64],
) -> Result<(), ModelError> {
    for (&r, out) in vr.iter().zip(values.iter_mut()) {
        *out = model.get_real(r)?;
    }
    Ok(())
}
