//! The life-cycle calls of an instance: debug logging, experiment set-up,
//! initialization, terminate and reset.

use super::{fmi2_bool, Instance};
use crate::error::{FmiError, Status};
use fmi2::types::*;
use std::ffi::CString;

impl Instance {
    /// `fmi2SetDebugLogging`.
    pub fn set_debug_logging(
        &mut self,
        logging_on: bool,
        categories: &[&str],
    ) -> Result<Status, FmiError> {
        let c: Vec<CString> = categories
            .iter()
            .map(|s| self.fmu.c_string(s, "log category"))
            .collect::<Result<_, _>>()?;
        let pointers: Vec<fmi2String> = c.iter().map(|s| s.as_ptr()).collect();
        self.call(
            |_| {
                format!(
                    "fmi2SetDebugLogging(loggingOn={logging_on}, categories=[{}])",
                    categories.join(", ")
                )
            },
            false,
            // SAFETY: pointers into `c`, alive during the call.
            |f, comp| unsafe {
                (f.set_debug_logging)(
                    comp,
                    fmi2_bool(logging_on),
                    pointers.len(),
                    pointers.as_ptr(),
                )
            },
        )
    }

    /// `fmi2SetupExperiment`.
    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<Status, FmiError> {
        self.call(
            |_| {
                format!(
                    "fmi2SetupExperiment(tolerance={}, startTime={start_time}, stopTime={})",
                    tolerance.map_or("undefined".into(), |t| t.to_string()),
                    stop_time.map_or("undefined".into(), |t| t.to_string())
                )
            },
            false,
            // SAFETY: plain values.
            |f, c| unsafe {
                (f.setup_experiment)(
                    c,
                    fmi2_bool(tolerance.is_some()),
                    tolerance.unwrap_or(0.0),
                    start_time,
                    fmi2_bool(stop_time.is_some()),
                    stop_time.unwrap_or(0.0),
                )
            },
        )
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialization_mode(&mut self) -> Result<Status, FmiError> {
        // SAFETY: component only.
        self.call(
            |_| "fmi2EnterInitializationMode()".into(),
            false,
            |f, c| unsafe { (f.enter_initialization_mode)(c) },
        )
    }

    /// `fmi2ExitInitializationMode`.
    pub fn exit_initialization_mode(&mut self) -> Result<Status, FmiError> {
        // SAFETY: component only.
        self.call(
            |_| "fmi2ExitInitializationMode()".into(),
            false,
            |f, c| unsafe { (f.exit_initialization_mode)(c) },
        )
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Result<Status, FmiError> {
        // SAFETY: component only.
        self.call(
            |_| "fmi2Terminate()".into(),
            false,
            |f, c| unsafe { (f.terminate)(c) },
        )
    }

    /// `fmi2Reset`.
    pub fn reset(&mut self) -> Result<Status, FmiError> {
        // SAFETY: component only.
        self.call(
            |_| "fmi2Reset()".into(),
            false,
            |f, c| unsafe { (f.reset)(c) },
        )
    }
}
