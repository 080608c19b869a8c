//! `fmi2GetTypesPlatform`, `fmi2GetVersion`, and creating and freeing an instance
//! (`fmi2Instantiate`, `fmi2FreeInstance`).
//!
//! The `# Safety` sections below that say "see the module documentation" mean the safety
//! section of [`crate::api`], where these functions are re-exported.

use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::ptr;

use super::frame::{instance, panic_message, string};
use crate::instance::Instance;
use crate::logging::{Logger, LOG_EVENTS};
use crate::model::FmuModel;
use crate::types::*;
use crate::uri;

/// `fmi2GetTypesPlatform`.
pub fn get_types_platform() -> *const c_char {
    TYPES_PLATFORM.as_ptr()
}

/// `fmi2GetVersion`.
pub fn get_version() -> *const c_char {
    VERSION.as_ptr()
}

/// `fmi2Instantiate`. `model_identifier` is the FMU's modelIdentifier (the macro passes
/// the crate's library name); it is kept for log messages and the serialized-state header.
///
/// Returns NULL (after logging the reason through the logger when there is one) for: NULL
/// `functions` or logger, NULL or empty `instanceName`, `fmuType` other than
/// `fmi2CoSimulation`, NULL `fmuGUID`, NULL or undecodable `fmuResourceLocation`, an error
/// or panic of [`FmuModel::instantiate`], and a GUID different from [`FmuModel::guid`].
/// `visible` is ignored (there is no user interface); `allocateMemory`/`freeMemory` are
/// not used (Rust's allocator is; `canNotUseMemoryManagementFunctions="true"`).
///
/// # Safety
/// String arguments must be NULL or NUL-terminated; `functions` NULL or valid for reads;
/// the logger must stay callable until `fmi2FreeInstance`.
#[allow(clippy::too_many_arguments)]
pub unsafe fn instantiate<M: FmuModel>(
    model_identifier: &'static str,
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    fmu_guid: fmi2String,
    fmu_resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded contract.
        unsafe {
            instantiate_checked::<M>(
                model_identifier,
                instance_name,
                fmu_type,
                fmu_guid,
                fmu_resource_location,
                functions,
                logging_on != fmi2False,
            )
        }
    }))
    .unwrap_or(ptr::null_mut())
}

unsafe fn instantiate_checked<M: FmuModel>(
    model_identifier: &'static str,
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    fmu_guid: fmi2String,
    fmu_resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    logging_on: bool,
) -> fmi2Component {
    if functions.is_null() {
        return ptr::null_mut();
    }
    // SAFETY: non-NULL, readable (caller); copied so the importer's struct may go away.
    let callbacks = unsafe { functions.read() };
    let Some(callback) = callbacks.logger else {
        return ptr::null_mut();
    };
    let name = if instance_name.is_null() {
        String::new()
    } else {
        // SAFETY: non-NULL and NUL-terminated (caller).
        unsafe { CStr::from_ptr(instance_name) }
            .to_string_lossy()
            .into_owned()
    };
    let logger = Logger::new(callback, callbacks.componentEnvironment, &name, logging_on);
    let refuse = |reason: String| -> fmi2Component {
        logger.log_status(Status::Error, &format!("fmi2Instantiate: {reason}"));
        ptr::null_mut()
    };
    if name.is_empty() {
        return refuse("instanceName is NULL or empty".to_owned());
    }
    if fmu_type != fmi2CoSimulation {
        let kind = if fmu_type == fmi2ModelExchange {
            "fmi2ModelExchange"
        } else {
            "an unknown fmuType"
        };
        return refuse(format!(
            "fmuType {fmu_type} ({kind}) is not supported: {model_identifier} implements Co-Simulation only (fmi2CoSimulation = 1)"
        ));
    }
    // SAFETY: NULL or NUL-terminated (caller).
    let given_guid = match unsafe { string(fmu_guid, "fmuGUID") } {
        Ok("") => {
            return refuse(
                "fmuGUID is empty; pass the guid attribute of modelDescription.xml".to_owned(),
            )
        }
        Ok(g) => g.to_owned(),
        Err(e) => return refuse(e),
    };
    // SAFETY: NULL or NUL-terminated (caller).
    let location = match unsafe { string(fmu_resource_location, "fmuResourceLocation") } {
        Ok(l) => l.to_owned(),
        Err(e) => {
            return refuse(format!(
                "{e}; the FMU needs the location of its resources folder"
            ))
        }
    };
    let resources: PathBuf = match uri::resource_path(&location) {
        Ok(p) => p,
        Err(e) => return refuse(e),
    };
    match build::<M>(
        model_identifier,
        name,
        &given_guid,
        resources,
        logger,
        "fmi2",
    ) {
        Some(inst) => Box::into_raw(Box::new(inst)) as fmi2Component,
        None => ptr::null_mut(),
    }
}

/// The instance of `M` built from its resources folder, once its GUID (FMI 3.0: its
/// instantiation token) equals `given`; `None` after logging why not as an error of
/// `{prefix}Instantiate…` (`prefix` is `"fmi2"` or `"fmi3"`).
pub(crate) fn build<M: FmuModel>(
    model_identifier: &'static str,
    name: String,
    given: &str,
    resources: PathBuf,
    logger: Logger,
    prefix: &'static str,
) -> Option<Instance<M>> {
    let (function, token) = match prefix {
        "fmi3" => ("fmi3InstantiateCoSimulation", "instantiationToken"),
        _ => ("fmi2Instantiate", "fmuGUID"),
    };
    let refuse = |reason: String| {
        logger.log_status(Status::Error, &format!("{function}: {reason}"));
        None
    };
    let model = match catch_unwind(AssertUnwindSafe(|| M::instantiate(&resources, &logger))) {
        Ok(Ok(m)) => m,
        Ok(Err(e)) => {
            return refuse(format!(
                "the model could not be built from the resources folder {}: {e}",
                resources.display()
            ))
        }
        Err(payload) => {
            return refuse(format!(
                "panic while building the model: {}",
                panic_message(&*payload)
            ))
        }
    };
    let model_guid = match catch_unwind(AssertUnwindSafe(|| model.guid())) {
        Ok(g) => g,
        Err(payload) => {
            return refuse(format!(
                "panic while computing the model's GUID: {}",
                panic_message(&*payload)
            ))
        }
    };
    if model_guid != given {
        return refuse(format!(
            "GUID mismatch: {token} is '{given}' but this binary with its resources is '{model_guid}' (modelDescription.xml does not belong to this binary/resources)"
        ));
    }
    logger.log(
        Status::Ok,
        LOG_EVENTS,
        &format!(
            "instantiated {model_identifier} (GUID {model_guid}, resources {})",
            resources.display()
        ),
    );
    let mut inst = Instance::new(model_identifier, name, model_guid, resources, logger, model);
    inst.prefix = prefix;
    Some(inst)
}

/// `fmi2FreeInstance`: drops the instance; NULL and unknown pointers are ignored.
///
/// # Safety
/// `c` must be NULL or a component of this FMU that has not been freed.
pub unsafe fn free_instance<M: FmuModel>(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded contract.
        if let Some(inst) = unsafe { instance::<M>(c) } {
            let event = format!("{}FreeInstance", inst.prefix);
            inst.logger.log(Status::Ok, LOG_EVENTS, &event);
            inst.magic = 0;
            // SAFETY: created by Box::into_raw in `instantiate`, not yet freed.
            drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
        }
    }));
}
