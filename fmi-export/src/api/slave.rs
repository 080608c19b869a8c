//! Partial derivatives and the Co-Simulation functions: `fmi2GetDirectionalDerivative`,
//! `fmi2SetRealInputDerivatives`, `fmi2GetRealOutputDerivatives`, `fmi2DoStep`,
//! `fmi2CancelStep` and the five status queries.
//!
//! The `# Safety` sections below that say "see the module documentation" mean the safety
//! section of [`crate::api`], where these functions are re-exported.

use super::frame::{call, slice, slice_mut};
use crate::model::FmuModel;
use crate::state::Function;
use crate::types::*;

/// `fmi2GetDirectionalDerivative`: the model's [`FmuModel::directional_derivative`] when it
/// provides them ([`FmuModel::PROVIDES_DIRECTIONAL_DERIVATIVE`]), else fmi2Error.
///
/// # Safety
/// See the module documentation; the arrays must hold `n_unknown` resp. `n_known` elements.
pub unsafe fn get_directional_derivative<M: FmuModel>(
    c: fmi2Component,
    v_unknown_ref: *const fmi2ValueReference,
    n_unknown: usize,
    v_known_ref: *const fmi2ValueReference,
    n_known: usize,
    dv_known: *const fmi2Real,
    dv_unknown: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetDirectionalDerivative, |inst| {
            if !M::PROVIDES_DIRECTIONAL_DERIVATIVE {
                return Err("directional derivatives are not provided \
                            (providesDirectionalDerivative=\"false\")"
                    .to_owned());
            }
            let unknowns = slice(v_unknown_ref, n_unknown, "vUnknown_ref[]")?;
            let knowns = slice(v_known_ref, n_known, "vKnown_ref[]")?;
            let seed = slice(dv_known, n_known, "dvKnown[]")?;
            let out = slice_mut(dv_unknown, n_unknown, "dvUnknown[]")?;
            inst.directional_derivative(unknowns, knowns, seed, out)
        })
    }
}

/// `fmi2SetRealInputDerivatives`: not supported (`canInterpolateInputs="false"`).
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_real_input_derivatives<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetRealInputDerivatives, |_| {
            Err("input derivatives are not supported (canInterpolateInputs=\"false\")".to_owned())
        })
    }
}

/// `fmi2GetRealOutputDerivatives`: not supported (`maxOutputDerivativeOrder="0"`).
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_real_output_derivatives<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetRealOutputDerivatives, |_| {
            Err("output derivatives are not provided (maxOutputDerivativeOrder=\"0\")".to_owned())
        })
    }
}

/// `fmi2DoStep`: see [`crate::instance::Instance`] for the checks (communication point
/// within `1e-12·max(1,|t|)` of the internal time, `h` finite and positive, stop time).
/// `noSetFMUStatePriorToCurrentPoint` is ignored. Time advances only on fmi2OK.
///
/// # Safety
/// See the module documentation.
pub unsafe fn do_step<M: FmuModel>(
    c: fmi2Component,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
    _no_set_fmu_state_prior_to_current_point: fmi2Boolean,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::DoStep, |inst| {
            inst.do_step(current_communication_point, communication_step_size)
        })
    }
}

/// `fmi2CancelStep`: there is never a step in progress (synchronous stepping only), so
/// this is always an illegal call.
///
/// # Safety
/// See the module documentation.
pub unsafe fn cancel_step<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::CancelStep, |_| {
            Err(
                "asynchronous stepping is not supported (canRunAsynchronuously=\"false\")"
                    .to_owned(),
            )
        })
    }
}

/// `fmi2GetStatus`: no status kind applies to a synchronous FMU → fmi2Discard.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetStatus, |inst| {
            if value.is_null() {
                return Err("the value argument is NULL".to_owned());
            }
            Ok(inst.get_status(kind))
        })
    }
}

/// `fmi2GetRealStatus`: `fmi2LastSuccessfulTime` → end of the last successful step;
/// other kinds → fmi2Discard.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_real_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetRealStatus, |inst| {
            if value.is_null() {
                return Err("the value argument is NULL".to_owned());
            }
            Ok(match inst.get_real_status(kind) {
                Ok(v) => {
                    *value = v;
                    Status::Ok
                }
                Err(s) => s,
            })
        })
    }
}

/// `fmi2GetIntegerStatus`: no Integer status kinds exist → fmi2Discard.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_integer_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetIntegerStatus, |inst| {
            if value.is_null() {
                return Err("the value argument is NULL".to_owned());
            }
            Ok(inst.get_integer_status(kind))
        })
    }
}

/// `fmi2GetBooleanStatus`: `fmi2Terminated` → whether a step was discarded (the slave
/// wants to stop); other kinds → fmi2Discard.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_boolean_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetBooleanStatus, |inst| {
            if value.is_null() {
                return Err("the value argument is NULL".to_owned());
            }
            Ok(match inst.get_boolean_status(kind) {
                Ok(b) => {
                    *value = if b { fmi2True } else { fmi2False };
                    Status::Ok
                }
                Err(s) => s,
            })
        })
    }
}

/// `fmi2GetStringStatus`: no pending step exists → fmi2Discard.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_string_status<M: FmuModel>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetStringStatus, |inst| {
            if value.is_null() {
                return Err("the value argument is NULL".to_owned());
            }
            Ok(inst.get_string_status(kind))
        })
    }
}
