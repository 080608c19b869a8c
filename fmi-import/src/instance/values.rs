//! Getting and setting the values of an instance's Real, Integer (and Enumeration),
//! Boolean and String variables.

use super::{fmi2_bool, static_str, Instance, Space};
use crate::error::{FmiError, Status};
use fmi2::first_non_finite;
use fmi2::types::*;
use std::ffi::CString;

impl Instance {
    /// `fmi2SetReal`.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<Status, FmiError> {
        self.check_lengths("fmi2SetReal", vrs.len(), values.len())?;
        self.call(
            |fmu| format!("fmi2SetReal({} = {values:?})", fmu.names(Space::Real, vrs)),
            false,
            // SAFETY: both slices have vrs.len() elements.
            |f, c| unsafe { (f.set_real)(c, vrs.as_ptr(), vrs.len(), values.as_ptr()) },
        )
    }

    /// `fmi2GetReal`. A NaN or infinite value is an error naming the variable.
    pub fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<Status, FmiError> {
        self.check_lengths("fmi2GetReal", vrs.len(), values.len())?;
        let status = self.call(
            |fmu| format!("fmi2GetReal({})", fmu.names(Space::Real, vrs)),
            false,
            // SAFETY: both slices have vrs.len() elements.
            |f, c| unsafe { (f.get_real)(c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr()) },
        )?;
        if let Some(i) = first_non_finite(values) {
            return Err(FmiError::NonFinite {
                fmu: self.fmu.name.clone(),
                call: format!("fmi2GetReal (instance \"{}\")", self.name),
                variable: self.fmu.variable_name(Space::Real, vrs[i]),
                value_reference: vrs[i],
                value: values[i],
                messages: self.sink.take_call_messages(),
            });
        }
        Ok(status)
    }

    /// `fmi2SetInteger` (also for Enumeration variables).
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<Status, FmiError> {
        self.check_lengths("fmi2SetInteger", vrs.len(), values.len())?;
        self.call(
            |fmu| {
                format!(
                    "fmi2SetInteger({} = {values:?})",
                    fmu.names(Space::Integer, vrs)
                )
            },
            false,
            // SAFETY: both slices have vrs.len() elements.
            |f, c| unsafe { (f.set_integer)(c, vrs.as_ptr(), vrs.len(), values.as_ptr()) },
        )
    }

    /// `fmi2GetInteger` (also for Enumeration variables).
    pub fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Result<Status, FmiError> {
        self.check_lengths("fmi2GetInteger", vrs.len(), values.len())?;
        self.call(
            |fmu| format!("fmi2GetInteger({})", fmu.names(Space::Integer, vrs)),
            false,
            // SAFETY: both slices have vrs.len() elements.
            |f, c| unsafe { (f.get_integer)(c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr()) },
        )
    }

    /// `fmi2SetBoolean`.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<Status, FmiError> {
        self.check_lengths("fmi2SetBoolean", vrs.len(), values.len())?;
        let raw: Vec<fmi2Boolean> = values.iter().map(|&b| fmi2_bool(b)).collect();
        self.call(
            |fmu| {
                format!(
                    "fmi2SetBoolean({} = {values:?})",
                    fmu.names(Space::Boolean, vrs)
                )
            },
            false,
            // SAFETY: both slices have vrs.len() elements.
            |f, c| unsafe { (f.set_boolean)(c, vrs.as_ptr(), vrs.len(), raw.as_ptr()) },
        )
    }

    /// `fmi2GetBoolean` (any non-zero `fmi2Boolean` reads as `true`).
    pub fn get_boolean(&mut self, vrs: &[u32], values: &mut [bool]) -> Result<Status, FmiError> {
        self.check_lengths("fmi2GetBoolean", vrs.len(), values.len())?;
        let mut raw = vec![fmi2False; vrs.len()];
        let status = self.call(
            |fmu| format!("fmi2GetBoolean({})", fmu.names(Space::Boolean, vrs)),
            false,
            // SAFETY: both buffers have vrs.len() elements.
            |f, c| unsafe { (f.get_boolean)(c, vrs.as_ptr(), vrs.len(), raw.as_mut_ptr()) },
        )?;
        for (v, r) in values.iter_mut().zip(raw) {
            *v = r != fmi2False;
        }
        Ok(status)
    }

    /// `fmi2SetString`.
    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<Status, FmiError> {
        self.check_lengths("fmi2SetString", vrs.len(), values.len())?;
        let c: Vec<CString> = values
            .iter()
            .map(|s| self.fmu.c_string(s, "String value"))
            .collect::<Result<_, _>>()?;
        let pointers: Vec<fmi2String> = c.iter().map(|s| s.as_ptr()).collect();
        self.call(
            |fmu| {
                format!(
                    "fmi2SetString({} = {values:?})",
                    fmu.names(Space::String, vrs)
                )
            },
            false,
            // SAFETY: pointers into `c`, alive during the call; vrs.len() elements each.
            |f, comp| unsafe { (f.set_string)(comp, vrs.as_ptr(), vrs.len(), pointers.as_ptr()) },
        )
    }

    /// `fmi2GetString` (the strings are copied before the next call can invalidate them).
    pub fn get_string(&mut self, vrs: &[u32]) -> Result<Vec<String>, FmiError> {
        let mut raw: Vec<fmi2String> = vec![std::ptr::null(); vrs.len()];
        self.call(
            |fmu| format!("fmi2GetString({})", fmu.names(Space::String, vrs)),
            false,
            // SAFETY: both buffers have vrs.len() elements.
            |f, c| unsafe { (f.get_string)(c, vrs.as_ptr(), vrs.len(), raw.as_mut_ptr()) },
        )?;
        // SAFETY: the FMU returned NUL-terminated strings valid until its next call.
        Ok(raw.into_iter().map(|p| unsafe { static_str(p) }).collect())
    }
}
