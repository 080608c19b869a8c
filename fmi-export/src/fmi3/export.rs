//! [`export_fmi3!`](crate::export_fmi3): every C symbol of `fmi3Functions.h` for an FMI
//! 3.0 Co-Simulation FMU.

/// Emit every FMI 3.0 function (the names of [`fmi3::FUNCTION_NAMES`]) for a model type,
/// each as `#[no_mangle] pub unsafe extern "C" fn fmi3…` with the `fmi3FunctionTypes.h`
/// signature, forwarding to [`crate::fmi3::api`] or, for the FMU-state functions and
/// those without FMI 3.0 arguments of their own, to [`crate::api`]; functions of types,
/// modes and interfaces the FMU does not have return `fmi3Error` naming them.
///
/// Invoke it beside [`crate::export_fmi2!`] in the FMU's `cdylib` crate: the `fmi2…` and
/// `fmi3…` names differ, so one shared object serves an FMI 2.0 and an FMI 3.0 FMU, each
/// with its own `modelDescription.xml`.
#[macro_export]
macro_rules! export_fmi3 {
    ($model:ty) => {
        $crate::export_fmi3!($model, ::core::env!("CARGO_CRATE_NAME"));
    };
    ($model:ty, $model_identifier:expr) => {
        #[allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]
        const _: () = {
            use ::std::ffi::c_char;
            use $crate::api as __api2;
            use $crate::api::frame::unsupported as __unsupported;
            use $crate::fmi3::api as __api;
            use $crate::fmi3_types::*;

            const __MODEL_IDENTIFIER: &str = $model_identifier;

            #[unsafe(no_mangle)]
            pub extern "C" fn fmi3GetVersion() -> *const c_char {
                __api::get_version()
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3SetDebugLogging(
                c: fmi3Instance,
                logging_on: fmi3Boolean,
                n: usize,
                categories: *const fmi3String,
            ) -> fmi3Status {
                unsafe { __api::set_debug_logging::<$model>(c, logging_on, n, categories) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
                instance_name: fmi3String,
                instantiation_token: fmi3String,
                resource_path: fmi3String,
                _visible: fmi3Boolean,
                logging_on: fmi3Boolean,
                event_mode_used: fmi3Boolean,
                _early_return_allowed: fmi3Boolean,
                _required_intermediate_variables: *const fmi3ValueReference,
                _n_required_intermediate_variables: usize,
                instance_environment: fmi3InstanceEnvironment,
                log_message: fmi3LogMessageCallback,
                _intermediate_update: fmi3IntermediateUpdateCallback,
            ) -> fmi3Instance {
                unsafe {
                    __api::instantiate_co_simulation::<$model>(
                        __MODEL_IDENTIFIER,
                        instance_name,
                        instantiation_token,
                        resource_path,
                        logging_on,
                        event_mode_used,
                        instance_environment,
                        log_message,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3InstantiateModelExchange(
                instance_name: fmi3String,
                _instantiation_token: fmi3String,
                _resource_path: fmi3String,
                _visible: fmi3Boolean,
                _logging_on: fmi3Boolean,
                instance_environment: fmi3InstanceEnvironment,
                log_message: fmi3LogMessageCallback,
            ) -> fmi3Instance {
                unsafe {
                    __api::instantiate_other(
                        __MODEL_IDENTIFIER,
                        "ModelExchange",
                        instance_name,
                        instance_environment,
                        log_message,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
                instance_name: fmi3String,
                _instantiation_token: fmi3String,
                _resource_path: fmi3String,
                _visible: fmi3Boolean,
                _logging_on: fmi3Boolean,
                instance_environment: fmi3InstanceEnvironment,
                log_message: fmi3LogMessageCallback,
                _clock_update: fmi3ClockUpdateCallback,
                _lock_preemption: fmi3PreemptionCallback,
                _unlock_preemption: fmi3PreemptionCallback,
            ) -> fmi3Instance {
                unsafe {
                    __api::instantiate_other(
                        __MODEL_IDENTIFIER,
                        "ScheduledExecution",
                        instance_name,
                        instance_environment,
                        log_message,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3FreeInstance(c: fmi3Instance) {
                unsafe { __api2::free_instance::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3EnterInitializationMode(
                c: fmi3Instance,
                tolerance_defined: fmi3Boolean,
                tolerance: fmi3Float64,
                start_time: fmi3Float64,
                stop_time_defined: fmi3Boolean,
                stop_time: fmi3Float64,
            ) -> fmi3Status {
                unsafe {
                    __api::enter_initialization_mode::<$model>(
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
            pub unsafe extern "C" fn fmi3ExitInitializationMode(c: fmi3Instance) -> fmi3Status {
                unsafe { __api2::exit_initialization_mode::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3Terminate(c: fmi3Instance) -> fmi3Status {
                unsafe { __api2::terminate::<$model>(c) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3Reset(c: fmi3Instance) -> fmi3Status {
                unsafe { __api2::reset::<$model>(c) }
            }

            $crate::export_fmi3!(@values $model, fmi3GetFloat64, get_float64, *mut fmi3Float64);
            $crate::export_fmi3!(@values $model, fmi3SetFloat64, set_float64, *const fmi3Float64);
            $crate::export_fmi3!(@values $model, fmi3GetInt32, get_int32, *mut fmi3Int32);
            $crate::export_fmi3!(@values $model, fmi3SetInt32, set_int32, *const fmi3Int32);
            $crate::export_fmi3!(@values $model, fmi3GetBoolean, get_boolean, *mut fmi3Boolean);
            $crate::export_fmi3!(@values $model, fmi3SetBoolean, set_boolean, *const fmi3Boolean);
            $crate::export_fmi3!(@values $model, fmi3GetString, get_string, *mut fmi3String);
            $crate::export_fmi3!(@values $model, fmi3SetString, set_string, *const fmi3String);

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3GetFMUState(
                c: fmi3Instance,
                state: *mut fmi3FMUState,
            ) -> fmi3Status {
                unsafe { __api2::get_fmu_state::<$model>(c, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3SetFMUState(
                c: fmi3Instance,
                state: fmi3FMUState,
            ) -> fmi3Status {
                unsafe { __api2::set_fmu_state::<$model>(c, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3FreeFMUState(
                c: fmi3Instance,
                state: *mut fmi3FMUState,
            ) -> fmi3Status {
                unsafe { __api2::free_fmu_state::<$model>(c, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
                c: fmi3Instance,
                state: fmi3FMUState,
                size: *mut usize,
            ) -> fmi3Status {
                unsafe { __api2::serialized_fmu_state_size::<$model>(c, state, size) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3SerializeFMUState(
                c: fmi3Instance,
                state: fmi3FMUState,
                bytes: *mut fmi3Byte,
                size: usize,
            ) -> fmi3Status {
                unsafe { __api2::serialize_fmu_state::<$model>(c, state, bytes.cast(), size) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3DeserializeFMUState(
                c: fmi3Instance,
                bytes: *const fmi3Byte,
                size: usize,
                state: *mut fmi3FMUState,
            ) -> fmi3Status {
                unsafe { __api2::de_serialize_fmu_state::<$model>(c, bytes.cast(), size, state) }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
                c: fmi3Instance,
                unknowns: *const fmi3ValueReference,
                n_unknowns: usize,
                knowns: *const fmi3ValueReference,
                n_knowns: usize,
                seed: *const fmi3Float64,
                n_seed: usize,
                sensitivity: *mut fmi3Float64,
                n_sensitivity: usize,
            ) -> fmi3Status {
                unsafe {
                    __api::get_directional_derivative::<$model>(
                        c,
                        unknowns,
                        n_unknowns,
                        knowns,
                        n_knowns,
                        seed,
                        n_seed,
                        sensitivity,
                        n_sensitivity,
                    )
                }
            }

            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn fmi3DoStep(
                c: fmi3Instance,
                t: fmi3Float64,
                h: fmi3Float64,
                no_set_fmu_state_prior_to_current_point: fmi3Boolean,
                event_handling_needed: *mut fmi3Boolean,
                terminate_simulation: *mut fmi3Boolean,
                early_return: *mut fmi3Boolean,
                last_successful_time: *mut fmi3Float64,
            ) -> fmi3Status {
                unsafe {
                    __api::do_step::<$model>(
                        c,
                        t,
                        h,
                        no_set_fmu_state_prior_to_current_point,
                        event_handling_needed,
                        terminate_simulation,
                        early_return,
                        last_successful_time,
                    )
                }
            }

            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no event mode (hasEventMode=\"false\")",
                fmi3EnterEventMode();
                fmi3EvaluateDiscreteStates();
                fmi3UpdateDiscreteStates(
                    _a: *mut fmi3Boolean,
                    _b: *mut fmi3Boolean,
                    _cc: *mut fmi3Boolean,
                    _d: *mut fmi3Boolean,
                    _e: *mut fmi3Boolean,
                    _f: *mut fmi3Float64,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no event mode, so it is in step mode after initialization",
                fmi3EnterStepMode();
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no structural parameters (no configuration mode)",
                fmi3EnterConfigurationMode();
                fmi3ExitConfigurationMode();
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU implements Co-Simulation only",
                fmi3EnterContinuousTimeMode();
                fmi3CompletedIntegratorStep(
                    _a: fmi3Boolean,
                    _b: *mut fmi3Boolean,
                    _cc: *mut fmi3Boolean,
                );
                fmi3SetTime(_t: fmi3Float64);
                fmi3SetContinuousStates(_x: *const fmi3Float64, _n: usize);
                fmi3GetContinuousStateDerivatives(_x: *mut fmi3Float64, _n: usize);
                fmi3GetEventIndicators(_x: *mut fmi3Float64, _n: usize);
                fmi3GetContinuousStates(_x: *mut fmi3Float64, _n: usize);
                fmi3GetNominalsOfContinuousStates(_x: *mut fmi3Float64, _n: usize);
                fmi3GetNumberOfEventIndicators(_n: *mut usize);
                fmi3GetNumberOfContinuousStates(_n: *mut usize);
                fmi3ActivateModelPartition(_clock: fmi3ValueReference, _t: fmi3Float64);
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "variable dependencies are in modelDescription.xml only",
                fmi3GetNumberOfVariableDependencies(_vr: fmi3ValueReference, _n: *mut usize);
                fmi3GetVariableDependencies(
                    _vr: fmi3ValueReference,
                    _a: *mut usize,
                    _b: *mut fmi3ValueReference,
                    _cc: *mut usize,
                    _d: *mut fmi3DependencyKind,
                    _n: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "adjoint derivatives are not provided (providesAdjointDerivatives=\"false\")",
                fmi3GetAdjointDerivative(
                    _u: *const fmi3ValueReference,
                    _nu: usize,
                    _k: *const fmi3ValueReference,
                    _nk: usize,
                    _s: *const fmi3Float64,
                    _ns: usize,
                    _o: *mut fmi3Float64,
                    _no: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "output derivatives are not provided (maxOutputDerivativeOrder=\"0\")",
                fmi3GetOutputDerivatives(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _o: *const fmi3Int32,
                    _a: *mut fmi3Float64,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no clocks",
                fmi3GetIntervalDecimal(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3Float64,
                    _q: *mut fmi3IntervalQualifier,
                );
                fmi3GetIntervalFraction(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3UInt64,
                    _b: *mut fmi3UInt64,
                    _q: *mut fmi3IntervalQualifier,
                );
                fmi3GetShiftDecimal(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3Float64,
                );
                fmi3GetShiftFraction(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3UInt64,
                    _b: *mut fmi3UInt64,
                );
                fmi3SetIntervalDecimal(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3Float64,
                );
                fmi3SetIntervalFraction(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3UInt64,
                    _b: *const fmi3UInt64,
                );
                fmi3SetShiftDecimal(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3Float64,
                );
                fmi3SetShiftFraction(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3UInt64,
                    _b: *const fmi3UInt64,
                );
                fmi3GetClock(_vr: *const fmi3ValueReference, _n: usize, _a: *mut fmi3Clock);
                fmi3SetClock(_vr: *const fmi3ValueReference, _n: usize, _a: *const fmi3Clock);
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no Binary variables",
                fmi3GetBinary(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _s: *mut usize,
                    _a: *mut fmi3Binary,
                    _nv: usize,
                );
                fmi3SetBinary(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _s: *const usize,
                    _a: *const fmi3Binary,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no Float32 variables",
                fmi3GetFloat32(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3Float32,
                    _nv: usize,
                );
                fmi3SetFloat32(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3Float32,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no Int8 variables",
                fmi3GetInt8(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3Int8,
                    _nv: usize,
                );
                fmi3SetInt8(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3Int8,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no UInt8 variables",
                fmi3GetUInt8(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3UInt8,
                    _nv: usize,
                );
                fmi3SetUInt8(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3UInt8,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no Int16 variables",
                fmi3GetInt16(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3Int16,
                    _nv: usize,
                );
                fmi3SetInt16(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3Int16,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no UInt16 variables",
                fmi3GetUInt16(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3UInt16,
                    _nv: usize,
                );
                fmi3SetUInt16(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3UInt16,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no UInt32 variables",
                fmi3GetUInt32(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3UInt32,
                    _nv: usize,
                );
                fmi3SetUInt32(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3UInt32,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no Int64 variables",
                fmi3GetInt64(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3Int64,
                    _nv: usize,
                );
                fmi3SetInt64(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3Int64,
                    _nv: usize,
                );
            );
            $crate::export_fmi3!(
                @unsupported $model,
                "the FMU has no UInt64 variables",
                fmi3GetUInt64(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *mut fmi3UInt64,
                    _nv: usize,
                );
                fmi3SetUInt64(
                    _vr: *const fmi3ValueReference,
                    _n: usize,
                    _a: *const fmi3UInt64,
                    _nv: usize,
                );
            );
        };
    };
    (@unsupported $model:ty, $why:literal, $($symbol:ident($($arg:ident: $ty:ty),* $(,)?);)+) => {
        $(
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $symbol(c: fmi3Instance, $($arg: $ty),*) -> fmi3Status {
                unsafe { __unsupported::<$model>(c, ::core::stringify!($symbol), $why) }
            }
        )+
    };
    (@values $model:ty, $symbol:ident, $function:ident, $values:ty) => {
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $symbol(
            c: fmi3Instance,
            vr: *const fmi3ValueReference,
            nvr: usize,
            values: $values,
            n_values: usize,
        ) -> fmi3Status {
            unsafe { __api::$function::<$model>(c, vr, nvr, values, n_values) }
        }
    };
}
