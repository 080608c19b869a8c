//! An FMU instance as a participant of the coupling library ([`tbi_coupling::Participant`]):
//! Real values through `fmi2GetReal`/`fmi2SetReal`, Integer and Boolean ones through their
//! calls, `fmi2DoStep` as the step (a discard reported as [`StepStatus::Discard`]), and one
//! rollback slot held with `fmi2GetFMUstate`/`fmi2SetFMUstate`.

use crate::{Fmu, FmuState, Instance, StepResult};
use model_description::VariableKind;
use std::collections::HashMap;
use tbi_coupling::{CouplingError, Discrete, Participant, StepStatus};

/// An FMU instance as a coupling participant, with one rollback slot.
pub struct FmuParticipant {
    pub inst: Instance,
    saved: Option<FmuState>,
    /// Declared unit of each Real variable, by value reference.
    units: HashMap<u32, String>,
    /// Name of each Real variable, by value reference (for messages).
    names: HashMap<u32, String>,
}

impl FmuParticipant {
    /// Wrap an instance of `fmu`; the units of its Real variables come from its model
    /// description.
    pub fn new(fmu: &Fmu, inst: Instance) -> Self {
        let units = fmu
            .model_description()
            .model_variables
            .iter()
            .filter_map(|v| match &v.kind {
                VariableKind::Real(r) => r.attributes.unit.clone().map(|u| (v.value_reference, u)),
                _ => None,
            })
            .collect();
        let names = fmu
            .model_description()
            .model_variables
            .iter()
            .filter(|v| matches!(v.kind, VariableKind::Real(_)))
            .map(|v| (v.value_reference, v.name.clone()))
            .collect();
        FmuParticipant {
            inst,
            saved: None,
            units,
            names,
        }
    }
}

fn cerr(e: impl std::fmt::Display) -> CouplingError {
    CouplingError::new(e.to_string())
}

impl Participant for FmuParticipant {
    fn name(&self) -> &str {
        self.inst.name()
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), CouplingError> {
        self.inst.set_real(vrs, values).map(|_| ()).map_err(cerr)
    }
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), CouplingError> {
        self.inst.get_real(vrs, values).map(|_| ()).map_err(cerr)
    }
    /// The importer's `get_real` refuses a value that is not finite, naming the variable.
    fn get_real_refuses_non_finite(&self) -> bool {
        true
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<StepStatus, CouplingError> {
        match self.inst.do_step(t, h, false).map_err(cerr)? {
            StepResult::Discard => Ok(StepStatus::Discard),
            _ => Ok(StepStatus::Ok),
        }
    }
    fn save_state(&mut self) -> Result<(), CouplingError> {
        let s = self.inst.get_fmu_state(self.saved.take()).map_err(cerr)?;
        self.saved = Some(s);
        Ok(())
    }
    fn restore_state(&mut self) -> Result<(), CouplingError> {
        let s = self
            .saved
            .as_ref()
            .ok_or_else(|| CouplingError::new(format!("{}: no saved state", self.inst.name())))?;
        self.inst.set_fmu_state(s).map(|_| ()).map_err(cerr)
    }
    fn unit(&self, vr: u32) -> Option<&str> {
        self.units.get(&vr).map(String::as_str)
    }
    fn variable_name(&self, vr: u32) -> Option<String> {
        self.names.get(&vr).cloned()
    }
    fn exit_initialization(&mut self) -> Result<(), CouplingError> {
        self.inst
            .exit_initialization_mode()
            .map(drop)
            .map_err(|e| CouplingError::new(e.to_string()))
    }
    fn get_discrete(
        &mut self,
        kind: Discrete,
        vrs: &[u32],
        values: &mut [i32],
    ) -> Result<(), CouplingError> {
        for (&vr, v) in vrs.iter().zip(values) {
            *v = get_discrete(&mut self.inst, kind, vr).map_err(CouplingError::new)?;
        }
        Ok(())
    }
    fn set_discrete(
        &mut self,
        kind: Discrete,
        vrs: &[u32],
        values: &[i32],
    ) -> Result<(), CouplingError> {
        for (&vr, &v) in vrs.iter().zip(values) {
            set_discrete(&mut self.inst, kind, vr, v).map_err(CouplingError::new)?;
        }
        Ok(())
    }
}

/// One Integer or Boolean (0/1) value of an instance.
fn get_discrete(inst: &mut Instance, kind: Discrete, vr: u32) -> Result<i32, String> {
    match kind {
        Discrete::Integer => {
            let mut v = [0];
            inst.get_integer(&[vr], &mut v).map_err(|e| e.to_string())?;
            Ok(v[0])
        }
        Discrete::Boolean => {
            let mut v = [false];
            inst.get_boolean(&[vr], &mut v).map_err(|e| e.to_string())?;
            Ok(i32::from(v[0]))
        }
    }
}

/// Set one Integer or Boolean (0/1) input of an instance.
fn set_discrete(inst: &mut Instance, kind: Discrete, vr: u32, value: i32) -> Result<(), String> {
    match kind {
        Discrete::Integer => inst.set_integer(&[vr], &[value]),
        Discrete::Boolean => inst.set_boolean(&[vr], &[value != 0]),
    }
    .map(drop)
    .map_err(|e| e.to_string())
}
