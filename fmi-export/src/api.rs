//! The FMI 2.0 functions as generic Rust functions over the model type.
//!
//! [`crate::export_fmi2!`] emits one `extern "C"` symbol per function that forwards to the
//! function of the same name here, so all checking exists once. Each function
//!
//! 1. runs inside `catch_unwind`, so no panic crosses the C boundary: a panic is logged
//!    (`logStatusError`) and reported as `fmi2Error`, the instance moves to `Error`;
//! 2. resolves the component pointer (NULL → `fmi2Error` without dereferencing; see the
//!    safety section);
//! 3. checks the call against the state table ([`crate::state`]): an illegal call is
//!    logged and answered with `fmi2Error`, the instance moves to `Error`;
//! 4. checks pointer/length arguments (a NULL array with `n > 0` → `fmi2Error`);
//! 5. runs the body in [`crate::instance::Instance`]; any `fmi2Error` is logged with the
//!    function name and moves the instance to `Error`.
//!
//! # Ownership of the component pointer
//!
//! `instantiate` boxes an [`Instance`] and returns the raw pointer; the importer owns it
//! until it passes it to `free_instance`, which drops the box. Every other function
//! borrows the instance mutably for the duration of the call (FMI 2.0 forbids calling
//! one instance from several threads at once). Different instances share nothing, so they
//! may be used from different threads.
//!
//! # Safety
//!
//! The functions are `unsafe`: their pointer arguments are trusted as the standard
//! requires of the importer (arrays of the stated length, NUL-terminated strings, a
//! component returned by `instantiate` of the same FMU and not yet freed). NULL is always
//! detected. Beyond that, the first two words of a component or FMU-state object are a
//! magic number and a model-type tag, checked before the object is used; this catches a
//! pointer of another FMU, a state passed as a component or an object freed while its
//! memory is still mapped, but it cannot make an arbitrary pointer safe.

use std::ffi::{c_char, CStr};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::ptr;

use crate::instance::{type_tag, Instance, INSTANCE_MAGIC};
use crate::logging::{Logger, LOG_EVENTS};
use crate::model::FmuModel;
use crate::snapshot::Snapshot;
use crate::state::{Allowed, Function, State};
use crate::types::*;
use crate::uri;

/// The message of a panic payload.
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string panic payload)".to_owned()
    }
}

/// Resolve a component pointer (see the module's safety section).
unsafe fn instance<'a, M: FmuModel>(c: fmi2Component) -> Option<&'a mut Instance<M>> {
    if c.is_null() {
        return None;
    }
    let header = c as *const u64;
    // SAFETY: a non-NULL component points to at least an Instance header (caller).
    let (magic, tag) = unsafe { (header.read_unaligned(), header.add(1).read_unaligned()) };
    if magic != INSTANCE_MAGIC || tag != type_tag::<M>() {
        return None;
    }
    // SAFETY: header matches: a live Instance<M> created by `instantiate`.
    Some(unsafe { &mut *(c as *mut Instance<M>) })
}

impl<M: FmuModel> Instance<M> {
    /// Log `message` as an error of `function` and enter the `Error` state.
    fn fail(&mut self, function: Function, message: &str) {
        self.logger
            .log_status(Status::Error, &format!("{function}: {message}"));
        if self.frame.state != State::Fatal {
            self.frame.state = State::Error;
        }
    }
}

/// The common frame of every function taking a component (steps 1–5 of the module docs).
/// Only the checks and the call of `body` are made for each function; what a refused or
/// failed call reports is in [`refused`], one copy per model, out of the way of the
/// functions' code.
unsafe fn call<M: FmuModel>(
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Instance<M>) -> Result<Status, String>,
) -> fmi2Status {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded contract of the caller.
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
            return Status::Error;
        };
        if !function.is_allowed_in(inst.frame.state) {
            return refused(inst, function, Refusal::State);
        }
        match catch_unwind(AssertUnwindSafe(|| body(&mut *inst))) {
            Ok(Ok(status)) if status < Status::Error => status,
            Ok(Ok(status)) => refused(inst, function, Refusal::Status(status)),
            Ok(Err(message)) => refused(inst, function, Refusal::Message(message)),
            Err(payload) => refused(inst, function, Refusal::Panic(payload)),
        }
    }));
    outcome.unwrap_or(Status::Error).raw()
}

/// Why [`call`] refuses a call.
enum Refusal {
    /// Not allowed in the instance's state.
    State,
    /// The model returned an error or fatal status.
    Status(Status),
    /// The model returned an error message.
    Message(String),
    /// The model panicked.
    Panic(Box<dyn std::any::Any + Send>),
}

/// Logs `why` as an error of `function`, enters the `Error` state and returns the error
/// status.
#[cold]
#[inline(never)]
fn refused<M: FmuModel>(inst: &mut Instance<M>, function: Function, why: Refusal) -> Status {
    let message = match why {
        Refusal::State => format!(
            "illegal call in state {} (allowed in: {})",
            inst.frame.state,
            function.allowed()
        ),
        Refusal::Status(status) => format!("failed with {}", status.name()),
        Refusal::Message(message) => message,
        Refusal::Panic(payload) => format!("panic in the model: {}", panic_message(&*payload)),
    };
    inst.fail(function, &message);
    Status::Error
}

/// `&[T]` from a C array, refusing NULL with `n > 0` and impossible lengths.
unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], String> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL while its length is {n}"));
    }
    if n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} has an impossible length {n}"));
    }
    // SAFETY: non-NULL, length plausible; the caller guarantees n readable elements.
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// `&mut [T]` from a C array (see [`slice`]).
unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], String> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(format!("{what} is NULL while its length is {n}"));
    }
    if n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(format!("{what} has an impossible length {n}"));
    }
    // SAFETY: as in `slice`, writable.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// A `&str` from a NUL-terminated C string.
unsafe fn string<'a>(ptr: *const c_char, what: &str) -> Result<&'a str, String> {
    if ptr.is_null() {
        return Err(format!("{what} is NULL"));
    }
    // SAFETY: non-NULL and NUL-terminated (caller).
    unsafe { CStr::from_ptr(ptr) }
        .to_str()
        .map_err(|_| format!("{what} is not valid UTF-8"))
}

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
    if model_guid != given_guid {
        return refuse(format!(
            "GUID mismatch: fmuGUID is '{given_guid}' but this binary with its resources is '{model_guid}' (modelDescription.xml does not belong to this binary/resources)"
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
    let inst = Instance::new(model_identifier, name, model_guid, resources, logger, model);
    Box::into_raw(Box::new(inst)) as fmi2Component
}

/// `fmi2FreeInstance`: drops the instance; NULL and unknown pointers are ignored.
///
/// # Safety
/// `c` must be NULL or a component of this FMU that has not been freed.
pub unsafe fn free_instance<M: FmuModel>(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: forwarded contract.
        if let Some(inst) = unsafe { instance::<M>(c) } {
            inst.logger.log(Status::Ok, LOG_EVENTS, "fmi2FreeInstance");
            inst.magic = 0;
            // SAFETY: created by Box::into_raw in `instantiate`, not yet freed.
            drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
        }
    }));
}

/// `fmi2SetDebugLogging` (categories: see [`crate::logging`]).
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_debug_logging<M: FmuModel>(
    c: fmi2Component,
    logging_on: fmi2Boolean,
    n_categories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetDebugLogging, |inst| {
            let ptrs = slice(categories, n_categories, "categories[]")?;
            let mut names = Vec::with_capacity(ptrs.len());
            for (i, p) in ptrs.iter().enumerate() {
                names.push(string(*p, &format!("categories[{i}]"))?);
            }
            Ok(inst.set_debug_logging(logging_on != fmi2False, &names))
        })
    }
}

/// `fmi2SetupExperiment`. The tolerance is ignored (the models integrate with fixed
/// schemes).
///
/// # Safety
/// See the module documentation.
pub unsafe fn setup_experiment<M: FmuModel>(
    c: fmi2Component,
    _tolerance_defined: fmi2Boolean,
    _tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetupExperiment, |inst| {
            let stop = (stop_time_defined != fmi2False).then_some(stop_time);
            inst.setup_experiment(start_time, stop)
        })
    }
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn enter_initialization_mode<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::EnterInitializationMode, |i| {
            i.enter_initialization_mode()
        })
    }
}

/// `fmi2ExitInitializationMode`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn exit_initialization_mode<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::ExitInitializationMode, |i| {
            i.exit_initialization_mode()
        })
    }
}

/// `fmi2Terminate`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn terminate<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    unsafe { call::<M>(c, Function::Terminate, |i| i.terminate()) }
}

/// `fmi2Reset`: back to `Instantiated` with the model's [`FmuModel::reset`].
///
/// # Safety
/// See the module documentation.
pub unsafe fn reset<M: FmuModel>(c: fmi2Component) -> fmi2Status {
    unsafe { call::<M>(c, Function::Reset, |i| i.reset()) }
}

/// `fmi2GetReal`: a non-finite value is an error naming the value reference.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_real<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetReal, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice_mut(value, nvr, "value[]")?;
            inst.get_real(vr, value)
        })
    }
}

/// `fmi2GetInteger`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_integer<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetInteger, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice_mut(value, nvr, "value[]")?;
            inst.get_integer(vr, value)
        })
    }
}

/// `fmi2GetBoolean` (writes `fmi2True`/`fmi2False`).
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_boolean<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetBoolean, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice_mut(value, nvr, "value[]")?;
            inst.get_boolean(vr, value)
        })
    }
}

/// `fmi2GetString`: the returned strings stay valid until the next `fmi2GetString` on
/// the same instance or `fmi2FreeInstance`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn get_string<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetString, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice_mut(value, nvr, "value[]")?;
            let strings = inst.get_string(vr)?;
            for (out, s) in value.iter_mut().zip(strings) {
                *out = s.as_ptr();
            }
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SetReal`: non-finite values are refused (fmi2Error naming the value reference and
/// value) before the model sees any of the values; the model gets the [`crate::Phase`].
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_real<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetReal, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice(value, nvr, "value[]")?;
            inst.set_real(vr, value)
        })
    }
}

/// `fmi2SetInteger`.
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_integer<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Integer,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetInteger, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice(value, nvr, "value[]")?;
            inst.set_integer(vr, value)
        })
    }
}

/// `fmi2SetBoolean` (any non-zero value is true).
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_boolean<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Boolean,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetBoolean, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value: Vec<bool> = slice(value, nvr, "value[]")?
                .iter()
                .map(|v| *v != fmi2False)
                .collect();
            inst.set_boolean(vr, &value)
        })
    }
}

/// `fmi2SetString` (NULL entries and non-UTF-8 strings are errors).
///
/// # Safety
/// See the module documentation.
pub unsafe fn set_string<M: FmuModel>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2String,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetString, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let ptrs = slice(value, nvr, "value[]")?;
            let mut values = Vec::with_capacity(nvr);
            for (i, p) in ptrs.iter().enumerate() {
                values.push(string(*p, &format!("value[{i}]"))?);
            }
            inst.set_string(vr, &values)
        })
    }
}

/// `fmi2GetFMUstate`: allocates a snapshot when `*FMUstate` is NULL, else overwrites the
/// snapshot it points to.
///
/// # Safety
/// See the module documentation; `*state` must be NULL or a live snapshot of this FMU.
pub unsafe fn get_fmu_state<M: FmuModel>(c: fmi2Component, state: *mut fmi2FMUstate) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::GetFmuState, |inst| {
            if state.is_null() {
                return Err("the FMUstate argument is NULL".to_owned());
            }
            if (*state).is_null() {
                let snap = Box::new(inst.snapshot());
                inst.logger.log(
                    Status::Ok,
                    LOG_EVENTS,
                    &format!("FMU state saved at t = {}", inst.time()),
                );
                *state = Box::into_raw(snap) as fmi2FMUstate;
            } else {
                let snap = Snapshot::<M>::from_handle(*state, inst.type_tag)?;
                inst.snapshot_into(snap);
            }
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SetFMUstate`: restores machine state, time, stop time and the model.
///
/// # Safety
/// See the module documentation; `state` must be NULL or a live snapshot of this FMU.
pub unsafe fn set_fmu_state<M: FmuModel>(c: fmi2Component, state: fmi2FMUstate) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SetFmuState, |inst| {
            let snap = Snapshot::<M>::from_handle(state, inst.type_tag)?;
            inst.restore(snap);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2FreeFMUstate`: NULL (pointer or pointee) is ignored; sets `*FMUstate` to NULL.
///
/// # Safety
/// See the module documentation; `*state` must be NULL or a live snapshot of this FMU.
pub unsafe fn free_fmu_state<M: FmuModel>(
    c: fmi2Component,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::FreeFmuState, |inst| {
            if state.is_null() || (*state).is_null() {
                return Ok(Status::Ok);
            }
            let snap = Snapshot::<M>::from_handle(*state, inst.type_tag)?;
            snap.invalidate();
            drop(Box::from_raw(snap as *mut Snapshot<M>));
            *state = ptr::null_mut();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SerializedFMUstateSize` (format: [`crate::snapshot`]).
///
/// # Safety
/// See the module documentation.
pub unsafe fn serialized_fmu_state_size<M: FmuModel>(
    c: fmi2Component,
    state: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SerializedFmuStateSize, |inst| {
            if size.is_null() {
                return Err("the size argument is NULL".to_owned());
            }
            let snap = Snapshot::<M>::from_handle(state, inst.type_tag)?;
            *size = inst.serialize(snap).len();
            Ok(Status::Ok)
        })
    }
}

/// `fmi2SerializeFMUstate`: `size` must equal `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// See the module documentation; `serialized_state` must hold `size` writable bytes.
pub unsafe fn serialize_fmu_state<M: FmuModel>(
    c: fmi2Component,
    state: fmi2FMUstate,
    serialized_state: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::SerializeFmuState, |inst| {
            let snap = Snapshot::<M>::from_handle(state, inst.type_tag)?;
            let bytes = inst.serialize(snap);
            if size != bytes.len() {
                return Err(format!(
                    "the buffer size {size} differs from the serialized size {} (see fmi2SerializedFMUstateSize)",
                    bytes.len()
                ));
            }
            let out = slice_mut(serialized_state as *mut u8, size, "serializedState[]")?;
            out.copy_from_slice(&bytes);
            Ok(Status::Ok)
        })
    }
}

/// `fmi2DeSerializeFMUstate(c, bytes, size, *FMUstate)`: like `fmi2GetFMUstate`, allocates
/// when `*FMUstate` is NULL and overwrites otherwise. Foreign or damaged bytes are refused.
///
/// # Safety
/// See the module documentation; `serialized_state` must hold `size` readable bytes and
/// `*state` must be NULL or a live snapshot of this FMU.
pub unsafe fn de_serialize_fmu_state<M: FmuModel>(
    c: fmi2Component,
    serialized_state: *const fmi2Byte,
    size: usize,
    state: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        call::<M>(c, Function::DeSerializeFmuState, |inst| {
            if state.is_null() {
                return Err("the FMUstate argument is NULL".to_owned());
            }
            let bytes = slice(serialized_state as *const u8, size, "serializedState[]")?;
            let (frame, model) = inst.deserialize(bytes)?;
            if (*state).is_null() {
                let snap = Box::new(Snapshot::new(inst.type_tag, frame, model));
                *state = Box::into_raw(snap) as fmi2FMUstate;
            } else {
                let snap = Snapshot::<M>::from_handle(*state, inst.type_tag)?;
                snap.frame = frame;
                snap.model = model;
            }
            Ok(Status::Ok)
        })
    }
}

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

/// The generic functions driven directly (no shared object) with a mock model; the
/// logger is the binding's C shim (a dev-dependency feature).
#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Log, Phase, StepOutcome};
    use fmi2::logger::LogCapture;
    use std::ffi::CString;
    use std::path::Path;

    /// `y = u · t`; panics for `h > 1`, errors for `h > 0.5`.
    #[derive(Clone)]
    struct Mock {
        u: f64,
        t: f64,
    }

    impl FmuModel for Mock {
        fn instantiate(resources: &Path, _log: &dyn Log) -> Result<Self, String> {
            if resources.ends_with("broken") {
                panic!("cannot cope with {}", resources.display());
            }
            Ok(Mock { u: 0.0, t: 0.0 })
        }
        fn guid(&self) -> String {
            "mock-guid".to_owned()
        }
        fn exit_initialization(&mut self) -> Result<(), String> {
            Ok(())
        }
        fn set_real(&mut self, vr: u32, value: f64, _phase: Phase) -> Result<(), String> {
            match vr {
                0 => {
                    self.u = value;
                    Ok(())
                }
                _ => Err(format!("unknown value reference {vr}")),
            }
        }
        fn get_real(&mut self, vr: u32) -> Result<f64, String> {
            match vr {
                1 => Ok(self.u * self.t),
                _ => Err(format!("unknown value reference {vr}")),
            }
        }
        fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, String> {
            assert!(h <= 1.0, "step {h} too large for the mock");
            if h > 0.5 {
                return Err("h > 0.5".to_owned());
            }
            self.t = t + h;
            Ok(StepOutcome::Ok)
        }
        fn reset(&mut self) -> Result<(), String> {
            *self = Mock { u: 0.0, t: 0.0 };
            Ok(())
        }
        fn serialize_state(&self) -> Vec<u8> {
            [self.u, self.t]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect()
        }
        fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), String> {
            let v: Vec<f64> = bytes
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect();
            (self.u, self.t) = (v[0], v[1]);
            Ok(())
        }
    }

    /// A second model type (for cross-FMU pointer checks).
    #[derive(Clone)]
    struct Other(Mock);

    impl FmuModel for Other {
        fn instantiate(resources: &Path, log: &dyn Log) -> Result<Self, String> {
            Mock::instantiate(resources, log).map(Other)
        }
        fn guid(&self) -> String {
            self.0.guid()
        }
        fn exit_initialization(&mut self) -> Result<(), String> {
            Ok(())
        }
        fn set_real(&mut self, vr: u32, value: f64, phase: Phase) -> Result<(), String> {
            self.0.set_real(vr, value, phase)
        }
        fn get_real(&mut self, vr: u32) -> Result<f64, String> {
            self.0.get_real(vr)
        }
        fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, String> {
            self.0.do_step(t, h)
        }
        fn reset(&mut self) -> Result<(), String> {
            self.0.reset()
        }
        fn serialize_state(&self) -> Vec<u8> {
            self.0.serialize_state()
        }
        fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), String> {
            self.0.deserialize_state(bytes)
        }
    }

    fn new<M: FmuModel>(log: &LogCapture, location: &str) -> fmi2Component {
        let callbacks = log.callbacks();
        let loc = CString::new(location).unwrap();
        unsafe {
            instantiate::<M>(
                "mock",
                c"m".as_ptr(),
                fmi2CoSimulation,
                c"mock-guid".as_ptr(),
                loc.as_ptr(),
                &callbacks,
                fmi2False,
                fmi2False,
            )
        }
    }

    fn stepping<M: FmuModel>(log: &LogCapture) -> fmi2Component {
        let c = new::<M>(log, "file:///tmp/resources");
        assert!(!c.is_null());
        unsafe {
            assert_eq!(enter_initialization_mode::<M>(c), fmi2OK);
            assert_eq!(exit_initialization_mode::<M>(c), fmi2OK);
        }
        c
    }

    fn state_of(c: fmi2Component) -> State {
        unsafe { instance::<Mock>(c) }.unwrap().state()
    }

    #[test]
    fn a_panicking_model_gives_fmi2error_and_the_error_state() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        let status = unsafe { do_step::<Mock>(c, 0.0, 2.0, fmi2False) };
        assert_eq!(status, fmi2Error);
        assert_eq!(state_of(c), State::Error);
        let records = log.take();
        assert!(records
            .iter()
            .any(|r| r.is_error() && r.message.contains("panic in the model: step 2 too large")));
        // Reset recovers the instance.
        unsafe {
            assert_eq!(reset::<Mock>(c), fmi2OK);
            assert_eq!(state_of(c), State::Instantiated);
            free_instance::<Mock>(c);
        }
    }

    #[test]
    fn an_empty_guid_is_refused_with_a_logged_reason() {
        let log = LogCapture::new();
        let callbacks = log.callbacks();
        let c = unsafe {
            instantiate::<Mock>(
                "mock",
                c"m".as_ptr(),
                fmi2CoSimulation,
                c"".as_ptr(),
                c"file:///tmp/resources".as_ptr(),
                &callbacks,
                fmi2False,
                fmi2False,
            )
        };
        assert!(c.is_null());
        assert!(log
            .take()
            .iter()
            .any(|r| r.is_error() && r.message.contains("fmuGUID is empty")));
    }

    #[test]
    fn a_panic_while_instantiating_gives_null_and_a_logged_reason() {
        let log = LogCapture::new();
        let c = new::<Mock>(&log, "file:///tmp/broken");
        assert!(c.is_null());
        assert!(log
            .take()
            .iter()
            .any(|r| r.is_error() && r.message.contains("panic while building the model")));
    }

    #[test]
    fn model_errors_and_illegal_calls_move_to_error() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        unsafe {
            assert_eq!(do_step::<Mock>(c, 0.0, 0.75, fmi2False), fmi2Error);
            assert_eq!(state_of(c), State::Error);
            let r = log.take();
            assert!(r.iter().any(|r| r.message == "fmi2DoStep: step from t = 0 by h = 0.75 failed: h > 0.5"), "{r:?}");
            // Time did not advance; in Error, GetReal still answers (debugging only).
            let mut y = f64::NAN;
            assert_eq!(get_real::<Mock>(c, &1, 1, &mut y), fmi2OK);
            assert_eq!(y, 0.0);
            assert_eq!(do_step::<Mock>(c, 0.0, 0.1, fmi2False), fmi2Error);
            assert!(log.take()[0]
                .message
                .contains("illegal call in state Error"));
            free_instance::<Mock>(c);
        }
    }

    #[test]
    fn time_tolerance_is_relative() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        unsafe {
            assert_eq!(do_step::<Mock>(c, 0.0, 0.5, fmi2False), fmi2OK);
            // 0.5 · (1 + 5e-13) is within 1e-12·max(1, 0.5) of 0.5.
            assert_eq!(
                do_step::<Mock>(c, 0.5 * (1.0 + 5e-13), 0.5, fmi2False),
                fmi2OK
            );
            let mut t = 0.0;
            assert_eq!(
                get_real_status::<Mock>(c, fmi2LastSuccessfulTime, &mut t),
                fmi2OK
            );
            assert_eq!(t, 0.5 * (1.0 + 5e-13) + 0.5);
            assert_eq!(do_step::<Mock>(c, t + 2e-12, 0.5, fmi2False), fmi2Error);
            free_instance::<Mock>(c);
        }
    }

    #[test]
    fn pointers_of_another_fmu_are_refused() {
        let log = LogCapture::new();
        let mock = stepping::<Mock>(&log);
        let other = stepping::<Other>(&log);
        unsafe {
            // A component of another model type is not dereferenced as this one.
            assert_eq!(do_step::<Mock>(other, 0.0, 0.1, fmi2False), fmi2Error);
            assert_eq!(do_step::<Other>(other, 0.0, 0.1, fmi2False), fmi2OK);
            // An FMU state of another model type is refused with a message.
            let mut s: fmi2FMUstate = ptr::null_mut();
            assert_eq!(get_fmu_state::<Other>(other, &mut s), fmi2OK);
            assert_eq!(set_fmu_state::<Mock>(mock, s), fmi2Error);
            assert!(log
                .take()
                .iter()
                .any(|r| r.message.contains("different FMU")));
            // A component passed as an FMU state is refused too.
            assert_eq!(set_fmu_state::<Other>(other, mock), fmi2Error);
            assert_eq!(free_fmu_state::<Other>(mock, &mut s), fmi2Error);
            let mut s2 = s;
            // `other` is in Error now (the refused SetFMUstate); freeing is still allowed.
            assert_eq!(free_fmu_state::<Other>(other, &mut s2), fmi2OK);
            assert!(s2.is_null());
            free_instance::<Mock>(mock);
            free_instance::<Other>(other);
        }
    }

    #[test]
    fn de_serialize_overwrites_an_existing_state() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        unsafe {
            assert_eq!(set_real::<Mock>(c, &0, 1, &2.0), fmi2OK);
            assert_eq!(do_step::<Mock>(c, 0.0, 0.25, fmi2False), fmi2OK);
            let mut s: fmi2FMUstate = ptr::null_mut();
            assert_eq!(get_fmu_state::<Mock>(c, &mut s), fmi2OK);
            let mut n = 0;
            assert_eq!(serialized_fmu_state_size::<Mock>(c, s, &mut n), fmi2OK);
            let mut bytes = vec![0 as fmi2Byte; n];
            assert_eq!(
                serialize_fmu_state::<Mock>(c, s, bytes.as_mut_ptr(), n),
                fmi2OK
            );
            assert_eq!(do_step::<Mock>(c, 0.25, 0.25, fmi2False), fmi2OK);
            let mut later: fmi2FMUstate = ptr::null_mut();
            assert_eq!(get_fmu_state::<Mock>(c, &mut later), fmi2OK);
            let kept = later;
            assert_eq!(
                de_serialize_fmu_state::<Mock>(c, bytes.as_ptr(), n, &mut later),
                fmi2OK
            );
            assert_eq!(later, kept, "overwritten in place");
            assert_eq!(set_fmu_state::<Mock>(c, later), fmi2OK);
            let mut y = 0.0;
            assert_eq!(get_real::<Mock>(c, &1, 1, &mut y), fmi2OK);
            assert_eq!(y, 2.0 * 0.25);
            free_fmu_state::<Mock>(c, &mut s);
            free_fmu_state::<Mock>(c, &mut later);
            free_instance::<Mock>(c);
        }
    }
}
