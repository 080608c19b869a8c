//! [`export_fmi2!`](crate::export_fmi2): the 34 C symbols of an FMI 2.0 Co-Simulation FMU.

/// Emit the 34 FMI 2.0 functions (25 common + 9 Co-Simulation) for a model type, each as
/// `#[no_mangle] pub unsafe extern "C" fn fmi2…` with the exact `fmi2Functions.h`
/// signature, forwarding to the generic function of the same name in [`crate::api`].
///
/// Invoke it once in the FMU's `cdylib` crate:
///
/// ```no_run
/// use std::path::Path;
/// use fmi_export::{FmuModel, Log, ModelError, Phase, StepOutcome};
///
/// /// `y = ∫ u dt`
/// #[derive(Clone)]
/// pub struct Integrator {
///     u: f64,
///     y: f64,
/// }
///
/// impl FmuModel for Integrator {
///     fn instantiate(_resources: &Path, _log: &dyn Log) -> Result<Self, ModelError> {
///         Ok(Integrator { u: 0.0, y: 0.0 })
///     }
///     fn guid(&self) -> String {
///         fmi_export::guid("integrator", "1", b"")
///     }
///     fn exit_initialization(&mut self) -> Result<(), ModelError> {
///         Ok(())
///     }
///     fn set_real(&mut self, vr: u32, value: f64, _phase: Phase) -> Result<(), ModelError> {
///         match vr {
///             0 => {
///                 self.u = value;
///                 Ok(())
///             }
///             _ => Err(ModelError::UnknownVariable { kind: "Real", vr }),
///         }
///     }
///     fn get_real(&mut self, vr: u32) -> Result<f64, ModelError> {
///         match vr {
///             0 => Ok(self.u),
///             1 => Ok(self.y),
///             _ => Err(ModelError::UnknownVariable { kind: "Real", vr }),
///         }
///     }
///     fn do_step(&mut self, _t: f64, h: f64) -> Result<StepOutcome, ModelError> {
///         self.y += self.u * h;
///         Ok(StepOutcome::Ok)
///     }
///     fn reset(&mut self) -> Result<(), ModelError> {
///         *self = Integrator { u: 0.0, y: 0.0 };
///         Ok(())
///     }
///     fn serialize_state(&self) -> Vec<u8> {
///         [self.u, self.y].iter().flat_map(|v| v.to_le_bytes()).collect()
///     }
///     fn deserialize_state(&mut self, b: &[u8]) -> Result<(), ModelError> {
///         let f = |i: usize| b.get(8 * i..8 * i + 8).map(|s| f64::from_le_bytes(s.try_into().unwrap()));
///         (self.u, self.y) = (f(0).ok_or("short state")?, f(1).ok_or("short state")?);
///         Ok(())
///     }
/// }
///
/// fmi_export::export_fmi2!(Integrator, "integrator");
/// # fn main() {}
/// ```
///
/// The model identifier defaults to the library's crate name (`[lib] name`), which is
/// also the shared object's file stem inside the FMU (`binaries/linux64/<name>.so`) and
/// must equal `modelIdentifier` in `modelDescription.xml`. Give it explicitly with
/// `export_fmi2!(Bridge, "bridge")` if that is not the case.
///
/// The symbols are unprefixed (a binary FMU, not a source FMU), so one shared object can
/// export one model. The FMU crate must not set `panic = "abort"`: the plumbing turns a
/// model panic into `fmi2Error` with `catch_unwind`.
#[macro_export]
macro_rules! export_fmi2 {
    ($model:ty) => {
        $crate::export_fmi2!($model, ::core::env!("CARGO_CRATE_NAME"));
    };
    ($model:ty, $model_identifier:expr) => {
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        const _: () = {
            use ::std::ffi::c_char;
            use $crate::api as __api;
            use $crate::types::{
                fmi2Boolean, fmi2Byte, fmi2CallbackFunctions, fmi2Component, fmi2FMUstate,
                fmi2Integer, fmi2Real, fmi2Status, fmi2StatusKind, fmi2String, fmi2Type,
                fmi2ValueReference,
            };

            const __MODEL_IDENTIFIER: &str = $model_identifier;

            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
                __api::get_types_platform()
            }

            #[unsafe(no_mangle)]
            pub extern "C" fn fmi2GetVersion() -> *const c_char {
                __api::get_version()
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: fmi2Component,
                logging_on: fmi2Boolean,
                n_categories: usize,
                categories: *const fmi2String,
            ) -> fmi2Status {
                unsafe {
                    __api::set_debug_logging::<$model>(c, logging_on, n_categories, categories)
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Instantiate(
                instance_name: fmi2String,
                fmu_type: fmi2Type,
                fmu_guid: fmi2String,
                fmu_resource_location: fmi2String,
                functions: *const fmi2CallbackFunctions,
                visible: fmi2Boolean,
                logging_on: fmi2Boolean,
            ) -> fmi2Component {
                unsafe {
                    __api::instantiate::<$model>(
                        __MODEL_IDENTIFIER,
                        instance_name,
                        fmu_type,
                        fmu_guid,
                        fmu_resource_location,
                        functions,
                        visible,
                        logging_on,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
                unsafe { __api::free_instance::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: fmi2Component,
                tolerance_defined: fmi2Boolean,
                tolerance: fmi2Real,
                start_time: fmi2Real,
                stop_time_defined: fmi2Boolean,
                stop_time: fmi2Real,
            ) -> fmi2Status {
                unsafe {
                    __api::setup_experiment::<$model>(
                        c,
                        tolerance_defined,
                        tolerance,
                        start_time,
                        stop_time_defined,
                        stop_time,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
                unsafe { __api::enter_initialization_mode::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
                unsafe { __api::exit_initialization_mode::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
                unsafe { __api::terminate::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
                unsafe { __api::reset::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetReal(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe { __api::get_real::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Integer,
            ) -> fmi2Status {
                unsafe { __api::get_integer::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Boolean,
            ) -> fmi2Status {
                unsafe { __api::get_boolean::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetString(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2String,
            ) -> fmi2Status {
                unsafe { __api::get_string::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetReal(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Real,
            ) -> fmi2Status {
                unsafe { __api::set_real::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Integer,
            ) -> fmi2Status {
                unsafe { __api::set_integer::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Boolean,
            ) -> fmi2Status {
                unsafe { __api::set_boolean::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetString(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2String,
            ) -> fmi2Status {
                unsafe { __api::set_string::<$model>(c, vr, nvr, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetFMUstate(
                c: fmi2Component,
                state: *mut fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { __api::get_fmu_state::<$model>(c, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetFMUstate(
                c: fmi2Component,
                state: fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { __api::set_fmu_state::<$model>(c, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2FreeFMUstate(
                c: fmi2Component,
                state: *mut fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { __api::free_fmu_state::<$model>(c, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: fmi2Component,
                state: fmi2FMUstate,
                size: *mut usize,
            ) -> fmi2Status {
                unsafe { __api::serialized_fmu_state_size::<$model>(c, state, size) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: fmi2Component,
                state: fmi2FMUstate,
                serialized_state: *mut fmi2Byte,
                size: usize,
            ) -> fmi2Status {
                unsafe { __api::serialize_fmu_state::<$model>(c, state, serialized_state, size) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: fmi2Component,
                serialized_state: *const fmi2Byte,
                size: usize,
                state: *mut fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { __api::de_serialize_fmu_state::<$model>(c, serialized_state, size, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: fmi2Component,
                v_unknown_ref: *const fmi2ValueReference,
                n_unknown: usize,
                v_known_ref: *const fmi2ValueReference,
                n_known: usize,
                dv_known: *const fmi2Real,
                dv_unknown: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe {
                    __api::get_directional_derivative::<$model>(
                        c,
                        v_unknown_ref,
                        n_unknown,
                        v_known_ref,
                        n_known,
                        dv_known,
                        dv_unknown,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: fmi2Component,
                _vr: *const fmi2ValueReference,
                _nvr: usize,
                _order: *const fmi2Integer,
                _value: *const fmi2Real,
            ) -> fmi2Status {
                unsafe { __api::set_real_input_derivatives::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: fmi2Component,
                _vr: *const fmi2ValueReference,
                _nvr: usize,
                _order: *const fmi2Integer,
                _value: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe { __api::get_real_output_derivatives::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2DoStep(
                c: fmi2Component,
                current_communication_point: fmi2Real,
                communication_step_size: fmi2Real,
                no_set_fmu_state_prior_to_current_point: fmi2Boolean,
            ) -> fmi2Status {
                unsafe {
                    __api::do_step::<$model>(
                        c,
                        current_communication_point,
                        communication_step_size,
                        no_set_fmu_state_prior_to_current_point,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
                unsafe { __api::cancel_step::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Status,
            ) -> fmi2Status {
                unsafe { __api::get_status::<$model>(c, kind, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe { __api::get_real_status::<$model>(c, kind, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Integer,
            ) -> fmi2Status {
                unsafe { __api::get_integer_status::<$model>(c, kind, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Boolean,
            ) -> fmi2Status {
                unsafe { __api::get_boolean_status::<$model>(c, kind, value) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2String,
            ) -> fmi2Status {
                unsafe { __api::get_string_status::<$model>(c, kind, value) }
            }

            // The signatures above are exactly the fmi2FunctionTypes.h typedefs.
            const _: () = {
                use $crate::functions::*;
                const _: fmi2GetTypesPlatformTYPE = fmi2GetTypesPlatform;
                const _: fmi2GetVersionTYPE = fmi2GetVersion;
                const _: fmi2SetDebugLoggingTYPE = fmi2SetDebugLogging;
                const _: fmi2InstantiateTYPE = fmi2Instantiate;
                const _: fmi2FreeInstanceTYPE = fmi2FreeInstance;
                const _: fmi2SetupExperimentTYPE = fmi2SetupExperiment;
                const _: fmi2EnterInitializationModeTYPE = fmi2EnterInitializationMode;
                const _: fmi2ExitInitializationModeTYPE = fmi2ExitInitializationMode;
                const _: fmi2TerminateTYPE = fmi2Terminate;
                const _: fmi2ResetTYPE = fmi2Reset;
                const _: fmi2GetRealTYPE = fmi2GetReal;
                const _: fmi2GetIntegerTYPE = fmi2GetInteger;
                const _: fmi2GetBooleanTYPE = fmi2GetBoolean;
                const _: fmi2GetStringTYPE = fmi2GetString;
                const _: fmi2SetRealTYPE = fmi2SetReal;
                const _: fmi2SetIntegerTYPE = fmi2SetInteger;
                const _: fmi2SetBooleanTYPE = fmi2SetBoolean;
                const _: fmi2SetStringTYPE = fmi2SetString;
                const _: fmi2GetFMUstateTYPE = fmi2GetFMUstate;
                const _: fmi2SetFMUstateTYPE = fmi2SetFMUstate;
                const _: fmi2FreeFMUstateTYPE = fmi2FreeFMUstate;
                const _: fmi2SerializedFMUstateSizeTYPE = fmi2SerializedFMUstateSize;
                const _: fmi2SerializeFMUstateTYPE = fmi2SerializeFMUstate;
                const _: fmi2DeSerializeFMUstateTYPE = fmi2DeSerializeFMUstate;
                const _: fmi2GetDirectionalDerivativeTYPE = fmi2GetDirectionalDerivative;
                const _: fmi2SetRealInputDerivativesTYPE = fmi2SetRealInputDerivatives;
                const _: fmi2GetRealOutputDerivativesTYPE = fmi2GetRealOutputDerivatives;
                const _: fmi2DoStepTYPE = fmi2DoStep;
                const _: fmi2CancelStepTYPE = fmi2CancelStep;
                const _: fmi2GetStatusTYPE = fmi2GetStatus;
                const _: fmi2GetRealStatusTYPE = fmi2GetRealStatus;
                const _: fmi2GetIntegerStatusTYPE = fmi2GetIntegerStatus;
                const _: fmi2GetBooleanStatusTYPE = fmi2GetBooleanStatus;
                const _: fmi2GetStringStatusTYPE = fmi2GetStringStatus;
            };
        };
    };
}
