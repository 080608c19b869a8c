//! An FMU instance as a participant of the coupling library ([`tbi_coupling::Participant`]):
//! Real values through `fmi2GetReal`/`fmi2SetReal`, Integer and Boolean ones through their
//! calls, `fmi2DoStep` as the step (a discard reported as [`StepStatus::Discard`]), and one
//! rollback slot held with `fmi2GetFMUstate`/`fmi2SetFMUstate`.
//!
//! The calls go through [`FmiCalls`]: to an [`Instance`] in this process ([`LocalInstance`])
//! or to one in a worker process ([`crate::remote::RemoteInstance`]), the same for the
//! coupling.

use crate::{FmuState, Instance, StepResult};
use model_description::{ModelDescription, VariableKind};
use std::collections::HashMap;
use tbi_coupling::{CouplingError, Discrete, Participant, StepStatus};

/// The FMI calls a master makes on one Co-Simulation instance, with one rollback slot;
/// errors are messages that name the instance.
pub trait FmiCalls {
    /// The instance name.
    fn name(&self) -> &str;
    /// `fmi2SetupExperiment`.
    fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), String>;
    /// `fmi2EnterInitializationMode`.
    fn enter_initialization_mode(&mut self) -> Result<(), String>;
    /// `fmi2ExitInitializationMode`.
    fn exit_initialization_mode(&mut self) -> Result<(), String>;
    /// `fmi2SetReal`.
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String>;
    /// `fmi2GetReal`; a value that is not finite is an error naming the variable.
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), String>;
    /// `fmi2SetInteger`.
    fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), String>;
    /// `fmi2GetInteger`.
    fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Result<(), String>;
    /// `fmi2SetBoolean`.
    fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), String>;
    /// `fmi2GetBoolean`.
    fn get_boolean(&mut self, vrs: &[u32], values: &mut [bool]) -> Result<(), String>;
    /// `fmi2SetString`.
    fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<(), String>;
    /// `fmi2DoStep(t, h)`; `true` when the FMU discarded the step.
    fn do_step(&mut self, t: f64, h: f64) -> Result<bool, String>;
    /// Start `fmi2DoStep(t, h)`: `Some(discarded)` when done now (the default), `None` when
    /// it runs on (in a worker) until [`FmiCalls::finish_step`].
    fn start_step(&mut self, t: f64, h: f64) -> Result<Option<bool>, String> {
        self.do_step(t, h).map(Some)
    }
    /// End the step [`FmiCalls::start_step`] left running; `true` when discarded.
    fn finish_step(&mut self) -> Result<bool, String> {
        Err(format!("{}: no step is running", self.name()))
    }
    /// `fmi2GetFMUstate` into the one slot.
    fn save_state(&mut self) -> Result<(), String>;
    /// `fmi2SetFMUstate` from the slot.
    fn restore_state(&mut self) -> Result<(), String>;
    /// `fmi2DoStep(t, h)` with `noSetFMUStatePriorToCurrentPoint = fmi2True` (a run that
    /// never rolls back, as `tbi simulate` and FMPy step); `true` when discarded.
    fn do_step_final(&mut self, t: f64, h: f64) -> Result<bool, String>;
    /// `fmi2GetBooleanStatus(fmi2Terminated)`: whether the FMU asked to end the run.
    fn terminated(&mut self) -> Result<bool, String>;
    /// `fmi2GetRealStatus(fmi2LastSuccessfulTime)`, s.
    fn last_successful_time(&mut self) -> Result<f64, String>;
    /// `fmi2Terminate`.
    fn terminate(&mut self) -> Result<(), String>;
}

/// An instance in this process, with its rollback slot.
pub struct LocalInstance {
    pub inst: Instance,
    saved: Option<FmuState>,
}

impl LocalInstance {
    pub fn new(inst: Instance) -> Self {
        LocalInstance { inst, saved: None }
    }
}

fn text(e: crate::FmiError) -> String {
    e.to_string()
}

impl FmiCalls for LocalInstance {
    fn name(&self) -> &str {
        self.inst.name()
    }
    fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), String> {
        self.inst
            .setup_experiment(tolerance, start, stop)
            .map(drop)
            .map_err(text)
    }
    fn enter_initialization_mode(&mut self) -> Result<(), String> {
        self.inst
            .enter_initialization_mode()
            .map(drop)
            .map_err(text)
    }
    fn exit_initialization_mode(&mut self) -> Result<(), String> {
        self.inst.exit_initialization_mode().map(drop).map_err(text)
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        self.inst.set_real(vrs, values).map(drop).map_err(text)
    }
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), String> {
        self.inst.get_real(vrs, values).map(drop).map_err(text)
    }
    fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), String> {
        self.inst.set_integer(vrs, values).map(drop).map_err(text)
    }
    fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Result<(), String> {
        self.inst.get_integer(vrs, values).map(drop).map_err(text)
    }
    fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), String> {
        self.inst.set_boolean(vrs, values).map(drop).map_err(text)
    }
    fn get_boolean(&mut self, vrs: &[u32], values: &mut [bool]) -> Result<(), String> {
        self.inst.get_boolean(vrs, values).map(drop).map_err(text)
    }
    fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<(), String> {
        self.inst.set_string(vrs, values).map(drop).map_err(text)
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<bool, String> {
        let r = self.inst.do_step(t, h, false).map_err(text)?;
        Ok(matches!(r, StepResult::Discard))
    }
    fn save_state(&mut self) -> Result<(), String> {
        let s = self.inst.get_fmu_state(self.saved.take()).map_err(text)?;
        self.saved = Some(s);
        Ok(())
    }
    fn restore_state(&mut self) -> Result<(), String> {
        let s = self
            .saved
            .as_ref()
            .ok_or_else(|| format!("{}: no saved state", self.inst.name()))?;
        self.inst.set_fmu_state(s).map(drop).map_err(text)
    }
    fn do_step_final(&mut self, t: f64, h: f64) -> Result<bool, String> {
        let r = self.inst.do_step(t, h, true).map_err(text)?;
        Ok(matches!(r, StepResult::Discard))
    }
    fn terminated(&mut self) -> Result<bool, String> {
        self.inst.terminated().map_err(text)
    }
    fn last_successful_time(&mut self) -> Result<f64, String> {
        self.inst.last_successful_time().map_err(text)
    }
    fn terminate(&mut self) -> Result<(), String> {
        self.inst.terminate().map(drop).map_err(text)
    }
}

/// An FMU instance as a coupling participant.
pub struct FmuParticipant {
    pub calls: Box<dyn FmiCalls>,
    /// Declared unit of each Real variable, by value reference.
    units: HashMap<u32, String>,
    /// Name of each Real variable, by value reference (for messages).
    names: HashMap<u32, String>,
}

impl FmuParticipant {
    /// Wrap the calls to an instance of the FMU described by `md` (the units of its Real
    /// variables come from there).
    pub fn new(md: &ModelDescription, calls: Box<dyn FmiCalls>) -> Self {
        let units = md
            .model_variables
            .iter()
            .filter_map(|v| match &v.kind {
                VariableKind::Real(r) => r.attributes.unit.clone().map(|u| (v.value_reference, u)),
                _ => None,
            })
            .collect();
        let names = md
            .model_variables
            .iter()
            .filter(|v| matches!(v.kind, VariableKind::Real(_)))
            .map(|v| (v.value_reference, v.name.clone()))
            .collect();
        FmuParticipant {
            calls,
            units,
            names,
        }
    }
}

/// The coupling's status of a step that was (`true`) or was not discarded.
fn status(discarded: bool) -> StepStatus {
    if discarded {
        StepStatus::Discard
    } else {
        StepStatus::Ok
    }
}

impl Participant for FmuParticipant {
    fn name(&self) -> &str {
        self.calls.name()
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError> {
        self.calls.set_real(vrs, values).map_err(CouplingError::new)
    }
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError> {
        self.calls.get_real(vrs, values).map_err(CouplingError::new)
    }
    /// The importer's `get_real` refuses a value that is not finite, naming the variable.
    fn get_real_refuses_non_finite(&self) -> bool {
        true
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepStatus, CouplingError> {
        self.calls
            .do_step(t, h)
            .map(status)
            .map_err(CouplingError::new)
    }
    fn start_step(&mut self, t: f64, h: f64) -> Result<Option<StepStatus>, CouplingError> {
        let started = self.calls.start_step(t, h).map_err(CouplingError::new)?;
        Ok(started.map(status))
    }
    fn finish_step(&mut self) -> Result<StepStatus, CouplingError> {
        self.calls
            .finish_step()
            .map(status)
            .map_err(CouplingError::new)
    }
    fn save_state(&mut self) -> Result<(), CouplingError> {
        self.calls.save_state().map_err(CouplingError::new)
    }
    fn restore_state(&mut self) -> Result<(), CouplingError> {
        self.calls.restore_state().map_err(CouplingError::new)
    }
    fn unit(&self, vr: u32) -> Option<&str> {
        self.units.get(&vr).map(String::as_str)
    }
    fn variable_name(&self, vr: u32) -> Option<String> {
        self.names.get(&vr).cloned()
    }
    fn exit_initialization(&mut self) -> Result<(), CouplingError> {
        self.calls
            .exit_initialization_mode()
            .map_err(CouplingError::new)
    }
    fn get_discrete(
        &mut self,
        kind: Discrete,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<(), CouplingError> {
        match kind {
            Discrete::Integer => self.calls.get_integer(vrs, values),
            Discrete::Boolean => {
                let mut b = vec![false; vrs.len()];
                self.calls.get_boolean(vrs, &mut b).map(|()| {
                    for (v, b) in values.iter_mut().zip(b) {
                        *v = i32::from(b);
                    }
                })
            }
        }
        .map_err(CouplingError::new)
    }
    fn set_discrete(
        &mut self,
        kind: Discrete,
        vrs: &[u32],
        values: &[i32],
    ) -> Result<(), CouplingError> {
        match kind {
            Discrete::Integer => self.calls.set_integer(vrs, values),
            Discrete::Boolean => {
                let b: Vec<bool> = values.iter().map(|&v| v != 0).collect();
                self.calls.set_boolean(vrs, &b)
            }
        }
        .map_err(CouplingError::new)
    }
}
