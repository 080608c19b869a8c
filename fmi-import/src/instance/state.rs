//! Saved FMU states ([`FmuState`]): `fmi2GetFMUstate`, `fmi2SetFMUstate`,
//! `fmi2FreeFMUstate` and their serialization.

use super::Instance;
use crate::error::{FmiError, Status};
use fmi2::types::*;

/// An FMU state saved by [`Instance::get_fmu_state`]. It belongs to the instance that
/// created or deserialized it; the other methods refuse a state of another instance.
/// Release it with [`Instance::free_fmu_state`] (states not freed are released by the
/// FMU's `fmi2FreeInstance`, as the standard requires of the FMU).
#[derive(Debug)]
pub struct FmuState {
    pointer: fmi2FMUstate,
    instance_id: u64,
}

impl Instance {
    fn check_state(&self, state: &FmuState, call: &str) -> Result<(), FmiError> {
        if state.instance_id == self.id {
            Ok(())
        } else {
            Err(FmiError::Unsupported {
                fmu: self.fmu.name.clone(),
                message: format!(
                    "{call}: the FMU state belongs to another instance than \"{}\"",
                    self.name
                ),
            })
        }
    }

    /// `fmi2GetFMUstate`: save the state into a new [`FmuState`], or overwrite `reuse`.
    pub fn get_fmu_state(&mut self, reuse: Option<FmuState>) -> Result<FmuState, FmiError> {
        let mut pointer: fmi2FMUstate = std::ptr::null_mut();
        if let Some(state) = reuse {
            self.check_state(&state, "fmi2GetFMUstate")?;
            pointer = state.pointer;
        }
        let result = self.call(
            |_| "fmi2GetFMUstate()".into(),
            false,
            // SAFETY: `pointer` is NULL (allocate) or a state of this instance (overwrite).
            |f, c| unsafe { (f.get_fmu_state)(c, &mut pointer) },
        );
        let state = FmuState {
            pointer,
            instance_id: self.id,
        };
        match result {
            Ok(_) => Ok(state),
            Err(e) => {
                if !state.pointer.is_null() {
                    let _ = self.free_fmu_state(state);
                }
                Err(e)
            }
        }
    }

    /// `fmi2SetFMUstate`: restore a saved state.
    pub fn set_fmu_state(&mut self, state: &FmuState) -> Result<Status, FmiError> {
        self.check_state(state, "fmi2SetFMUstate")?;
        let pointer = state.pointer;
        // SAFETY: a state created by this instance and not yet freed (FmuState is not
        // Clone, and free_fmu_state consumes it).
        self.call(
            |_| "fmi2SetFMUstate()".into(),
            false,
            |f, c| unsafe { (f.set_fmu_state)(c, pointer) },
        )
    }

    /// `fmi2FreeFMUstate`.
    pub fn free_fmu_state(&mut self, state: FmuState) -> Result<Status, FmiError> {
        self.check_state(&state, "fmi2FreeFMUstate")?;
        let mut pointer = state.pointer;
        // SAFETY: as in set_fmu_state; the FmuState is consumed.
        self.call(
            |_| "fmi2FreeFMUstate()".into(),
            false,
            |f, c| unsafe { (f.free_fmu_state)(c, &mut pointer) },
        )
    }

    /// `fmi2SerializedFMUstateSize` + `fmi2SerializeFMUstate`.
    pub fn serialize_fmu_state(&mut self, state: &FmuState) -> Result<Vec<u8>, FmiError> {
        self.check_state(state, "fmi2SerializeFMUstate")?;
        let pointer = state.pointer;
        let mut size = 0usize;
        // SAFETY: a live state of this instance; one output value.
        self.call(
            |_| "fmi2SerializedFMUstateSize()".into(),
            false,
            |f, c| unsafe { (f.serialized_fmu_state_size)(c, pointer, &mut size) },
        )?;
        let mut bytes = vec![0u8; size];
        // SAFETY: the buffer has the size the FMU asked for.
        self.call(
            |_| format!("fmi2SerializeFMUstate(size={size})"),
            false,
            |f, c| unsafe {
                (f.serialize_fmu_state)(c, pointer, bytes.as_mut_ptr().cast::<fmi2Byte>(), size)
            },
        )?;
        Ok(bytes)
    }

    /// `fmi2DeSerializeFMUstate`: a new [`FmuState`] of this instance from bytes written
    /// by [`Instance::serialize_fmu_state`] (possibly of another instance of the FMU).
    pub fn deserialize_fmu_state(&mut self, bytes: &[u8]) -> Result<FmuState, FmiError> {
        let mut pointer: fmi2FMUstate = std::ptr::null_mut();
        let result = self.call(
            |_| format!("fmi2DeSerializeFMUstate(size={})", bytes.len()),
            false,
            // SAFETY: the buffer is valid for bytes.len() bytes during the call.
            |f, c| unsafe {
                (f.de_serialize_fmu_state)(
                    c,
                    bytes.as_ptr().cast::<fmi2Byte>(),
                    bytes.len(),
                    &mut pointer,
                )
            },
        );
        let state = FmuState {
            pointer,
            instance_id: self.id,
        };
        match result {
            Ok(_) => Ok(state),
            Err(e) => {
                if !state.pointer.is_null() {
                    let _ = self.free_fmu_state(state);
                }
                Err(e)
            }
        }
    }
}
