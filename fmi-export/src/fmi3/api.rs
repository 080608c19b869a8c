//! The FMI 3.0 functions as generic Rust functions over the model type; those with an FMI
//! 2.0 twin of the same arguments (FMU states, terminate, reset, …) are the functions of
//! [`crate::api`] themselves, forwarded by [`crate::export_fmi3!`].
//!
//! # Safety
//!
//! As for [`crate::api`]: pointer arguments are trusted as the standard requires of the
//! importer (arrays of the stated length, NUL-terminated strings, an instance returned by
//! `fmi3InstantiateCoSimulation` of the same FMU and not yet freed); NULL is always
//! detected.

use std::ffi::{c_char, c_int, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::ptr;

use fmi3::*;

use super::TIME_VALUE_REFERENCE;
use crate::api::build;
use crate::api::frame::{call, slice, slice_mut, string};
use crate::logging::Logger;
use crate::model::FmuModel;
use crate::state::Function;
use crate::types::Status;

/// `fmi3GetVersion`.
pub fn get_version() -> *const c_char {
    fmi3Version.as_ptr()
}

/// `fmi3InstantiateCoSimulation` (see the module docs of [`crate::fmi3`]): NULL after
/// logging the reason for a NULL logger, a NULL or empty `instanceName`, `eventModeUsed`,
/// a NULL token or resource path, a model that cannot be built from its resources, or a
/// token other than the model's.
///
/// # Safety
/// String arguments must be NULL or NUL-terminated; the logger must stay callable until
/// `fmi3FreeInstance`.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate_co_simulation<M: FmuModel>(
    model_identifier: &'static str,
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    resource_path: fmi3String,
    logging_on: fmi3Boolean,
    event_mode_used: fmi3Boolean,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    let Some(callback) = log_message else {
        return ptr::null_mut();
    };
    catch_unwind(AssertUnwindSafe(|| {
        let name = if instance_name.is_null() {
            String::new()
        } else {
            // SAFETY: non-NULL and NUL-terminated (caller).
            unsafe { CStr::from_ptr(instance_name) }
                .to_string_lossy()
                .into_owned()
        };
        let logger = Logger::new_fmi3(callback, instance_environment, &name, logging_on != 0);
        let refuse = |reason: String| -> fmi3Instance {
            logger.log_status(
                Status::Error,
                &format!("fmi3InstantiateCoSimulation: {reason}"),
            );
            ptr::null_mut()
        };
        if name.is_empty() {
            return refuse("instanceName is NULL or empty".into());
        }
        if event_mode_used != 0 {
            return refuse(format!(
                "eventModeUsed is true, but {model_identifier} has no event mode (hasEventMode=\"false\")"
            ));
        }
        // SAFETY: NULL or NUL-terminated (caller).
        let token = match unsafe { string(instantiation_token, "instantiationToken") } {
            Ok(t) => t.to_owned(),
            Err(e) => return refuse(e),
        };
        // SAFETY: NULL or NUL-terminated (caller).
        let resources = match unsafe { string(resource_path, "resourcePath") } {
            Ok(p) => PathBuf::from(p),
            Err(e) => return refuse(format!("{e}; the FMU needs its resources folder")),
        };
        match build::<M>(model_identifier, name, &token, resources, logger, "fmi3") {
            Some(inst) => Box::into_raw(Box::new(inst)) as fmi3Instance,
            None => ptr::null_mut(),
        }
    }))
    .unwrap_or(ptr::null_mut())
}

/// `fmi3InstantiateModelExchange` and `fmi3InstantiateScheduledExecution`: NULL, after
/// logging that the FMU implements Co-Simulation only.
///
/// # Safety
/// `instance_name` must be NULL or NUL-terminated.
pub unsafe fn instantiate_other(
    model_identifier: &'static str,
    interface: &str,
    instance_name: fmi3String,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    if let Some(callback) = log_message {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: NULL or NUL-terminated (caller).
            let name = unsafe { string(instance_name, "instanceName") }.unwrap_or("");
            Logger::new_fmi3(callback, instance_environment, name, false).log_status(
                Status::Error,
                &format!(
                    "fmi3Instantiate{interface}: {model_identifier} implements Co-Simulation only"
                ),
            );
        }));
    }
    ptr::null_mut()
}

/// `fmi3EnterInitializationMode`: `fmi2SetupExperiment` (start and stop time; the
/// tolerance is unused) then `fmi2EnterInitializationMode`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn enter_initialization_mode<M: FmuModel>(
    c: fmi3Instance,
    tolerance_defined: fmi3Boolean,
    tolerance: fmi3Float64,
    start_time: fmi3Float64,
    stop_time_defined: fmi3Boolean,
    stop_time: fmi3Float64,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        let status = crate::api::setup_experiment::<M>(
            c,
            c_int::from(tolerance_defined != 0),
            tolerance,
            start_time,
            c_int::from(stop_time_defined != 0),
            stop_time,
        );
        if status >= fmi3Error {
            return status;
        }
        crate::api::enter_initialization_mode::<M>(c).max(status)
    }
}

/// `fmi3SetDebugLogging`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_debug_logging<M: FmuModel>(
    c: fmi3Instance,
    logging_on: fmi3Boolean,
    n_categories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        crate::api::set_debug_logging::<M>(
            c,
            c_int::from(logging_on != 0),
            n_categories,
            categories,
        )
    }
}

/// `nValues` equals `nValueReferences`: the FMU has scalar variables only.
fn scalars(nvr: usize, n_values: usize) -> Result<(), String> {
    if nvr == n_values {
        Ok(())
    } else {
        Err(format!(
            "nValues {n_values} differs from nValueReferences {nvr}; the FMU has no array variables"
        ))
    }
}

/// `fmi3GetFloat64`: as `fmi2GetReal`, and [`TIME_VALUE_REFERENCE`] reads the time.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_float64<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::GetReal, |inst| {
            scalars(nvr, n_values)?;
            let vr = slice(vr, nvr, "valueReferences[]")?;
            let values = slice_mut(values, nvr, "values[]")?;
            if !vr.contains(&TIME_VALUE_REFERENCE) {
                return inst.get_real(vr, values);
            }
            for (r, v) in vr.iter().zip(values.iter_mut()) {
                if *r == TIME_VALUE_REFERENCE {
                    *v = inst.time();
                } else {
                    inst.get_real(std::slice::from_ref(r), std::slice::from_mut(v))?;
                }
            }
            Ok(Status::Ok)
        })
    }
}

/// `fmi3SetFloat64`: as `fmi2SetReal`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_float64<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3Float64,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::SetReal, |inst| {
            scalars(nvr, n_values)?;
            inst.set_real(
                slice(vr, nvr, "valueReferences[]")?,
                slice(values, nvr, "values[]")?,
            )
        })
    }
}

/// `fmi3GetInt32`: as `fmi2GetInteger`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_int32<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3Int32,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::GetInteger, |inst| {
            scalars(nvr, n_values)?;
            inst.get_integer(
                slice(vr, nvr, "valueReferences[]")?,
                slice_mut(values, nvr, "values[]")?,
            )
        })
    }
}

/// `fmi3SetInt32`: as `fmi2SetInteger`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_int32<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3Int32,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::SetInteger, |inst| {
            scalars(nvr, n_values)?;
            inst.set_integer(
                slice(vr, nvr, "valueReferences[]")?,
                slice(values, nvr, "values[]")?,
            )
        })
    }
}

/// `fmi3GetBoolean`: as `fmi2GetBoolean`, one byte per value.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_boolean<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::GetBoolean, |inst| {
            scalars(nvr, n_values)?;
            let vr = slice(vr, nvr, "valueReferences[]")?;
            let out = slice_mut(values, nvr, "values[]")?;
            let mut ints = vec![0; nvr];
            let status = inst.get_boolean(vr, &mut ints)?;
            for (o, i) in out.iter_mut().zip(ints) {
                *o = u8::from(i != 0);
            }
            Ok(status)
        })
    }
}

/// `fmi3SetBoolean`: as `fmi2SetBoolean` (any non-zero byte is true).
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_boolean<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3Boolean,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::SetBoolean, |inst| {
            scalars(nvr, n_values)?;
            let vr = slice(vr, nvr, "valueReferences[]")?;
            let bools: Vec<bool> = slice(values, nvr, "values[]")?
                .iter()
                .map(|&b| b != 0)
                .collect();
            inst.set_boolean(vr, &bools)
        })
    }
}

/// `fmi3GetString`: as `fmi2GetString` (the strings stay valid until the next call).
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_string<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3String,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::GetString, |inst| {
            scalars(nvr, n_values)?;
            let vr = slice(vr, nvr, "valueReferences[]")?;
            let out = slice_mut(values, nvr, "values[]")?;
            for (o, s) in out.iter_mut().zip(inst.get_string(vr)?) {
                *o = s.as_ptr();
            }
            Ok(Status::Ok)
        })
    }
}

/// `fmi3SetString`: as `fmi2SetString`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_string<M: FmuModel>(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3String,
    n_values: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::SetString, |inst| {
            scalars(nvr, n_values)?;
            let vr = slice(vr, nvr, "valueReferences[]")?;
            let strings = slice(values, nvr, "values[]")?
                .iter()
                .map(|&p| string(p, "values[]"))
                .collect::<Result<Vec<_>, _>>()?;
            inst.set_string(vr, &strings)
        })
    }
}

/// `fmi3GetDirectionalDerivative`: as `fmi2GetDirectionalDerivative`; `nSeed` must equal
/// `nKnowns` and `nSensitivity` `nUnknowns`.
///
/// # Safety
/// See the module documentation.
#[allow(clippy::too_many_arguments)]
pub unsafe fn get_directional_derivative<M: FmuModel>(
    c: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    n_unknowns: usize,
    knowns: *const fmi3ValueReference,
    n_knowns: usize,
    seed: *const fmi3Float64,
    n_seed: usize,
    sensitivity: *mut fmi3Float64,
    n_sensitivity: usize,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::GetDirectionalDerivative, |inst| {
            if !M::PROVIDES_DIRECTIONAL_DERIVATIVE {
                return Err("directional derivatives are not provided \
                            (providesDirectionalDerivatives=\"false\")"
                    .to_owned());
            }
            if n_seed != n_knowns || n_sensitivity != n_unknowns {
                return Err(format!(
                    "nSeed {n_seed} and nSensitivity {n_sensitivity} must equal nKnowns {n_knowns} and nUnknowns {n_unknowns}; the FMU has no array variables"
                ));
            }
            inst.directional_derivative(
                slice(unknowns, n_unknowns, "unknowns[]")?,
                slice(knowns, n_knowns, "knowns[]")?,
                slice(seed, n_seed, "seed[]")?,
                slice_mut(sensitivity, n_sensitivity, "sensitivity[]")?,
            )
        })
    }
}

/// `fmi3DoStep`: as `fmi2DoStep` (see the module docs of [`crate::fmi3`] for the output
/// arguments, which must not be NULL).
///
/// # Safety
/// See the module documentation; the output arguments must be writable.
#[allow(clippy::too_many_arguments)]
pub unsafe fn do_step<M: FmuModel>(
    c: fmi3Instance,
    t: fmi3Float64,
    h: fmi3Float64,
    _no_set_fmu_state_prior_to_current_point: fmi3Boolean,
    event_handling_needed: *mut fmi3Boolean,
    terminate_simulation: *mut fmi3Boolean,
    early_return: *mut fmi3Boolean,
    last_successful_time: *mut fmi3Float64,
) -> fmi3Status {
    // SAFETY: forwarded contract.
    unsafe {
        call::<M>(c, Function::DoStep, |inst| {
            for (p, what) in [
                (event_handling_needed, "eventHandlingNeeded"),
                (terminate_simulation, "terminateSimulation"),
                (early_return, "earlyReturn"),
            ] {
                if p.is_null() {
                    return Err(format!("{what} is NULL"));
                }
            }
            if last_successful_time.is_null() {
                return Err("lastSuccessfulTime is NULL".into());
            }
            let status = inst.do_step(t, h);
            *event_handling_needed = fmi3False;
            *early_return = fmi3False;
            *last_successful_time = inst.time();
            let end = matches!(status, Ok(Status::Discard)) && inst.frame.terminate_requested;
            *terminate_simulation = u8::from(end);
            status
        })
    }
}
