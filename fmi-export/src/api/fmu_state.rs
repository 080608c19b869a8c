//! FMU states: `fmi2GetFMUstate`, `fmi2SetFMUstate`, `fmi2FreeFMUstate`,
//! `fmi2SerializedFMUstateSize`, `fmi2SerializeFMUstate` and `fmi2DeSerializeFMUstate`
//! (the objects and the byte format are in [`crate::snapshot`]).
//!
//! The `# Safety` sections below that say "see the module documentation" mean the safety
//! section of [`crate::api`], where these functions are re-exported.

use std::ptr;

use super::frame::{call, slice, slice_mut};
use crate::logging::LOG_EVENTS;
use crate::model::FmuModel;
use crate::snapshot::Snapshot;
use crate::state::Function;
use crate::types::*;

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
