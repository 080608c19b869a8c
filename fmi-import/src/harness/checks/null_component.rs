//! Every component-taking function called with a NULL component.

use std::ffi::c_char;
use std::ptr;

use super::expect::status_name;
use super::slave::Ctx;
use super::Checker;
use fmi2::types::*;

pub(super) fn null_component_checks(ck: &mut Checker, ctx: &Ctx) {
    let lib = ctx.lib;
    let n = ptr::null_mut();
    let vr: u32 = ctx.cfg.input_vr;
    let mut real = 0.0f64;
    let mut int: fmi2Integer = 0;
    let mut string: fmi2String = ptr::null();
    let mut state: fmi2FMUstate = ptr::null_mut();
    let mut size = 0usize;
    let mut status: fmi2Status = 0;
    let byte: c_char = 0;
    let mut byte_out: c_char = 0;
    let order: fmi2Integer = 1;
    // SAFETY (all calls): every pointer argument except the component is valid.
    let calls: Vec<(&str, fmi2Status)> = unsafe {
        vec![
            (
                "fmi2SetDebugLogging",
                (lib.set_debug_logging)(n, fmi2True, 0, ptr::null()),
            ),
            (
                "fmi2SetupExperiment",
                (lib.setup_experiment)(n, fmi2False, 0.0, 0.0, fmi2False, 0.0),
            ),
            (
                "fmi2EnterInitializationMode",
                (lib.enter_initialization_mode)(n),
            ),
            (
                "fmi2ExitInitializationMode",
                (lib.exit_initialization_mode)(n),
            ),
            ("fmi2Terminate", (lib.terminate)(n)),
            ("fmi2Reset", (lib.reset)(n)),
            ("fmi2GetReal", (lib.get_real)(n, &vr, 1, &mut real)),
            ("fmi2GetInteger", (lib.get_integer)(n, &vr, 1, &mut int)),
            ("fmi2GetBoolean", (lib.get_boolean)(n, &vr, 1, &mut int)),
            ("fmi2GetString", (lib.get_string)(n, &vr, 1, &mut string)),
            ("fmi2SetReal", (lib.set_real)(n, &vr, 1, &real)),
            ("fmi2SetInteger", (lib.set_integer)(n, &vr, 1, &int)),
            ("fmi2SetBoolean", (lib.set_boolean)(n, &vr, 1, &int)),
            ("fmi2SetString", (lib.set_string)(n, &vr, 1, &c"x".as_ptr())),
            ("fmi2GetFMUstate", (lib.get_fmu_state)(n, &mut state)),
            ("fmi2SetFMUstate", (lib.set_fmu_state)(n, state)),
            ("fmi2FreeFMUstate", (lib.free_fmu_state)(n, &mut state)),
            (
                "fmi2SerializedFMUstateSize",
                (lib.serialized_fmu_state_size)(n, state, &mut size),
            ),
            (
                "fmi2SerializeFMUstate",
                (lib.serialize_fmu_state)(n, state, &mut byte_out, 1),
            ),
            (
                "fmi2DeSerializeFMUstate",
                (lib.de_serialize_fmu_state)(n, &byte, 1, &mut state),
            ),
            (
                "fmi2GetDirectionalDerivative",
                (lib.get_directional_derivative)(n, &vr, 1, &vr, 1, &real, &mut real),
            ),
            (
                "fmi2SetRealInputDerivatives",
                (lib.set_real_input_derivatives)(n, &vr, 1, &order, &real),
            ),
            (
                "fmi2GetRealOutputDerivatives",
                (lib.get_real_output_derivatives)(n, &vr, 1, &order, &mut real),
            ),
            ("fmi2DoStep", (lib.do_step)(n, 0.0, 1e-3, fmi2False)),
            ("fmi2CancelStep", (lib.cancel_step)(n)),
            (
                "fmi2GetStatus",
                (lib.get_status)(n, fmi2DoStepStatus, &mut status),
            ),
            (
                "fmi2GetRealStatus",
                (lib.get_real_status)(n, fmi2LastSuccessfulTime, &mut real),
            ),
            (
                "fmi2GetIntegerStatus",
                (lib.get_integer_status)(n, fmi2DoStepStatus, &mut int),
            ),
            (
                "fmi2GetBooleanStatus",
                (lib.get_boolean_status)(n, fmi2Terminated, &mut int),
            ),
            (
                "fmi2GetStringStatus",
                (lib.get_string_status)(n, fmi2PendingStatus, &mut string),
            ),
        ]
    };
    ck.check("NULL component: every function returns fmi2Error", || {
        let wrong: Vec<String> = calls
            .iter()
            .filter(|(_, s)| *s != fmi2Error)
            .map(|(f, s)| format!("{f} → {}", status_name(*s)))
            .collect();
        if wrong.is_empty() {
            Ok(())
        } else {
            Err(wrong.join(", "))
        }
    });
    ck.check("NULL component: fmi2FreeInstance(NULL) returns", || {
        // SAFETY: NULL must be ignored.
        unsafe { (lib.free_instance)(ptr::null_mut()) };
        Ok(())
    });
}
