//! Loading an FMU ([`Fmu::load`]), what it describes, and creating its instances
//! ([`Fmu::instantiate`]).

use super::{fmi2_bool, static_str, Fmu, Instance, InstantiateOptions, Space, PLATFORM};
use crate::archive::{fmu_display_name, unpack, UnpackLimits};
use crate::error::FmiError;
use crate::library::{Library, LoadError};
use crate::logger::{LogEnv, LogSink};
use fmi2::types::*;
use fmi2::uri::file_uri;
use model_description::{ModelDescription, VariableKind};
use std::collections::HashMap;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

impl Fmu {
    /// Unpack `path` (with the default [`UnpackLimits`]), read its model description,
    /// check it has a Co-Simulation interface, and load
    /// `binaries/linux64/<modelIdentifier>.so` with every FMI 2.0 CS function.
    pub fn load(path: impl AsRef<Path>) -> Result<Arc<Fmu>, FmiError> {
        Self::load_with_limits(path, &UnpackLimits::default())
    }

    /// The model description of the FMU at `path`, checked as [`Fmu::load`] checks it
    /// (the FMI 2.0 rules, a Co-Simulation interface, a binary for this platform), without
    /// loading its library: no code of the FMU runs in this process. The unpacked copy is
    /// removed before this returns.
    pub fn describe(path: impl AsRef<Path>) -> Result<ModelDescription, FmiError> {
        let (_, _dir, model_description, _) = Self::read(path.as_ref(), &UnpackLimits::default())?;
        Ok(model_description)
    }

    /// Unpack, read and check the description; (name, folder, description, library path
    /// relative to the folder: under `binaries/linux64/` for FMI 2.0, under
    /// `binaries/x86_64-linux/` for FMI 3.0).
    pub(crate) fn read(
        path: &Path,
        limits: &UnpackLimits,
    ) -> Result<
        (
            String,
            crate::archive::UnpackedDir,
            ModelDescription,
            String,
        ),
        FmiError,
    > {
        let name = fmu_display_name(path);
        let dir = unpack(path, limits)?;
        let unsupported = |message: String| FmiError::Unsupported {
            fmu: name.clone(),
            message,
        };
        let md_path = dir.path().join("modelDescription.xml");
        if !md_path.is_file() {
            return Err(FmiError::Archive {
                fmu: name.clone(),
                entry: None,
                message: "the archive has no modelDescription.xml at its root".into(),
            });
        }
        let md_error = |message: String| FmiError::Archive {
            fmu: name.clone(),
            entry: Some("modelDescription.xml".into()),
            message,
        };
        let bytes = std::fs::read(&md_path).map_err(|e| md_error(format!("cannot read: {e}")))?;
        let xml = String::from_utf8(bytes).map_err(|e| {
            md_error(format!(
                "not valid UTF-8 at byte {}",
                e.utf8_error().valid_up_to()
            ))
        })?;
        let model_description =
            ModelDescription::parse(&xml, &format!("{name}: modelDescription.xml"))?;
        // The rules `fmpy validate` checks (and FMPy's simulate applies), before any code of
        // the FMU runs: unique names, value references not shared by an input and an output,
        // ModelStructure indices, declared types, ...
        let problems = model_description.validate();
        if !problems.is_empty() {
            return Err(unsupported(format!(
                "modelDescription.xml breaks {} rule(s) of FMI {}:\n  {}",
                problems.len(),
                if model_description.fmi_version.starts_with('3') {
                    "3.0"
                } else {
                    "2.0"
                },
                problems.join("\n  ")
            )));
        }
        let identifier =
            match &model_description.co_simulation {
                Some(cs) => cs.model_identifier.clone(),
                None => return Err(unsupported(
                    "the FMU has no <CoSimulation> interface (only Co-Simulation FMUs can be run)"
                        .into(),
                )),
            };
        if identifier.is_empty()
            || !identifier
                .chars()
                .all(|c| c == '_' || c.is_ascii_alphanumeric())
        {
            return Err(unsupported(format!(
                "modelIdentifier \"{identifier}\" is not a valid C identifier"
            )));
        }
        let platform = if model_description.fmi_version.starts_with('3') {
            crate::fmi3::PLATFORM
        } else {
            PLATFORM
        };
        let relative = format!("binaries/{platform}/{identifier}.so");
        if !dir.path().join(&relative).is_file() {
            let platforms = list_platforms(dir.path());
            return Err(unsupported(format!(
                "no {relative} in the archive (binaries for: {})",
                if platforms.is_empty() {
                    "none".to_owned()
                } else {
                    platforms.join(", ")
                }
            )));
        }
        Ok((name, dir, model_description, relative))
    }

    /// [`Fmu::load`] with explicit unpacking limits.
    pub fn load_with_limits(
        path: impl AsRef<Path>,
        limits: &UnpackLimits,
    ) -> Result<Arc<Fmu>, FmiError> {
        let (name, dir, model_description, relative) = Self::read(path.as_ref(), limits)?;
        Self::from_read(name, dir, model_description, relative)
    }

    /// The library of an FMU [`Fmu::read`] unpacked, loaded.
    pub(crate) fn from_read(
        name: String,
        dir: crate::archive::UnpackedDir,
        model_description: ModelDescription,
        relative: String,
    ) -> Result<Arc<Fmu>, FmiError> {
        let unsupported = |message: String| FmiError::Unsupported {
            fmu: name.clone(),
            message,
        };
        if model_description.fmi_version.starts_with('3') {
            return Err(unsupported(
                "an FMI 3.0 FMU: load it with fmi_import::AnyFmu (Fmu loads FMI 2.0 FMUs)".into(),
            ));
        }
        let library_path = dir.path().join(&relative);
        let needs_tool =
            (model_description.co_simulation.as_ref()).is_some_and(|cs| cs.needs_execution_tool);
        let functions = Library::load_for(&library_path, needs_tool).map_err(|e| match e {
            LoadError::Open(message) => FmiError::Library {
                fmu: name.clone(),
                library: relative.clone(),
                message,
            },
            LoadError::MissingSymbols(symbols) => FmiError::MissingSymbols {
                fmu: name.clone(),
                library: relative.clone(),
                symbols: symbols.iter().map(|s| s.to_string()).collect(),
            },
        })?;
        // SAFETY: both functions take no arguments and return a static C string.
        let version = unsafe { static_str((functions.get_version)()) };
        if !version.starts_with("2.") {
            return Err(unsupported(format!(
                "fmi2GetVersion() returned \"{version}\", expected \"2.0\""
            )));
        }
        let platform = unsafe { static_str((functions.get_types_platform)()) };
        if platform != "default" {
            return Err(unsupported(format!(
                "fmi2GetTypesPlatform() returned \"{platform}\", expected \"default\""
            )));
        }
        let mut names = HashMap::new();
        for v in &model_description.model_variables {
            let space = match v.kind {
                VariableKind::Real(_) => Space::Real,
                VariableKind::Integer(_) | VariableKind::Enumeration(_) => Space::Integer,
                VariableKind::Boolean(_) => Space::Boolean,
                VariableKind::String(_) => Space::String,
            };
            names
                .entry((space, v.value_reference))
                .or_insert_with(|| v.name.clone());
        }
        Ok(Arc::new(Fmu {
            name,
            model_description,
            functions,
            names,
            library_path,
            dir,
        }))
    }

    /// The FMU's file name, used in every message.
    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn model_description(&self) -> &ModelDescription {
        &self.model_description
    }

    /// The directory the FMU was unpacked into (deleted when the `Fmu` is dropped).
    pub fn unpacked_dir(&self) -> &Path {
        self.dir.path()
    }

    /// The loaded shared library.
    pub fn library_path(&self) -> &Path {
        &self.library_path
    }

    /// The `fmuResourceLocation` passed to `fmi2Instantiate`: the `file:` URI of the
    /// unpacked `resources` directory, without a trailing slash (as FMPy passes it).
    pub fn resource_uri(&self) -> String {
        file_uri(&self.dir.path().join("resources"))
            .expect("the unpack directory is canonical, hence absolute")
    }

    /// `fmi2GetVersion()`.
    pub fn version(&self) -> String {
        // SAFETY: no arguments; returns a static string.
        unsafe { static_str((self.functions.get_version)()) }
    }

    /// `fmi2GetTypesPlatform()`.
    pub fn types_platform(&self) -> String {
        // SAFETY: no arguments; returns a static string.
        unsafe { static_str((self.functions.get_types_platform)()) }
    }

    /// `fmi2Instantiate` as a Co-Simulation slave with the description's GUID.
    pub fn instantiate(
        self: &Arc<Self>,
        options: &InstantiateOptions,
    ) -> Result<Instance, FmiError> {
        let cs = self
            .model_description
            .co_simulation
            .as_ref()
            .expect("checked in Fmu::load");
        let instance_name = options
            .instance_name
            .clone()
            .unwrap_or_else(|| cs.model_identifier.clone());
        let c_name = self.c_string(&instance_name, "instanceName")?;
        let c_guid = self.c_string(&self.model_description.guid, "guid")?;
        let c_uri = self.c_string(&self.resource_uri(), "fmuResourceLocation")?;
        let sink = Box::new(LogSink::new(options.echo_log));
        let env = Box::new(LogEnv::new(&*sink));
        let callbacks = Box::new(env.callbacks());
        sink.begin_call();
        // SAFETY: all strings are NUL-terminated and live across the call; `callbacks`,
        // `env` and `sink` are boxed and owned by the instance, so they outlive every
        // use the FMU makes of them (until fmi2FreeInstance).
        let component = unsafe {
            (self.functions.instantiate)(
                c_name.as_ptr(),
                fmi2CoSimulation,
                c_guid.as_ptr(),
                c_uri.as_ptr(),
                &*callbacks,
                fmi2_bool(options.visible),
                fmi2_bool(options.logging_on),
            )
        };
        if component.is_null() {
            return Err(FmiError::Instantiate {
                fmu: self.name.clone(),
                instance: instance_name,
                messages: sink.take_call_messages(),
            });
        }
        static NEXT_ID: AtomicU64 = AtomicU64::new(1);
        Ok(Instance {
            fmu: Arc::clone(self),
            component,
            name: instance_name,
            id: NEXT_ID.fetch_add(1, Ordering::Relaxed),
            fatal: false,
            _callbacks: callbacks,
            _env: env,
            sink,
        })
    }
}

fn list_platforms(dir: &Path) -> Vec<String> {
    let mut platforms: Vec<String> = std::fs::read_dir(dir.join("binaries"))
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| e.path().is_dir())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    platforms.sort();
    platforms
}
