//! A loaded FMU ([`Fmu`]) and its instances ([`Instance`]).
//!
//! This module holds the two types, the frame every FMI call of an instance runs in
//! ([`Instance`]'s private `call`) and the helpers the calls share; the calls themselves
//! are grouped by FMI function group in the submodules:
//!
//! - `fmu`: loading an FMU ([`Fmu::load`]), what it describes, and [`Fmu::instantiate`];
//! - `lifecycle`: debug logging, experiment set-up, initialization, terminate and reset;
//! - `values`: getting and setting Real, Integer, Boolean and String variables;
//! - `slave`: the Co-Simulation calls (stepping, derivatives, status) with [`StepResult`]
//!   and [`StatusKind`];
//! - `state`: getting, setting and serializing the FMU state ([`FmuState`]).

mod fmu;
mod lifecycle;
mod slave;
mod state;
mod values;

pub use slave::{StatusKind, StepResult};
pub use state::FmuState;

use crate::archive::UnpackedDir;
use crate::error::{CallStatus, FmiError, Status};
use crate::library::Library;
use crate::logger::{LogEnv, LogMessage, LogSink};
use fmi2::types::*;
use fmi2::Functions;
use model_description::ModelDescription;
use std::collections::HashMap;
use std::ffi::{c_char, CStr, CString};
use std::path::PathBuf;
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

impl InstantiateOptions {
    /// A system component's instance: named, not visible, debug logging off, and what it
    /// logs echoed to standard error as it comes (as `tbi cosim` runs its components).
    pub fn component(name: &str) -> Self {
        InstantiateOptions {
            instance_name: Some(name.to_owned()),
            echo_log: true,
            ..Self::default()
        }
    }
}

impl Fmu {
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
}
