//! The life cycle of an instance: `fmi2SetDebugLogging`, `fmi2SetupExperiment`,
//! `fmi2EnterInitializationMode`, `fmi2ExitInitializationMode`, `fmi2Terminate` and
//! `fmi2Reset`.
//!
//! The `# Safety` sections below that say "see the module documentation" mean the safety
//! section of [`crate::api`], where these functions are re-exported.

use super::frame::{call, slice, string};
use crate::model::FmuModel;
use crate::state::Function;
use crate::types::*;

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
