//! Loading an FMU shared object and resolving its 34 functions.

use std::path::{Path, PathBuf};

use crate::state::Function;
use crate::types::function_types::*;

/// The 34 FMI 2.0 Co-Simulation functions of a loaded shared object.
///
/// The library stays loaded as long as this value lives; the function pointers must not
/// be used after it is dropped (they are only reachable through `&self`).
pub struct Fmi2Library {
    path: PathBuf,
    pub get_types_platform: fmi2GetTypesPlatformTYPE,
    pub get_version: fmi2GetVersionTYPE,
    pub set_debug_logging: fmi2SetDebugLoggingTYPE,
    pub instantiate: fmi2InstantiateTYPE,
    pub free_instance: fmi2FreeInstanceTYPE,
    pub setup_experiment: fmi2SetupExperimentTYPE,
    pub enter_initialization_mode: fmi2EnterInitializationModeTYPE,
    pub exit_initialization_mode: fmi2ExitInitializationModeTYPE,
    pub terminate: fmi2TerminateTYPE,
    pub reset: fmi2ResetTYPE,
    pub get_real: fmi2GetRealTYPE,
    pub get_integer: fmi2GetIntegerTYPE,
    pub get_boolean: fmi2GetBooleanTYPE,
    pub get_string: fmi2GetStringTYPE,
    pub set_real: fmi2SetRealTYPE,
    pub set_integer: fmi2SetIntegerTYPE,
    pub set_boolean: fmi2SetBooleanTYPE,
    pub set_string: fmi2SetStringTYPE,
    pub get_fmu_state: fmi2GetFMUstateTYPE,
    pub set_fmu_state: fmi2SetFMUstateTYPE,
    pub free_fmu_state: fmi2FreeFMUstateTYPE,
    pub serialized_fmu_state_size: fmi2SerializedFMUstateSizeTYPE,
    pub serialize_fmu_state: fmi2SerializeFMUstateTYPE,
    pub de_serialize_fmu_state: fmi2DeSerializeFMUstateTYPE,
    pub get_directional_derivative: fmi2GetDirectionalDerivativeTYPE,
    pub set_real_input_derivatives: fmi2SetRealInputDerivativesTYPE,
    pub get_real_output_derivatives: fmi2GetRealOutputDerivativesTYPE,
    pub do_step: fmi2DoStepTYPE,
    pub cancel_step: fmi2CancelStepTYPE,
    pub get_status: fmi2GetStatusTYPE,
    pub get_real_status: fmi2GetRealStatusTYPE,
    pub get_integer_status: fmi2GetIntegerStatusTYPE,
    pub get_boolean_status: fmi2GetBooleanStatusTYPE,
    pub get_string_status: fmi2GetStringStatusTYPE,
    // Last field: dropped after the pointers above are gone.
    _library: libloading::Library,
}

impl std::fmt::Debug for Fmi2Library {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmi2Library")
            .field("path", &self.path)
            .finish_non_exhaustive()
    }
}

impl Fmi2Library {
    /// Load `path` and resolve all 34 functions. The error names the library and every
    /// missing symbol.
    ///
    /// Loading runs the library's initialisers and the returned pointers are trusted to
    /// have the fmi2 signatures: the library must be an FMU binary, as for any importer.
    pub fn load(path: &Path) -> Result<Fmi2Library, String> {
        // SAFETY: loading an FMU binary is what this type is for (see above).
        let library = unsafe { libloading::Library::new(path) }
            .map_err(|e| format!("cannot load {}: {e}", path.display()))?;
        let missing: Vec<&str> = Function::ALL
            .iter()
            .map(|f| f.symbol())
            .filter(|name| {
                // SAFETY: only checks presence; the pointer is not used.
                unsafe { library.get::<*const ()>(name.as_bytes()) }.is_err()
            })
            .collect();
        if !missing.is_empty() {
            return Err(format!(
                "{} does not export {}",
                path.display(),
                missing.join(", ")
            ));
        }
        macro_rules! sym {
            ($name:literal) => {
                // SAFETY: present (checked above); the type is the fmi2 typedef of the
                // symbol of that name.
                *unsafe { library.get($name.as_bytes()) }.map_err(|e| format!("{}: {e}", $name))?
            };
        }
        Ok(Fmi2Library {
            path: path.to_owned(),
            get_types_platform: sym!("fmi2GetTypesPlatform"),
            get_version: sym!("fmi2GetVersion"),
            set_debug_logging: sym!("fmi2SetDebugLogging"),
            instantiate: sym!("fmi2Instantiate"),
            free_instance: sym!("fmi2FreeInstance"),
            setup_experiment: sym!("fmi2SetupExperiment"),
            enter_initialization_mode: sym!("fmi2EnterInitializationMode"),
            exit_initialization_mode: sym!("fmi2ExitInitializationMode"),
            terminate: sym!("fmi2Terminate"),
            reset: sym!("fmi2Reset"),
            get_real: sym!("fmi2GetReal"),
            get_integer: sym!("fmi2GetInteger"),
            get_boolean: sym!("fmi2GetBoolean"),
            get_string: sym!("fmi2GetString"),
            set_real: sym!("fmi2SetReal"),
            set_integer: sym!("fmi2SetInteger"),
            set_boolean: sym!("fmi2SetBoolean"),
            set_string: sym!("fmi2SetString"),
            get_fmu_state: sym!("fmi2GetFMUstate"),
            set_fmu_state: sym!("fmi2SetFMUstate"),
            free_fmu_state: sym!("fmi2FreeFMUstate"),
            serialized_fmu_state_size: sym!("fmi2SerializedFMUstateSize"),
            serialize_fmu_state: sym!("fmi2SerializeFMUstate"),
            de_serialize_fmu_state: sym!("fmi2DeSerializeFMUstate"),
            get_directional_derivative: sym!("fmi2GetDirectionalDerivative"),
            set_real_input_derivatives: sym!("fmi2SetRealInputDerivatives"),
            get_real_output_derivatives: sym!("fmi2GetRealOutputDerivatives"),
            do_step: sym!("fmi2DoStep"),
            cancel_step: sym!("fmi2CancelStep"),
            get_status: sym!("fmi2GetStatus"),
            get_real_status: sym!("fmi2GetRealStatus"),
            get_integer_status: sym!("fmi2GetIntegerStatus"),
            get_boolean_status: sym!("fmi2GetBooleanStatus"),
            get_string_status: sym!("fmi2GetStringStatus"),
            _library: library,
        })
    }

    /// The path the library was loaded from.
    pub fn path(&self) -> &Path {
        &self.path
    }
}
