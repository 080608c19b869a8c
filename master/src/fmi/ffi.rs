//! The FMI 2.0 C API as Rust types, and the table of the 34 functions a Co-Simulation FMU
//! exports (25 common + 9 co-simulation), resolved once when the library is loaded.

use std::ffi::{c_char, c_int, c_uint, c_void};

pub type Fmi2Component = *mut c_void;
pub type Fmi2ComponentEnvironment = *mut c_void;
pub type Fmi2FmuState = *mut c_void;
pub type Fmi2ValueReference = c_uint;
pub type Fmi2Real = f64;
pub type Fmi2Integer = c_int;
/// `fmi2Boolean` is a C `int` (`fmi2True` = 1, `fmi2False` = 0).
pub type Fmi2Boolean = c_int;
pub type Fmi2String = *const c_char;
pub type Fmi2Byte = c_char;
/// `fmi2Status` (an enum, passed as `int`).
pub type Fmi2Status = c_int;
/// `fmi2Type`.
pub type Fmi2Type = c_int;
/// `fmi2StatusKind`.
pub type Fmi2StatusKind = c_int;

pub const FMI2_TRUE: Fmi2Boolean = 1;
pub const FMI2_FALSE: Fmi2Boolean = 0;
pub const FMI2_CO_SIMULATION: Fmi2Type = 1;

/// `fmi2CallbackLogger`: variadic, printf-style.
pub type Fmi2CallbackLogger = unsafe extern "C" fn(
    Fmi2ComponentEnvironment,
    Fmi2String,
    Fmi2Status,
    Fmi2String,
    Fmi2String,
    ...
);
pub type Fmi2CallbackAllocateMemory = unsafe extern "C" fn(usize, usize) -> *mut c_void;
pub type Fmi2CallbackFreeMemory = unsafe extern "C" fn(*mut c_void);
pub type Fmi2StepFinished = unsafe extern "C" fn(Fmi2ComponentEnvironment, Fmi2Status);

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct Fmi2CallbackFunctions {
    pub logger: Option<Fmi2CallbackLogger>,
    pub allocate_memory: Option<Fmi2CallbackAllocateMemory>,
    pub free_memory: Option<Fmi2CallbackFreeMemory>,
    pub step_finished: Option<Fmi2StepFinished>,
    pub component_environment: Fmi2ComponentEnvironment,
}

unsafe extern "C" {
    pub fn calloc(count: usize, size: usize) -> *mut c_void;
    pub fn free(pointer: *mut c_void);
}

/// Declares the function table: one field per exported function, named after the C
/// symbol, and a loader that resolves them all (collecting every missing name).
macro_rules! fmi2_functions {
    ($( $field:ident = $symbol:literal : fn($($arg:ty),*) $(-> $ret:ty)? ;)+) => {
        /// Every function of the FMI 2.0 Co-Simulation API, resolved from the library.
        #[allow(non_snake_case)]
        pub struct Fmi2Functions {
            $( pub $field: unsafe extern "C" fn($($arg),*) $(-> $ret)?, )+
        }

        /// The names of the functions in [`Fmi2Functions`].
        pub const FMI2_CS_FUNCTION_NAMES: &[&str] = &[$($symbol),+];

        impl Fmi2Functions {
            /// Resolve every function; `Err` lists the names the library does not export.
            ///
            /// # Safety
            /// The library must be an FMI 2.0 FMU whose exported symbols have the
            /// signatures of the FMI 2.0 headers (what the FMU standard requires).
            pub unsafe fn load(library: &libloading::Library) -> Result<Self, Vec<String>> {
                let mut missing = Vec::new();
                $(
                    let $field = unsafe {
                        library
                            .get::<unsafe extern "C" fn($($arg),*) $(-> $ret)?>(
                                concat!($symbol, "\0").as_bytes(),
                            )
                            .map(|symbol| *symbol)
                    };
                    if $field.is_err() {
                        missing.push($symbol.to_owned());
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
    get_types_platform = "fmi2GetTypesPlatform": fn() -> *const c_char;
    get_version = "fmi2GetVersion": fn() -> *const c_char;
    set_debug_logging = "fmi2SetDebugLogging": fn(Fmi2Component, Fmi2Boolean, usize, *const Fmi2String) -> Fmi2Status;
    instantiate = "fmi2Instantiate": fn(Fmi2String, Fmi2Type, Fmi2String, Fmi2String, *const Fmi2CallbackFunctions, Fmi2Boolean, Fmi2Boolean) -> Fmi2Component;
    free_instance = "fmi2FreeInstance": fn(Fmi2Component);
    setup_experiment = "fmi2SetupExperiment": fn(Fmi2Component, Fmi2Boolean, Fmi2Real, Fmi2Real, Fmi2Boolean, Fmi2Real) -> Fmi2Status;
    enter_initialization_mode = "fmi2EnterInitializationMode": fn(Fmi2Component) -> Fmi2Status;
    exit_initialization_mode = "fmi2ExitInitializationMode": fn(Fmi2Component) -> Fmi2Status;
    terminate = "fmi2Terminate": fn(Fmi2Component) -> Fmi2Status;
    reset = "fmi2Reset": fn(Fmi2Component) -> Fmi2Status;
    get_real = "fmi2GetReal": fn(Fmi2Component, *const Fmi2ValueReference, usize, *mut Fmi2Real) -> Fmi2Status;
    get_integer = "fmi2GetInteger": fn(Fmi2Component, *const Fmi2ValueReference, usize, *mut Fmi2Integer) -> Fmi2Status;
    get_boolean = "fmi2GetBoolean": fn(Fmi2Component, *const Fmi2ValueReference, usize, *mut Fmi2Boolean) -> Fmi2Status;
    get_string = "fmi2GetString": fn(Fmi2Component, *const Fmi2ValueReference, usize, *mut Fmi2String) -> Fmi2Status;
    set_real = "fmi2SetReal": fn(Fmi2Component, *const Fmi2ValueReference, usize, *const Fmi2Real) -> Fmi2Status;
    set_integer = "fmi2SetInteger": fn(Fmi2Component, *const Fmi2ValueReference, usize, *const Fmi2Integer) -> Fmi2Status;
    set_boolean = "fmi2SetBoolean": fn(Fmi2Component, *const Fmi2ValueReference, usize, *const Fmi2Boolean) -> Fmi2Status;
    set_string = "fmi2SetString": fn(Fmi2Component, *const Fmi2ValueReference, usize, *const Fmi2String) -> Fmi2Status;
    get_fmu_state = "fmi2GetFMUstate": fn(Fmi2Component, *mut Fmi2FmuState) -> Fmi2Status;
    set_fmu_state = "fmi2SetFMUstate": fn(Fmi2Component, Fmi2FmuState) -> Fmi2Status;
    free_fmu_state = "fmi2FreeFMUstate": fn(Fmi2Component, *mut Fmi2FmuState) -> Fmi2Status;
    serialized_fmu_state_size = "fmi2SerializedFMUstateSize": fn(Fmi2Component, Fmi2FmuState, *mut usize) -> Fmi2Status;
    serialize_fmu_state = "fmi2SerializeFMUstate": fn(Fmi2Component, Fmi2FmuState, *mut Fmi2Byte, usize) -> Fmi2Status;
    deserialize_fmu_state = "fmi2DeSerializeFMUstate": fn(Fmi2Component, *const Fmi2Byte, usize, *mut Fmi2FmuState) -> Fmi2Status;
    get_directional_derivative = "fmi2GetDirectionalDerivative": fn(Fmi2Component, *const Fmi2ValueReference, usize, *const Fmi2ValueReference, usize, *const Fmi2Real, *mut Fmi2Real) -> Fmi2Status;
    set_real_input_derivatives = "fmi2SetRealInputDerivatives": fn(Fmi2Component, *const Fmi2ValueReference, usize, *const Fmi2Integer, *const Fmi2Real) -> Fmi2Status;
    get_real_output_derivatives = "fmi2GetRealOutputDerivatives": fn(Fmi2Component, *const Fmi2ValueReference, usize, *const Fmi2Integer, *mut Fmi2Real) -> Fmi2Status;
    do_step = "fmi2DoStep": fn(Fmi2Component, Fmi2Real, Fmi2Real, Fmi2Boolean) -> Fmi2Status;
    cancel_step = "fmi2CancelStep": fn(Fmi2Component) -> Fmi2Status;
    get_status = "fmi2GetStatus": fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2Status) -> Fmi2Status;
    get_real_status = "fmi2GetRealStatus": fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2Real) -> Fmi2Status;
    get_integer_status = "fmi2GetIntegerStatus": fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2Integer) -> Fmi2Status;
    get_boolean_status = "fmi2GetBooleanStatus": fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2Boolean) -> Fmi2Status;
    get_string_status = "fmi2GetStringStatus": fn(Fmi2Component, Fmi2StatusKind, *mut Fmi2String) -> Fmi2Status;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_34_functions_are_listed_once() {
        assert_eq!(FMI2_CS_FUNCTION_NAMES.len(), 34);
        let mut names = FMI2_CS_FUNCTION_NAMES.to_vec();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), 34);
    }
}
