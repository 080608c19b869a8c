//! A loaded FMU ([`Fmu`]) and its instances ([`Instance`]).

use crate::archive::{fmu_display_name, unpack, UnpackLimits, UnpackedDir};
use crate::error::{CallStatus, FmiError, Status};
use crate::library::{Library, LoadError};
use crate::logger::{LogEnv, LogMessage, LogSink};
use fmi2::types::*;
use fmi2::uri::file_uri;
use fmi2::{first_non_finite, Functions};
use model_description::{ModelDescription, VariableKind};
use std::collections::HashMap;
use std::ffi::{c_char, CStr, CString};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// The platform directory under `binaries/` this importer loads from.
pub const PLATFORM: &str = "linux64";

/// An unpacked FMU with its model description and its shared library loaded.
///
/// Field order matters: the function table is dropped before the library is unloaded,
/// and the library is unloaded before its directory is deleted. Instances hold an
/// `Arc<Fmu>`, so the library stays loaded while any instance exists.
pub struct Fmu {
    name: String,
    model_description: ModelDescription,
    functions: Library,
    /// (value-reference space, value reference) → name of the first variable with it.
    names: HashMap<(Space, u32), String>,
    library_path: PathBuf,
    dir: UnpackedDir,
}

/// The value-reference space of a variable's type (Enumeration shares Integer's).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Space {
    Real,
    Integer,
    Boolean,
    String,
}

impl std::fmt::Debug for Fmu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmu")
            .field("name", &self.name)
            .field("model_name", &self.model_description.model_name)
            .field("dir", &self.dir.path())
            .finish_non_exhaustive()
    }
}

/// Options of [`Fmu::instantiate`].
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct InstantiateOptions {
    /// The `instanceName`; `None` uses the modelIdentifier (as FMPy does).
    pub instance_name: Option<String>,
    /// `visible` (interactive mode). Default `false`.
    pub visible: bool,
    /// `loggingOn`: enable the FMU's debug logging. Default `false`.
    pub logging_on: bool,
    /// Print every message the FMU logs to standard error as it arrives. Default `false`
    /// (messages of a failed call are part of its error either way).
    pub echo_log: bool,
}

impl Fmu {
    /// Unpack `path` (with the default [`UnpackLimits`]), read its model description,
    /// check it has a Co-Simulation interface, and load
    /// `binaries/linux64/<modelIdentifier>.so` with every FMI 2.0 CS function.
    pub fn load(path: impl AsRef<Path>) -> Result<Arc<Fmu>, FmiError> {
        Self::load_with_limits(path, &UnpackLimits::default())
    }

    /// [`Fmu::load`] with explicit unpacking limits.
    pub fn load_with_limits(
        path: impl AsRef<Path>,
        limits: &UnpackLimits,
    ) -> Result<Arc<Fmu>, FmiError> {
        let path = path.as_ref();
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
                "modelDescription.xml breaks {} rule(s) of FMI 2.0:\n  {}",
                problems.len(),
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
        let relative = format!("binaries/{PLATFORM}/{identifier}.so");
        let library_path = dir.path().join(&relative);
        if !library_path.is_file() {
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
        let functions = Library::load(&library_path).map_err(|e| match e {
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

    fn c_string(&self, value: &str, what: &str) -> Result<CString, FmiError> {
        CString::new(value).map_err(|_| FmiError::Unsupported {
            fmu: self.name.clone(),
            message: format!("{what} \"{value}\" contains a NUL character"),
        })
    }

    /// The names of the variables with these value references, comma-separated.
    fn names(&self, space: Space, vrs: &[u32]) -> String {
        let names: Vec<String> = vrs
            .iter()
            .map(|&vr| self.variable_name(space, vr))
            .collect();
        names.join(", ")
    }

    fn variable_name(&self, space: Space, vr: u32) -> String {
        self.names
            .get(&(space, vr))
            .cloned()
            .unwrap_or_else(|| format!("<unknown value reference {vr}>"))
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

/// # Safety
/// `p` is NULL or a NUL-terminated string.
unsafe fn static_str(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

fn fmi2_bool(b: bool) -> fmi2Boolean {
    if b {
        fmi2True
    } else {
        fmi2False
    }
}

/// `fmi2StatusKind`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatusKind {
    DoStepStatus = 0,
    PendingStatus = 1,
    LastSuccessfulTime = 2,
    Terminated = 3,
}

impl StatusKind {
    fn name(self) -> &'static str {
        match self {
            StatusKind::DoStepStatus => "fmi2DoStepStatus",
            StatusKind::PendingStatus => "fmi2PendingStatus",
            StatusKind::LastSuccessfulTime => "fmi2LastSuccessfulTime",
            StatusKind::Terminated => "fmi2Terminated",
        }
    }
}

/// How `fmi2DoStep` ended when it did not fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepResult {
    /// `fmi2OK`.
    Ok,
    /// `fmi2Warning`: the step was completed; the FMU logged something worth reading.
    Warning,
    /// `fmi2Discard`: the step was not completed as requested; ask
    /// [`Instance::terminated`] and [`Instance::last_successful_time`] how far it got.
    Discard,
}

/// An FMU state saved by [`Instance::get_fmu_state`]. It belongs to the instance that
/// created or deserialized it; the other methods refuse a state of another instance.
/// Release it with [`Instance::free_fmu_state`] (states not freed are released by the
/// FMU's `fmi2FreeInstance`, as the standard requires of the FMU).
#[derive(Debug)]
pub struct FmuState {
    pointer: fmi2FMUstate,
    instance_id: u64,
}

/// A Co-Simulation instance. `fmi2FreeInstance` is called on drop (unless the FMU
/// returned `fmi2Fatal`, after which the standard allows no further call).
///
/// Every wrapper returns `Err` for `fmi2Error`, `fmi2Fatal`, `fmi2Pending` and
/// out-of-range codes, and for `fmi2Discard` except from `fmi2DoStep` (where it is a
/// [`StepResult`]). The error names the FMU, the call with its arguments, the status and
/// the messages the FMU logged during the call.
pub struct Instance {
    fmu: Arc<Fmu>,
    component: fmi2Component,
    name: String,
    id: u64,
    fatal: bool,
    // Owned for the FMU: it may keep pointers to these until fmi2FreeInstance.
    _callbacks: Box<fmi2CallbackFunctions>,
    _env: Box<LogEnv>,
    sink: Box<LogSink>,
}

// SAFETY: FMI 2.0 allows an instance to be used from any thread as long as calls are not
// concurrent; `&mut self` on every call enforces that. The logger sink is a Mutex.
unsafe impl Send for Instance {}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance")
            .field("fmu", &self.fmu.name)
            .field("name", &self.name)
            .finish_non_exhaustive()
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if !self.fatal {
            // SAFETY: the component came from fmi2Instantiate of this library and is freed
            // exactly once; the callbacks are still alive (dropped after this).
            unsafe { (self.fmu.functions.free_instance)(self.component) };
        }
    }
}

impl Instance {
    pub fn fmu(&self) -> &Arc<Fmu> {
        &self.fmu
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// Print (or stop printing) the FMU's log messages to standard error as they arrive.
    pub fn set_echo_log(&self, echo: bool) {
        self.sink.set_echo(echo);
    }

    /// The messages logged during the most recent call (taken: a second call returns
    /// only what arrived since).
    pub fn take_messages(&self) -> Vec<LogMessage> {
        self.sink.take_call_messages()
    }

    /// Run one FMI call: reset the call log, call, map the status.
    fn call(
        &mut self,
        describe: impl FnOnce(&Fmu) -> String,
        allow_discard: bool,
        f: impl FnOnce(&Functions, fmi2Component) -> fmi2Status,
    ) -> Result<Status, FmiError> {
        self.sink.begin_call();
        let raw = f(&self.fmu.functions, self.component);
        match Status::from_raw(raw) {
            Some(s @ (Status::Ok | Status::Warning)) => Ok(s),
            Some(Status::Discard) if allow_discard => Ok(Status::Discard),
            other => {
                if other == Some(Status::Fatal) {
                    self.fatal = true;
                }
                Err(FmiError::Call {
                    fmu: self.fmu.name.clone(),
                    instance: self.name.clone(),
                    call: describe(&self.fmu),
                    status: other.map_or(CallStatus::Illegal(raw), CallStatus::Status),
                    messages: self.sink.take_call_messages(),
                })
            }
        }
    }

    fn check_lengths(&self, call: &str, vrs: usize, values: usize) -> Result<(), FmiError> {
        if vrs == values {
            Ok(())
        } else {
            Err(FmiError::Unsupported {
                fmu: self.fmu.name.clone(),
                message: format!(
                    "{call}: {vrs} value references but {values} values (instance \"{}\")",
                    self.name
                ),
            })
        }
    }

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

    /// `fmi2DoStep(currentCommunicationPoint, communicationStepSize,
    /// noSetFMUStatePriorToCurrentPoint)`.
    pub fn do_step(
        &mut self,
        current_communication_point: f64,
        communication_step_size: f64,
        no_set_fmu_state_prior_to_current_point: bool,
    ) -> Result<StepResult, FmiError> {
        let status = self.call(
            |_| {
                format!(
                    "fmi2DoStep(currentCommunicationPoint={current_communication_point}, communicationStepSize={communication_step_size}, noSetFMUStatePriorToCurrentPoint={no_set_fmu_state_prior_to_current_point})"
                )
            },
            true,
            // SAFETY: plain values.
            |f, c| unsafe {
                (f.do_step)(
                    c,
                    current_communication_point,
                    communication_step_size,
                    fmi2_bool(no_set_fmu_state_prior_to_current_point),
                )
            },
        )?;
        Ok(match status {
            Status::Warning => StepResult::Warning,
            Status::Discard => StepResult::Discard,
            _ => StepResult::Ok,
        })
    }

    /// `fmi2CancelStep`.
    pub fn cancel_step(&mut self) -> Result<Status, FmiError> {
        // SAFETY: component only.
        self.call(
            |_| "fmi2CancelStep()".into(),
            false,
            |f, c| unsafe { (f.cancel_step)(c) },
        )
    }

    /// `fmi2SetRealInputDerivatives`.
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<Status, FmiError> {
        self.check_lengths("fmi2SetRealInputDerivatives", vrs.len(), values.len())?;
        self.check_lengths("fmi2SetRealInputDerivatives", vrs.len(), orders.len())?;
        self.call(
            |fmu| {
                format!(
                    "fmi2SetRealInputDerivatives({}, orders={orders:?}, values={values:?})",
                    fmu.names(Space::Real, vrs)
                )
            },
            false,
            // SAFETY: all slices have vrs.len() elements.
            |f, c| unsafe {
                (f.set_real_input_derivatives)(
                    c,
                    vrs.as_ptr(),
                    vrs.len(),
                    orders.as_ptr(),
                    values.as_ptr(),
                )
            },
        )
    }

    /// `fmi2GetRealOutputDerivatives`.
    pub fn get_real_output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &mut [f64],
    ) -> Result<Status, FmiError> {
        self.check_lengths("fmi2GetRealOutputDerivatives", vrs.len(), values.len())?;
        self.check_lengths("fmi2GetRealOutputDerivatives", vrs.len(), orders.len())?;
        self.call(
            |fmu| {
                format!(
                    "fmi2GetRealOutputDerivatives({}, orders={orders:?})",
                    fmu.names(Space::Real, vrs)
                )
            },
            false,
            // SAFETY: all slices have vrs.len() elements.
            |f, c| unsafe {
                (f.get_real_output_derivatives)(
                    c,
                    vrs.as_ptr(),
                    vrs.len(),
                    orders.as_ptr(),
                    values.as_mut_ptr(),
                )
            },
        )
    }

    /// `fmi2GetDirectionalDerivative`: `dv_unknown = J · dv_known` for the partial
    /// derivatives of the unknowns with respect to the knowns.
    pub fn get_directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Result<Status, FmiError> {
        self.check_lengths("fmi2GetDirectionalDerivative", knowns.len(), dv_known.len())?;
        self.check_lengths(
            "fmi2GetDirectionalDerivative",
            unknowns.len(),
            dv_unknown.len(),
        )?;
        self.call(
            |fmu| {
                format!(
                    "fmi2GetDirectionalDerivative(unknowns=[{}], knowns=[{}])",
                    fmu.names(Space::Real, unknowns),
                    fmu.names(Space::Real, knowns)
                )
            },
            false,
            // SAFETY: lengths checked above.
            |f, c| unsafe {
                (f.get_directional_derivative)(
                    c,
                    unknowns.as_ptr(),
                    unknowns.len(),
                    knowns.as_ptr(),
                    knowns.len(),
                    dv_known.as_ptr(),
                    dv_unknown.as_mut_ptr(),
                )
            },
        )
    }

    /// `fmi2GetStatus`.
    pub fn get_status(&mut self, kind: StatusKind) -> Result<CallStatus, FmiError> {
        let mut value: fmi2Status = 0;
        self.call(
            |_| format!("fmi2GetStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(Status::from_raw(value).map_or(CallStatus::Illegal(value), CallStatus::Status))
    }

    /// `fmi2GetRealStatus`.
    pub fn get_real_status(&mut self, kind: StatusKind) -> Result<f64, FmiError> {
        let mut value = 0.0;
        self.call(
            |_| format!("fmi2GetRealStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_real_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(value)
    }

    /// `fmi2GetIntegerStatus`.
    pub fn get_integer_status(&mut self, kind: StatusKind) -> Result<i32, FmiError> {
        let mut value = 0;
        self.call(
            |_| format!("fmi2GetIntegerStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_integer_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(value)
    }

    /// `fmi2GetBooleanStatus`.
    pub fn get_boolean_status(&mut self, kind: StatusKind) -> Result<bool, FmiError> {
        let mut value = fmi2False;
        self.call(
            |_| format!("fmi2GetBooleanStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_boolean_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        Ok(value != fmi2False)
    }

    /// `fmi2GetStringStatus`.
    pub fn get_string_status(&mut self, kind: StatusKind) -> Result<String, FmiError> {
        let mut value: fmi2String = std::ptr::null();
        self.call(
            |_| format!("fmi2GetStringStatus({})", kind.name()),
            false,
            // SAFETY: one output value.
            |f, c| unsafe { (f.get_string_status)(c, kind as fmi2StatusKind, &mut value) },
        )?;
        // SAFETY: NULL or a NUL-terminated string owned by the FMU.
        Ok(unsafe { static_str(value) })
    }

    /// `fmi2GetBooleanStatus(fmi2Terminated)`: whether the FMU asked to end the
    /// simulation (meaningful after `fmi2DoStep` returned `fmi2Discard`).
    pub fn terminated(&mut self) -> Result<bool, FmiError> {
        self.get_boolean_status(StatusKind::Terminated)
    }

    /// `fmi2GetRealStatus(fmi2LastSuccessfulTime)`.
    pub fn last_successful_time(&mut self) -> Result<f64, FmiError> {
        self.get_real_status(StatusKind::LastSuccessfulTime)
    }

    fn check_state(&self, state: &FmuState, call: &str) -> Result<(), FmiError> {
        if state.instance_id == self.id {
            Ok(())
        } else {
            Err(FmiError::Unsupported {
                fmu: self.fmu.name.clone(),
                message: format!(
                    "{call}: the FMU state belongs to another instance than \"{}\"",
                    self.name
                ),
            })
        }
    }

    /// `fmi2GetFMUstate`: save the state into a new [`FmuState`], or overwrite `reuse`.
    pub fn get_fmu_state(&mut self, reuse: Option<FmuState>) -> Result<FmuState, FmiError> {
        let mut pointer: fmi2FMUstate = std::ptr::null_mut();
        if let Some(state) = reuse {
            self.check_state(&state, "fmi2GetFMUstate")?;
            pointer = state.pointer;
        }
        let result = self.call(
            |_| "fmi2GetFMUstate()".into(),
            false,
            // SAFETY: `pointer` is NULL (allocate) or a state of this instance (overwrite).
            |f, c| unsafe { (f.get_fmu_state)(c, &mut pointer) },
        );
        let state = FmuState {
            pointer,
            instance_id: self.id,
        };
        match result {
            Ok(_) => Ok(state),
            Err(e) => {
                if !state.pointer.is_null() {
                    let _ = self.free_fmu_state(state);
                }
                Err(e)
            }
        }
    }

    /// `fmi2SetFMUstate`: restore a saved state.
    pub fn set_fmu_state(&mut self, state: &FmuState) -> Result<Status, FmiError> {
        self.check_state(state, "fmi2SetFMUstate")?;
        let pointer = state.pointer;
        // SAFETY: a state created by this instance and not yet freed (FmuState is not
        // Clone, and free_fmu_state consumes it).
        self.call(
            |_| "fmi2SetFMUstate()".into(),
            false,
            |f, c| unsafe { (f.set_fmu_state)(c, pointer) },
        )
    }

    /// `fmi2FreeFMUstate`.
    pub fn free_fmu_state(&mut self, state: FmuState) -> Result<Status, FmiError> {
        self.check_state(&state, "fmi2FreeFMUstate")?;
        let mut pointer = state.pointer;
        // SAFETY: as in set_fmu_state; the FmuState is consumed.
        self.call(
            |_| "fmi2FreeFMUstate()".into(),
            false,
            |f, c| unsafe { (f.free_fmu_state)(c, &mut pointer) },
        )
    }

    /// `fmi2SerializedFMUstateSize` + `fmi2SerializeFMUstate`.
    pub fn serialize_fmu_state(&mut self, state: &FmuState) -> Result<Vec<u8>, FmiError> {
        self.check_state(state, "fmi2SerializeFMUstate")?;
        let pointer = state.pointer;
        let mut size = 0usize;
        // SAFETY: a live state of this instance; one output value.
        self.call(
            |_| "fmi2SerializedFMUstateSize()".into(),
            false,
            |f, c| unsafe { (f.serialized_fmu_state_size)(c, pointer, &mut size) },
        )?;
        let mut bytes = vec![0u8; size];
        // SAFETY: the buffer has the size the FMU asked for.
        self.call(
            |_| format!("fmi2SerializeFMUstate(size={size})"),
            false,
            |f, c| unsafe {
                (f.serialize_fmu_state)(c, pointer, bytes.as_mut_ptr().cast::<fmi2Byte>(), size)
            },
        )?;
        Ok(bytes)
    }

    /// `fmi2DeSerializeFMUstate`: a new [`FmuState`] of this instance from bytes written
    /// by [`Instance::serialize_fmu_state`] (possibly of another instance of the FMU).
    pub fn deserialize_fmu_state(&mut self, bytes: &[u8]) -> Result<FmuState, FmiError> {
        let mut pointer: fmi2FMUstate = std::ptr::null_mut();
        let result = self.call(
            |_| format!("fmi2DeSerializeFMUstate(size={})", bytes.len()),
            false,
            // SAFETY: the buffer is valid for bytes.len() bytes during the call.
            |f, c| unsafe {
                (f.de_serialize_fmu_state)(
                    c,
                    bytes.as_ptr().cast::<fmi2Byte>(),
                    bytes.len(),
                    &mut pointer,
                )
            },
        );
        let state = FmuState {
            pointer,
            instance_id: self.id,
        };
        match result {
            Ok(_) => Ok(state),
            Err(e) => {
                if !state.pointer.is_null() {
                    let _ = self.free_fmu_state(state);
                }
                Err(e)
            }
        }
    }
}
