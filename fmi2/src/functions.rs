//! The 34 functions of the FMI 2.0 Co-Simulation API (25 common + 9 Co-Simulation), listed
//! once.
//!
//! From the one list in this file the macro below generates
//!
//! * [`Function`], an enum naming each function, with [`Function::ALL`] and
//!   [`Function::symbol`] (the exported C name);
//! * the `fmi2…TYPE` function-pointer typedefs of `fmi2FunctionTypes.h`, which the
//!   exporter checks its symbols against;
//! * [`Functions`], the table of resolved pointers an importer calls through, and (feature
//!   `load`) [`Functions::load`], which resolves all of them from a shared object and
//!   names every missing symbol at once.

#![allow(non_camel_case_types)]

use crate::types::*;
use std::ffi::c_char;

macro_rules! fmi2_functions {
    ($( $variant:ident, $field:ident, $typedef:ident = $symbol:literal : fn($($arg:ty),*) $(-> $ret:ty)? ;)+) => {
        $(
            #[doc = concat!("`", $symbol, "` as in `fmi2FunctionTypes.h`.")]
            pub type $typedef = unsafe extern "C" fn($($arg),*) $(-> $ret)?;
        )+

        /// One of the 34 FMI 2.0 Co-Simulation functions.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Function {
            $( #[doc = concat!("`", $symbol, "`")] $variant, )+
        }

        impl Function {
            /// All 34 functions, in the order of the standard's headers.
            pub const ALL: [Function; 34] = [$(Function::$variant),+];

            /// The exported C symbol name.
            pub const fn symbol(self) -> &'static str {
                match self {
                    $( Function::$variant => $symbol, )+
                }
            }
        }

        /// Every function of the FMI 2.0 Co-Simulation API, resolved from a library.
        #[derive(Clone, Copy)]
        pub struct Functions {
            $( #[doc = concat!("`", $symbol, "`")] pub $field: $typedef, )+
        }

        #[cfg(feature = "load")]
        impl Functions {
            /// Resolve every function; `Err` lists the names the library does not export.
            ///
            /// # Safety
            /// The library must be an FMI 2.0 FMU whose exported symbols have the
            /// signatures of the FMI 2.0 headers (what the standard requires). The
            /// pointers must not be called after the library is unloaded.
            pub unsafe fn load(library: &libloading::Library) -> Result<Self, Vec<&'static str>> {
                let mut missing = Vec::new();
                $(
                    // SAFETY: the symbol's type is its fmi2 typedef (contract above).
                    let $field = unsafe {
                        library
                            .get::<$typedef>(concat!($symbol, "\0").as_bytes())
                            .map(|symbol| *symbol)
                    };
                    if $field.is_err() {
                        missing.push($symbol);
                    }
                )+
                if !missing.is_empty() {
                    return Err(missing);
                }
                Ok(Self { $( $field: $field.expect("checked above"), )+ })
            }
        }
    };
}

fmi2_functions! {
    GetTypesPlatform, get_types_platform, fmi2GetTypesPlatformTYPE = "fmi2GetTypesPlatform": fn() -> *const c_char;
    GetVersion, get_version, fmi2GetVersionTYPE = "fmi2GetVersion": fn() -> *const c_char;
    SetDebugLogging, set_debug_logging, fmi2SetDebugLoggingTYPE = "fmi2SetDebugLogging": fn(fmi2Component, fmi2Boolean, usize, *const fmi2String) -> fmi2Status;
    Instantiate, instantiate, fmi2InstantiateTYPE = "fmi2Instantiate": fn(fmi2String, fmi2Type, fmi2String, fmi2String, *const fmi2CallbackFunctions, fmi2Boolean, fmi2Boolean) -> fmi2Component;
    FreeInstance, free_instance, fmi2FreeInstanceTYPE = "fmi2FreeInstance": fn(fmi2Component);
    SetupExperiment, setup_experiment, fmi2SetupExperimentTYPE = "fmi2SetupExperiment": fn(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean, fmi2Real) -> fmi2Status;
    EnterInitializationMode, enter_initialization_mode, fmi2EnterInitializationModeTYPE = "fmi2EnterInitializationMode": fn(fmi2Component) -> fmi2Status;
    ExitInitializationMode, exit_initialization_mode, fmi2ExitInitializationModeTYPE = "fmi2ExitInitializationMode": fn(fmi2Component) -> fmi2Status;
    Terminate, terminate, fmi2TerminateTYPE = "fmi2Terminate": fn(fmi2Component) -> fmi2Status;
    Reset, reset, fmi2ResetTYPE = "fmi2Reset": fn(fmi2Component) -> fmi2Status;
    GetReal, get_real, fmi2GetRealTYPE = "fmi2GetReal": fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Real) -> fmi2Status;
    GetInteger, get_integer, fmi2GetIntegerTYPE = "fmi2GetInteger": fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Integer) -> fmi2Status;
    GetBoolean, get_boolean, fmi2GetBooleanTYPE = "fmi2GetBoolean": fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Boolean) -> fmi2Status;
    GetString, get_string, fmi2GetStringTYPE = "fmi2GetString": fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2String) -> fmi2Status;
    SetReal, set_real, fmi2SetRealTYPE = "fmi2SetReal": fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Real) -> fmi2Status;
    SetInteger, set_integer, fmi2SetIntegerTYPE = "fmi2SetInteger": fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer) -> fmi2Status;
    SetBoolean, set_boolean, fmi2SetBooleanTYPE = "fmi2SetBoolean": fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Boolean) -> fmi2Status;
    SetString, set_string, fmi2SetStringTYPE = "fmi2SetString": fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2String) -> fmi2Status;
    GetFmuState, get_fmu_state, fmi2GetFMUstateTYPE = "fmi2GetFMUstate": fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status;
    SetFmuState, set_fmu_state, fmi2SetFMUstateTYPE = "fmi2SetFMUstate": fn(fmi2Component, fmi2FMUstate) -> fmi2Status;
    FreeFmuState, free_fmu_state, fmi2FreeFMUstateTYPE = "fmi2FreeFMUstate": fn(fmi2Component, *mut fmi2FMUstate) -> fmi2Status;
    SerializedFmuStateSize, serialized_fmu_state_size, fmi2SerializedFMUstateSizeTYPE = "fmi2SerializedFMUstateSize": fn(fmi2Component, fmi2FMUstate, *mut usize) -> fmi2Status;
    SerializeFmuState, serialize_fmu_state, fmi2SerializeFMUstateTYPE = "fmi2SerializeFMUstate": fn(fmi2Component, fmi2FMUstate, *mut fmi2Byte, usize) -> fmi2Status;
    DeSerializeFmuState, de_serialize_fmu_state, fmi2DeSerializeFMUstateTYPE = "fmi2DeSerializeFMUstate": fn(fmi2Component, *const fmi2Byte, usize, *mut fmi2FMUstate) -> fmi2Status;
    GetDirectionalDerivative, get_directional_derivative, fmi2GetDirectionalDerivativeTYPE = "fmi2GetDirectionalDerivative": fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2ValueReference, usize, *const fmi2Real, *mut fmi2Real) -> fmi2Status;
    SetRealInputDerivatives, set_real_input_derivatives, fmi2SetRealInputDerivativesTYPE = "fmi2SetRealInputDerivatives": fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer, *const fmi2Real) -> fmi2Status;
    GetRealOutputDerivatives, get_real_output_derivatives, fmi2GetRealOutputDerivativesTYPE = "fmi2GetRealOutputDerivatives": fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Integer, *mut fmi2Real) -> fmi2Status;
    DoStep, do_step, fmi2DoStepTYPE = "fmi2DoStep": fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status;
    CancelStep, cancel_step, fmi2CancelStepTYPE = "fmi2CancelStep": fn(fmi2Component) -> fmi2Status;
    GetStatus, get_status, fmi2GetStatusTYPE = "fmi2GetStatus": fn(fmi2Component, fmi2StatusKind, *mut fmi2Status) -> fmi2Status;
    GetRealStatus, get_real_status, fmi2GetRealStatusTYPE = "fmi2GetRealStatus": fn(fmi2Component, fmi2StatusKind, *mut fmi2Real) -> fmi2Status;
    GetIntegerStatus, get_integer_status, fmi2GetIntegerStatusTYPE = "fmi2GetIntegerStatus": fn(fmi2Component, fmi2StatusKind, *mut fmi2Integer) -> fmi2Status;
    GetBooleanStatus, get_boolean_status, fmi2GetBooleanStatusTYPE = "fmi2GetBooleanStatus": fn(fmi2Component, fmi2StatusKind, *mut fmi2Boolean) -> fmi2Status;
    GetStringStatus, get_string_status, fmi2GetStringStatusTYPE = "fmi2GetStringStatus": fn(fmi2Component, fmi2StatusKind, *mut fmi2String) -> fmi2Status;
}

impl std::fmt::Display for Function {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.symbol())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_34_symbols_are_distinct_fmi2_names() {
        let mut names: Vec<&str> = Function::ALL.iter().map(|f| f.symbol()).collect();
        assert!(names.iter().all(|n| n.starts_with("fmi2")));
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), 34);
    }
}
