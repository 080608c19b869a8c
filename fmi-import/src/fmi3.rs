//! FMI 3.0 Co-Simulation FMUs: [`Fmu3`] loads one (the same safe unpacking and checks of
//! the description as [`crate::Fmu`], the library under `binaries/x86_64-linux/`) and
//! [`Instance3`] runs it through [`FmiCalls`], so the coupling, the single-FMU runner and
//! the FMU workers take FMI 3.0 and FMI 2.0 FMUs alike ([`crate::AnyFmu`]).
//!
//! The calls are FMI 2.0's in FMI 3.0 form: `setup_experiment` keeps the times and
//! `fmi3EnterInitializationMode` passes them; Real, Integer, Boolean and String are
//! Float64, Int32, Boolean and String (scalars: `nValues` is the number of value
//! references); a step asks for no event mode and no early return, and keeps
//! `terminateSimulation` and `lastSuccessfulTime` for the status queries. The FMU's
//! messages reach the instance's [`LogSink`] through the (non-variadic) FMI 3.0 logger and
//! are attached to the error of a failed call.

// the C names of the FMI 3.0 status constants, matched on
#![allow(non_upper_case_globals)]

use crate::archive::UnpackedDir;
use crate::error::FmiError;
use crate::logger::{LogMessage, LogSink};
use crate::participant::FmiCalls;
use crate::{InstantiateOptions, UnpackLimits};
use fmi3::functions::*;
use fmi3::*;
use model_description::ModelDescription;
use std::collections::HashMap;
use std::ffi::{c_char, c_void, CStr, CString};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The folder under `binaries/` of FMI 3.0 binaries for this platform.
pub const PLATFORM: &str = "x86_64-linux";

/// The functions an FMI 3.0 Co-Simulation importer calls, resolved from the library.
struct Functions {
    get_version: fmi3GetVersionTYPE,
    instantiate: fmi3InstantiateCoSimulationTYPE,
    free_instance: fmi3FreeInstanceTYPE,
    enter_initialization_mode: fmi3EnterInitializationModeTYPE,
    exit_initialization_mode: fmi3InstanceOnlyTYPE,
    terminate: fmi3InstanceOnlyTYPE,
    get_float64: fmi3GetTYPE<f64>,
    set_float64: fmi3SetTYPE<f64>,
    get_int32: fmi3GetTYPE<i32>,
    set_int32: fmi3SetTYPE<i32>,
    get_boolean: fmi3GetTYPE<fmi3Boolean>,
    set_boolean: fmi3SetTYPE<fmi3Boolean>,
    set_string: fmi3SetTYPE<fmi3String>,
    do_step: fmi3DoStepTYPE,
    get_fmu_state: fmi3GetFMUStateTYPE,
    set_fmu_state: fmi3SetFMUStateTYPE,
    free_fmu_state: fmi3FreeFMUStateTYPE,
}

impl Functions {
    /// Resolve every function; `Err` lists the names the library does not export.
    ///
    /// # Safety
    /// The library must be an FMI 3.0 FMU's, whose symbols have the `fmi3FunctionTypes.h`
    /// signatures; the pointers must not be called after the library is unloaded.
    unsafe fn load(lib: &libloading::Library) -> Result<Functions, Vec<String>> {
        let mut missing = Vec::new();
        macro_rules! get {
            ($name:literal) => {
                // SAFETY: the symbol has the type of its field (contract above).
                match unsafe { lib.get(concat!($name, "\0").as_bytes()) } {
                    Ok(symbol) => Some(*symbol),
                    Err(_) => {
                        missing.push($name.to_owned());
                        None
                    }
                }
            };
        }
        let f = (
            get!("fmi3GetVersion"),
            get!("fmi3InstantiateCoSimulation"),
            get!("fmi3FreeInstance"),
            get!("fmi3EnterInitializationMode"),
            get!("fmi3ExitInitializationMode"),
            get!("fmi3Terminate"),
            get!("fmi3GetFloat64"),
            get!("fmi3SetFloat64"),
            get!("fmi3GetInt32"),
            get!("fmi3SetInt32"),
            get!("fmi3GetBoolean"),
            get!("fmi3SetBoolean"),
            get!("fmi3SetString"),
            get!("fmi3DoStep"),
            get!("fmi3GetFMUState"),
            get!("fmi3SetFMUState"),
            get!("fmi3FreeFMUState"),
        );
        if !missing.is_empty() {
            return Err(missing);
        }
        let x = "checked above";
        Ok(Functions {
            get_version: f.0.expect(x),
            instantiate: f.1.expect(x),
            free_instance: f.2.expect(x),
            enter_initialization_mode: f.3.expect(x),
            exit_initialization_mode: f.4.expect(x),
            terminate: f.5.expect(x),
            get_float64: f.6.expect(x),
            set_float64: f.7.expect(x),
            get_int32: f.8.expect(x),
            set_int32: f.9.expect(x),
            get_boolean: f.10.expect(x),
            set_boolean: f.11.expect(x),
            set_string: f.12.expect(x),
            do_step: f.13.expect(x),
            get_fmu_state: f.14.expect(x),
            set_fmu_state: f.15.expect(x),
            free_fmu_state: f.16.expect(x),
        })
    }
}

/// An unpacked FMI 3.0 Co-Simulation FMU with its library loaded. Field order: the
/// functions go before the library, the library before its folder.
pub struct Fmu3 {
    name: String,
    model_description: ModelDescription,
    functions: Functions,
    _library: libloading::Library,
    /// Value reference → name of the first Float64 variable with it (for messages).
    reals: HashMap<u32, String>,
    dir: UnpackedDir,
}

impl Fmu3 {
    /// Unpack `path`, read and check its FMI 3.0 description (a Co-Simulation interface,
    /// a binary for this platform) and load the library with every function it needs.
    pub fn load(path: impl AsRef<Path>) -> Result<Arc<Fmu3>, FmiError> {
        let (name, dir, model_description, relative) =
            crate::Fmu::read(path.as_ref(), &UnpackLimits::default())?;
        Self::from_read(name, dir, model_description, relative)
    }

    /// The library of an FMU [`crate::Fmu::read`] unpacked, loaded.
    pub(crate) fn from_read(
        name: String,
        dir: UnpackedDir,
        model_description: ModelDescription,
        relative: String,
    ) -> Result<Arc<Fmu3>, FmiError> {
        let unsupported = |message: String| FmiError::Unsupported {
            fmu: name.clone(),
            message,
        };
        if !model_description.fmi_version.starts_with('3') {
            return Err(unsupported("not an FMI 3.0 FMU".into()));
        }
        let library_path: PathBuf = dir.path().join(&relative);
        let needs_tool =
            (model_description.co_simulation.as_ref()).is_some_and(|cs| cs.needs_execution_tool);
        let library =
            crate::library::open_fmu_library(&library_path, needs_tool).map_err(|message| {
                FmiError::Library {
                    fmu: name.clone(),
                    library: relative.clone(),
                    message,
                }
            })?;
        // SAFETY: an FMI 3.0 FMU's library (its description says so).
        let functions =
            unsafe { Functions::load(&library) }.map_err(|symbols| FmiError::MissingSymbols {
                fmu: name.clone(),
                library: relative.clone(),
                symbols,
            })?;
        // SAFETY: no arguments; a static C string.
        let version = unsafe { CStr::from_ptr((functions.get_version)()) }
            .to_string_lossy()
            .into_owned();
        if !version.starts_with("3.") {
            return Err(unsupported(format!(
                "fmi3GetVersion() returned \"{version}\", expected \"3.0\""
            )));
        }
        let reals = (model_description.model_variables.iter())
            .filter(|v| matches!(v.kind, model_description::VariableKind::Real(_)))
            .map(|v| (v.value_reference, v.name.clone()))
            .collect();
        Ok(Arc::new(Fmu3 {
            name,
            model_description,
            functions,
            _library: library,
            reals,
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

    /// `fmi3InstantiateCoSimulation` with the options (no event mode, no early return).
    pub fn instantiate(
        self: &Arc<Self>,
        options: &InstantiateOptions,
    ) -> Result<Instance3, FmiError> {
        let cs = self
            .model_description
            .co_simulation
            .as_ref()
            .expect("checked on load");
        let name = options
            .instance_name
            .clone()
            .unwrap_or_else(|| cs.model_identifier.clone());
        let failed = |message: String| FmiError::Unsupported {
            fmu: self.name.clone(),
            message,
        };
        let c = |s: &str, what: &str| {
            CString::new(s).map_err(|_| failed(format!("{what} \"{s}\" contains a NUL character")))
        };
        let (c_name, token) = (
            c(&name, "instanceName")?,
            c(&self.model_description.guid, "instantiationToken")?,
        );
        let resources = c(
            &format!("{}/", self.dir.path().join("resources").display()),
            "resourcePath",
        )?;
        let env = Box::new(Env {
            sink: LogSink::new(options.echo_log),
            instance: name.clone(),
        });
        // SAFETY: valid strings; the environment is boxed and outlives the instance
        // (Instance3 frees the instance before dropping it).
        let instance = unsafe {
            (self.functions.instantiate)(
                c_name.as_ptr(),
                token.as_ptr(),
                resources.as_ptr(),
                u8::from(options.visible),
                u8::from(options.logging_on),
                fmi3False,
                fmi3False,
                std::ptr::null(),
                0,
                &*env as *const Env as *mut c_void,
                Some(log_message),
                None,
            )
        };
        if instance.is_null() {
            return Err(FmiError::Call3 {
                fmu: self.name.clone(),
                message: format!(
                    "fmi3InstantiateCoSimulation(instanceName=\"{name}\") failed (returned NULL){}",
                    logged(env.sink.take_call_messages())
                ),
            });
        }
        Ok(Instance3 {
            fmu: self.clone(),
            instance,
            env,
            start: (None, 0.0, None),
            terminated: false,
            last_successful_time: 0.0,
            saved: std::ptr::null_mut(),
            time: 0.0,
        })
    }
}

/// What the FMU's logger reaches: the instance's sink and name.
struct Env {
    sink: LogSink,
    instance: String,
}

/// The FMI 3.0 logger: hands each message to the instance's sink.
unsafe extern "C" fn log_message(
    env: *mut c_void,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    let text = |p: *const c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: a NUL-terminated string from the FMU.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    if env.is_null() {
        return;
    }
    // SAFETY: the environment passed at instantiation, alive while the instance is.
    let env = unsafe { &*(env as *const Env) };
    use crate::logger::LogReceiver;
    env.sink.receive(LogMessage {
        instance: env.instance.clone(),
        status: crate::Status::from_raw(status),
        category: text(category),
        message: text(message),
        fmi_version: 3,
    });
}

/// "; the FMU logged: …" for a failed call's messages.
fn logged(messages: Vec<LogMessage>) -> String {
    let mut text = String::new();
    if !messages.is_empty() {
        text.push_str("; the FMU logged:");
        for m in messages {
            text.push_str("\n  ");
            text.push_str(&m.to_string());
        }
    }
    text
}

/// An instance of an FMI 3.0 Co-Simulation FMU.
pub struct Instance3 {
    fmu: Arc<Fmu3>,
    instance: fmi3Instance,
    env: Box<Env>,
    /// (tolerance, start, stop) of `setup_experiment`, passed on entering initialisation.
    start: (Option<f64>, f64, Option<f64>),
    terminated: bool,
    last_successful_time: f64,
    /// The rollback slot (`fmi3GetFMUState`), NULL when empty.
    saved: fmi3FMUState,
    /// The communication point of the last step, for messages.
    time: f64,
}

// SAFETY: an FMI instance may be used from any one thread at a time (FMI 3.0, 2.4.1);
// Instance3 is never shared (no Sync), only moved, as FMI 2.0's Instance is.
unsafe impl Send for Instance3 {}

impl Instance3 {
    /// Run one call: collect its messages, map its status (`Discard` passes when
    /// `allow_discard`).
    fn call(
        &self,
        what: &dyn Fn() -> String,
        allow_discard: bool,
        f: impl FnOnce(&Functions, fmi3Instance) -> fmi3Status,
    ) -> Result<fmi3Status, String> {
        self.env.sink.begin_call();
        let status = f(&self.fmu.functions, self.instance);
        match status {
            fmi3OK | fmi3Warning => Ok(status),
            fmi3Discard if allow_discard => Ok(status),
            _ => {
                let name = match status {
                    fmi3Discard => "fmi3Discard".to_owned(),
                    fmi3Error => "fmi3Error".to_owned(),
                    fmi3Fatal => "fmi3Fatal".to_owned(),
                    other => format!("the illegal status code {other}"),
                };
                Err(format!(
                    "{}: {} returned {name} (instance \"{}\"){}",
                    self.fmu.name,
                    what(),
                    self.env.instance,
                    logged(self.env.sink.take_call_messages())
                ))
            }
        }
    }

    fn names(&self, vrs: &[u32]) -> String {
        let names: Vec<&str> = vrs
            .iter()
            .map(|vr| self.fmu.reals.get(vr).map_or("?", String::as_str))
            .collect();
        names.join(", ")
    }
}

impl Drop for Instance3 {
    fn drop(&mut self) {
        // SAFETY: the live instance and its saved state, freed once, before the environment.
        unsafe {
            if !self.saved.is_null() {
                (self.fmu.functions.free_fmu_state)(self.instance, &mut self.saved);
            }
            (self.fmu.functions.free_instance)(self.instance);
        }
    }
}

/// Strings as `fmi3String`s, alive with the returned vector.
fn c_strings(values: &[&str]) -> Result<Vec<CString>, String> {
    values
        .iter()
        .map(|s| {
            CString::new(*s).map_err(|_| format!("the string \"{s}\" contains a NUL character"))
        })
        .collect()
}

impl FmiCalls for Instance3 {
    fn name(&self) -> &str {
        &self.env.instance
    }
    fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> Result<(), String> {
        self.start = (tolerance, start, stop);
        self.time = start;
        Ok(())
    }
    fn enter_initialization_mode(&mut self) -> Result<(), String> {
        let (tol, start, stop) = self.start;
        let what = || format!("fmi3EnterInitializationMode(startTime={start})");
        self.call(&what, false, |f, i| {
            // SAFETY: the live instance.
            unsafe {
                (f.enter_initialization_mode)(
                    i,
                    u8::from(tol.is_some()),
                    tol.unwrap_or(0.0),
                    start,
                    u8::from(stop.is_some()),
                    stop.unwrap_or(0.0),
                )
            }
        })
        .map(drop)
    }
    fn exit_initialization_mode(&mut self) -> Result<(), String> {
        // SAFETY: the live instance.
        self.call(
            &|| "fmi3ExitInitializationMode".into(),
            false,
            |f, i| unsafe { (f.exit_initialization_mode)(i) },
        )
        .map(drop)
    }
    fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        let what = || format!("fmi3SetFloat64({})", self.names(vrs));
        // SAFETY: arrays of the stated length.
        self.call(&what, false, |f, i| unsafe {
            (f.set_float64)(i, vrs.as_ptr(), vrs.len(), values.as_ptr(), values.len())
        })
        .map(drop)
    }
    fn get_real(&mut self, vrs: &[u32], values: &mut [f64]) -> Result<(), String> {
        let what = || format!("fmi3GetFloat64({})", self.names(vrs));
        // SAFETY: arrays of the stated length.
        self.call(&what, false, |f, i| unsafe {
            (f.get_float64)(
                i,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        })?;
        if let Some(k) = crate::first_non_finite(values) {
            return Err(format!(
                "{}: fmi3GetFloat64 returned the non-finite value {} for variable \"{}\" (value reference {}) at t = {} s",
                self.fmu.name,
                values[k],
                self.names(&vrs[k..=k]),
                vrs[k],
                self.time
            ));
        }
        Ok(())
    }
    fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> Result<(), String> {
        // SAFETY: arrays of the stated length.
        self.call(&|| "fmi3SetInt32".into(), false, |f, i| unsafe {
            (f.set_int32)(i, vrs.as_ptr(), vrs.len(), values.as_ptr(), values.len())
        })
        .map(drop)
    }
    fn get_integer(&mut self, vrs: &[u32], values: &mut [i32]) -> Result<(), String> {
        // SAFETY: arrays of the stated length.
        self.call(&|| "fmi3GetInt32".into(), false, |f, i| unsafe {
            (f.get_int32)(
                i,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        })
        .map(drop)
    }
    fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> Result<(), String> {
        let bytes: Vec<u8> = values.iter().map(|&b| u8::from(b)).collect();
        // SAFETY: arrays of the stated length.
        self.call(&|| "fmi3SetBoolean".into(), false, |f, i| unsafe {
            (f.set_boolean)(i, vrs.as_ptr(), vrs.len(), bytes.as_ptr(), bytes.len())
        })
        .map(drop)
    }
    fn get_boolean(&mut self, vrs: &[u32], values: &mut [bool]) -> Result<(), String> {
        let mut bytes = vec![0u8; values.len()];
        // SAFETY: arrays of the stated length.
        self.call(&|| "fmi3GetBoolean".into(), false, |f, i| unsafe {
            (f.get_boolean)(i, vrs.as_ptr(), vrs.len(), bytes.as_mut_ptr(), bytes.len())
        })?;
        for (v, b) in values.iter_mut().zip(bytes) {
            *v = b != 0;
        }
        Ok(())
    }
    fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> Result<(), String> {
        let owned = c_strings(values)?;
        let ptrs: Vec<fmi3String> = owned.iter().map(|s| s.as_ptr()).collect();
        // SAFETY: arrays of the stated length; the strings outlive the call.
        self.call(&|| "fmi3SetString".into(), false, |f, i| unsafe {
            (f.set_string)(i, vrs.as_ptr(), vrs.len(), ptrs.as_ptr(), ptrs.len())
        })
        .map(drop)
    }
    fn do_step(&mut self, t: f64, h: f64) -> Result<bool, String> {
        self.step(t, h, false)
    }
    fn do_step_final(&mut self, t: f64, h: f64) -> Result<bool, String> {
        self.step(t, h, true)
    }
    fn save_state(&mut self) -> Result<(), String> {
        let slot = &mut self.saved as *mut fmi3FMUState;
        // SAFETY: the live instance; the slot is NULL or a state of this instance.
        self.call(&|| "fmi3GetFMUState".into(), false, |f, i| unsafe {
            (f.get_fmu_state)(i, slot)
        })
        .map(drop)
    }
    fn restore_state(&mut self) -> Result<(), String> {
        if self.saved.is_null() {
            return Err(format!("{}: no saved state", self.fmu.name));
        }
        let state = self.saved;
        // SAFETY: a state of this instance.
        self.call(&|| "fmi3SetFMUState".into(), false, |f, i| unsafe {
            (f.set_fmu_state)(i, state)
        })
        .map(drop)
    }
    fn terminated(&mut self) -> Result<bool, String> {
        Ok(self.terminated)
    }
    fn last_successful_time(&mut self) -> Result<f64, String> {
        Ok(self.last_successful_time)
    }
    fn terminate(&mut self) -> Result<(), String> {
        // SAFETY: the live instance.
        self.call(&|| "fmi3Terminate".into(), false, |f, i| unsafe {
            (f.terminate)(i)
        })
        .map(drop)
    }
}

impl Instance3 {
    /// `fmi3DoStep`; `true` when discarded (with `terminateSimulation` and
    /// `lastSuccessfulTime` kept for the status queries).
    fn step(&mut self, t: f64, h: f64, final_step: bool) -> Result<bool, String> {
        self.time = t;
        let (mut event, mut terminate, mut early, mut last) = (fmi3False, fmi3False, fmi3False, t);
        let what = || format!("fmi3DoStep(t={t}, h={h})");
        let status = self.call(&what, true, |f, i| {
            // SAFETY: the live instance and four writable outputs.
            unsafe {
                (f.do_step)(
                    i,
                    t,
                    h,
                    u8::from(final_step),
                    &mut event,
                    &mut terminate,
                    &mut early,
                    &mut last,
                )
            }
        })?;
        self.terminated = terminate != 0;
        self.last_successful_time = last;
        if early != 0 && status != fmi3Discard {
            return Err(format!(
                "{}: fmi3DoStep(t={t}, h={h}) returned early at t = {last} s although early return was not allowed",
                self.fmu.name
            ));
        }
        Ok(status == fmi3Discard)
    }
}
