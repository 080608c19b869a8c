//! The Co-Simulation calls of an instance: `fmi2DoStep` ([`StepResult`]),
//! `fmi2CancelStep`, input and output derivatives, directional derivatives, and the
//! status queries ([`StatusKind`]).

use super::{fmi2_bool, static_str, Instance, Space};
use crate::error::{CallStatus, FmiError, Status};
use fmi2::types::*;

/// `fmi2StatusKind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatusKind {
    DoStepStatus = 0,
    PendingStatus = 1,
    LastSuccessfulTime = 2,
    Terminated = 3,
}

impl StatusKind {
    fn name(self) -> &'static str {
        match self {
            StatusKind::DoStepStatus => "fmi2DoStepStatus",
            StatusKind::PendingStatus => "fmi2PendingStatus",
            StatusKind::LastSuccessfulTime => "fmi2LastSuccessfulTime",
            StatusKind::Terminated => "fmi2Terminated",
        }
    }
}

/// How `fmi2DoStep` ended when it did not fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepResult {
    /// `fmi2OK`.
    Ok,
    /// `fmi2Warning`: the step was completed; the FMU logged something worth reading.
    Warning,
    /// `fmi2Discard`: the step was not completed as requested; ask
    /// [`Instance::terminated`] and [`Instance::last_successful_time`] how far it got.
    Discard,
}

impl Instance {
    /// `fmi2DoStep(currentCommunicationPoint, communicationStepSize,
    /// noSetFMUStatePriorToCurrentPoint)`.
    pub fn do_step(
        &mut self,
        current_communication_point: f64,
        communication_step_size: f64,
        no_set_fmu_state_prior_to_current_point: bool,
    ) -> Result<StepResult, FmiError> {
        let status = self.call(
            |_| {
                format!(
                    "fmi2DoStep(currentCommunicationPoint={current_communication_point}, communicationStepSize={communication_step_size}, noSetFMUStatePriorToCurrentPoint={no_set_fmu_state_prior_to_current_point})"
                )
            },
            true,
            // SAFETY: plain values.
            |f, c| unsafe {
                (f.do_step)(
                    c,
                    current_communication_point,
                    communication_step_size,
                    fmi2_bool(no_set_fmu_state_prior_to_current_point),
                )
            },
        )?;
        Ok(match status {
            Status::Warning => StepResult::Warning,
            Status::Discard => StepResult::Discard,
            _ => StepResult::Ok,
        })
    }

    /// `fmi2CancelStep`.
    pub fn cancel_step(&mut self) -> Result<Status, FmiError> {
        // SAFETY: component only.
        self.call(
            |_| "fmi2CancelStep()".into(),
            false,
            |f, c| unsafe { (f.cancel_step)(c) },
        )
    }

    /// `fmi2SetRealInputDerivatives`.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<Status, FmiError> {
        self.check_lengths("fmi2SetRealInputDerivatives", vrs.len(), values.len())?;
        self.check_lengths("fmi2SetRealInputDerivatives", vrs.len(), orders.len())?;
        self.call(
            |fmu| {
                format!(
                    "fmi2SetRealInputDerivatives({}, orders={orders:?}, values={values:?})",
                    fmu.names(Space::Real, vrs)
                )
            },
            false,
            // SAFETY: all slices have vrs.len() elements.
            |f, c| unsafe {
                (f.set_real_input_derivatives)(
                    c,
                    vrs.as_ptr(),
                    vrs.len(),
                    orders.as_ptr(),
                    values.as_ptr(),
                )
            },
        )
    }

    /// `fmi2GetRealOutputDerivatives`.
    pub fn get_real_output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Result<Status, FmiError> {
        self.check_lengths("fmi2GetRealOutputDerivatives", vrs.len(), values.len())?;
        self.check_lengths("fmi2GetRealOutputDerivatives", vrs.len(), orders.len())?;
        self.call(
            |fmu| {
                format!(
                    "fmi2GetRealOutputDerivatives({}, orders={orders:?})",
                    fmu.names(Space::Real, vrs)
                )
            },
            false,
            // SAFETY: all slices have vrs.len() elements.
            |f, c| unsafe {
                (f.get_real_output_derivatives)(
                    c,
                    vrs.as_ptr(),
                    vrs.len(),
                    orders.as_ptr(),
                    values.as_mut_ptr(),
                )
            },
        )
    }

    /// `fmi2GetDirectionalDerivative`: `dv_unknown = J · dv_known` for the partial
    /// derivatives of the unknowns with respect to the knowns.
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Result<Status, FmiError> {
        self.check_lengths("fmi2GetDirectionalDerivative", knowns.len(), dv_known.len())?;
        self.check_lengths(
            "fmi2GetDirectionalDerivative",
            unknowns.len(),
            dv_unknown.len(),
        )?;
        self.call(
            |fmu| {
                format!(
                    "fmi2GetDirectionalDerivative(unknowns=[{}], knowns=[{}])",
                    fmu.names(Space::Real, unknowns),
                    fmu.names(Space::Real, knowns)
                )
            },
            false,
            // SAFETY: lengths checked above.
            |f, c| unsafe {
                (f.get_directional_derivative)(
                    c,
                    unknowns.as_ptr(),
                    unknowns.len(),
                    knowns.as_ptr(),
                    knowns.len(),
                    dv_known.as_ptr(),
                    dv_unknown.as_mut_ptr(),
                )
            },
        )
    }

    /// `fmi2GetStatus`.
    pub fn get_status(&mut self, kind: StatusKind) -> Result<CallStatus, FmiError> {
        let mut value: fmi2Status = 0;
        self.call(
            |_| format!("fmi2GetStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(Status::from_raw(value).map_or(CallStatus::Illegal(value), CallStatus::Status))
    }

    /// `fmi2GetRealStatus`.
    pub fn get_real_status(&mut self, kind: StatusKind) -> Result<f64, FmiError> {
        let mut value = 0.0;
        self.call(
            |_| format!("fmi2GetRealStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_real_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(value)
    }

    /// `fmi2GetIntegerStatus`.
    pub fn get_integer_status(&mut self, kind: StatusKind) -> Result<i32, FmiError> {
        let mut value = 0;
        self.call(
            |_| format!("fmi2GetIntegerStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_integer_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(value)
    }

    /// `fmi2GetBooleanStatus`.
    pub fn get_boolean_status(&mut self, kind: StatusKind) -> Result<bool, FmiError> {
        let mut value = fmi2False;
        self.call(
            |_| format!("fmi2GetBooleanStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_boolean_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(value != fmi2False)
    }

    /// `fmi2GetStringStatus`.
    pub fn get_string_status(&mut self, kind: StatusKind) -> Result<String, FmiError> {
        let mut value: fmi2String = std::ptr::null();
        self.call(
            |_| format!("fmi2GetStringStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_string_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        // SAFETY: NULL or a NUL-terminated string owned by the FMU.
        Ok(unsafe { static_str(value) })
    }

    /// `fmi2GetBooleanStatus(fmi2Terminated)`: whether the FMU asked to end the
    /// simulation (meaningful after `fmi2DoStep` returned `fmi2Discard`).
    pub fn terminated(&mut self) -> Result<bool, FmiError> {
        self.get_boolean_status(StatusKind::Terminated)
    }

    /// `fmi2GetRealStatus(fmi2LastSuccessfulTime)`.
    pub fn last_successful_time(&mut self) -> Result<f64, FmiError> {
        self.get_real_status(StatusKind::LastSuccessfulTime)
    }
}
