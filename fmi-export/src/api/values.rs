//! Getting and setting variable values: `fmi2GetReal`, `fmi2GetInteger`,
//! `fmi2GetBoolean`, `fmi2GetString` and the four `fmi2Set…`.
//!
//! The `# Safety` sections below that say "see the module documentation" mean the safety
//! section of [`crate::api`], where these functions are re-exported.

use super::frame::{call, slice, slice_mut, string};
use crate::model::FmuModel;
use crate::state::Function;
use crate::types::*;

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
