//! The checks run by [`super::run`].

use std::ffi::{c_char, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::ptr;

use super::{Check, HarnessConfig, Library, LogCapture, LogMessage, Report};
use crate::library::LoadError;
use fmi2::types::*;

type Outcome = Result<(), String>;
/// Brings a fresh instance into the state a check needs.
type Prepare = fn(&mut Slave) -> Outcome;

/// Collects checks; a panic inside a check (a harness bug or an assertion on a
/// malformed return value) is recorded as a failure.
struct Checker {
    checks: Vec<Check>,
}

impl Checker {
    fn check(&mut self, name: impl Into<String>, f: impl FnOnce() -> Outcome) {
        let name = name.into();
        let (passed, message) = match catch_unwind(AssertUnwindSafe(f)) {
            Ok(Ok(())) => (true, String::new()),
            Ok(Err(m)) => (false, m),
            Err(p) => (
                false,
                format!(
                    "panic in the harness: {}",
                    p.downcast_ref::<String>()
                        .cloned()
                        .or_else(|| p.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                        .unwrap_or_default()
                ),
            ),
        };
        self.checks.push(Check {
            name,
            passed,
            message,
        });
    }
}

fn status_name(s: fmi2Status) -> String {
    Status::from_raw(s).map_or_else(|| format!("invalid status {s}"), |s| s.name().to_owned())
}

fn expect(got: fmi2Status, want: &[Status], what: &str) -> Outcome {
    if want.iter().any(|w| w.raw() == got) {
        Ok(())
    } else {
        let want: Vec<&str> = want.iter().map(|w| w.name()).collect();
        Err(format!(
            "{what} returned {} (expected {})",
            status_name(got),
            want.join(" or ")
        ))
    }
}

fn expect_ok(got: fmi2Status, what: &str) -> Outcome {
    expect(got, &[Status::Ok], what)
}

/// An error (or worse) message must have been logged.
fn expect_logged_error(records: &[LogMessage], what: &str) -> Outcome {
    match records.iter().find(|r| r.is_error()) {
        Some(r) if !r.message.trim().is_empty() => Ok(()),
        Some(_) => Err(format!("{what}: an empty error message was logged")),
        None => Err(format!(
            "{what}: no fmi2Error message was logged (got {} other messages)",
            records.len()
        )),
    }
}

fn describe(records: &[LogMessage]) -> String {
    records
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(" | ")
}

/// Everything the checks share.
struct Ctx<'a> {
    cfg: &'a HarnessConfig,
    lib: &'a Library,
    guid: CString,
    uri: CString,
}

/// Arguments of one `fmi2Instantiate` call (valid unless changed).
struct InstantiateArgs {
    name: Option<CString>,
    fmu_type: fmi2Type,
    guid: Option<CString>,
    uri: Option<CString>,
    logger: bool,
    functions: bool,
    logging_on: bool,
}

impl Ctx<'_> {
    fn valid_args(&self) -> InstantiateArgs {
        InstantiateArgs {
            name: Some(c"harness".to_owned()),
            fmu_type: fmi2CoSimulation,
            guid: Some(self.guid.clone()),
            uri: Some(self.uri.clone()),
            logger: true,
            functions: true,
            logging_on: self.cfg.logging_on,
        }
    }

    fn instantiate_with(&self, args: &InstantiateArgs, log: &LogCapture) -> fmi2Component {
        let mut callbacks = log.callbacks();
        if !args.logger {
            callbacks.logger = None;
        }
        let cstr = |s: &Option<CString>| s.as_ref().map_or(ptr::null(), |s| s.as_ptr());
        let functions: *const fmi2CallbackFunctions = if args.functions {
            &callbacks
        } else {
            ptr::null()
        };
        // SAFETY: all strings are NULL or NUL-terminated; `callbacks` is copied by a
        // conforming FMU, and `log` outlives the instance (see Slave).
        unsafe {
            (self.lib.instantiate)(
                cstr(&args.name),
                args.fmu_type,
                cstr(&args.guid),
                cstr(&args.uri),
                functions,
                fmi2False,
                if args.logging_on { fmi2True } else { fmi2False },
            )
        }
    }

    /// A valid instance.
    fn slave(&self) -> Result<Slave<'_>, String> {
        self.slave_with(&self.valid_args())
    }

    fn slave_with(&self, args: &InstantiateArgs) -> Result<Slave<'_>, String> {
        let log = LogCapture::new();
        let c = self.instantiate_with(args, &log);
        if c.is_null() {
            return Err(format!(
                "fmi2Instantiate with valid arguments returned NULL; log: {}",
                describe(&log.take())
            ));
        }
        Ok(Slave {
            lib: self.lib,
            c,
            t: self.cfg.start_time,
            cfg: self.cfg,
            log,
        })
    }

    /// A valid instance in step mode (after `init`).
    fn stepping(&self) -> Result<Slave<'_>, String> {
        let mut s = self.slave()?;
        s.init(None)?;
        Ok(s)
    }
}

/// One FMU instance driven like a master does; freed on drop (before its logger).
struct Slave<'a> {
    lib: &'a Library,
    cfg: &'a HarnessConfig,
    c: fmi2Component,
    /// The master's time.
    t: f64,
    log: LogCapture,
}

impl Drop for Slave<'_> {
    fn drop(&mut self) {
        // SAFETY: created by fmi2Instantiate and not freed.
        unsafe { (self.lib.free_instance)(self.c) }
    }
}

// SAFETY (all methods): `self.c` is a live instance; pointers passed are valid for the
// stated lengths.
impl Slave<'_> {
    fn setup(&self, stop: Option<f64>) -> fmi2Status {
        unsafe {
            (self.lib.setup_experiment)(
                self.c,
                fmi2False,
                0.0,
                self.cfg.start_time,
                fmi2Boolean::from(stop.is_some()),
                stop.unwrap_or(0.0),
            )
        }
    }

    fn enter(&self) -> fmi2Status {
        unsafe { (self.lib.enter_initialization_mode)(self.c) }
    }

    fn exit(&self) -> fmi2Status {
        unsafe { (self.lib.exit_initialization_mode)(self.c) }
    }

    fn terminate(&self) -> fmi2Status {
        unsafe { (self.lib.terminate)(self.c) }
    }

    fn reset(&mut self) -> fmi2Status {
        self.t = self.cfg.start_time;
        unsafe { (self.lib.reset)(self.c) }
    }

    /// SetupExperiment, Enter/ExitInitializationMode, all fmi2OK.
    fn init(&mut self, stop: Option<f64>) -> Outcome {
        expect_ok(self.setup(stop), "fmi2SetupExperiment")?;
        expect_ok(self.enter(), "fmi2EnterInitializationMode")?;
        expect_ok(
            self.set(self.cfg.input_vr, self.cfg.input_value),
            "fmi2SetReal(input) in initialization mode",
        )?;
        expect_ok(self.exit(), "fmi2ExitInitializationMode")?;
        self.t = self.cfg.start_time;
        Ok(())
    }

    fn set(&self, vr: u32, value: f64) -> fmi2Status {
        unsafe { (self.lib.set_real)(self.c, &vr, 1, &value) }
    }

    fn get(&self, vr: u32) -> (fmi2Status, f64) {
        let mut v = f64::NAN;
        let s = unsafe { (self.lib.get_real)(self.c, &vr, 1, &mut v) };
        (s, v)
    }

    fn do_step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { (self.lib.do_step)(self.c, t, h, fmi2False) }
    }

    /// One communication step from the master's time; advances it on fmi2OK.
    fn step(&mut self) -> fmi2Status {
        let h = self.cfg.step_size;
        let s = self.do_step(self.t, h);
        if s == fmi2OK {
            self.t += h;
        }
        s
    }

    fn last_successful_time(&self) -> (fmi2Status, f64) {
        let mut v = f64::NAN;
        let s = unsafe { (self.lib.get_real_status)(self.c, fmi2LastSuccessfulTime, &mut v) };
        (s, v)
    }

    /// `n` steps with the input `input_value·(1 + k/8)` for the `k`-th step; returns
    /// (time bits, output bits) after each step.
    fn trajectory(&mut self, first_k: usize, n: usize) -> Result<Vec<(u64, u64)>, String> {
        let mut out = Vec::with_capacity(n);
        for k in first_k..first_k + n {
            let u = self.cfg.input_value * (1.0 + k as f64 / 8.0);
            expect_ok(self.set(self.cfg.input_vr, u), "fmi2SetReal(input)")?;
            let s = self.step();
            expect_ok(s, &format!("fmi2DoStep #{k} at t = {}", self.t))
                .map_err(|e| format!("{e}; log: {}", describe(&self.log.records())))?;
            let (s, y) = self.get(self.cfg.output_vr);
            expect_ok(s, "fmi2GetReal(output)")?;
            out.push((self.t.to_bits(), y.to_bits()));
        }
        Ok(out)
    }

    fn get_state(&self, state: &mut fmi2FMUstate) -> fmi2Status {
        unsafe { (self.lib.get_fmu_state)(self.c, state) }
    }

    fn set_state(&self, state: fmi2FMUstate) -> fmi2Status {
        unsafe { (self.lib.set_fmu_state)(self.c, state) }
    }

    fn free_state(&self, state: &mut fmi2FMUstate) -> fmi2Status {
        unsafe { (self.lib.free_fmu_state)(self.c, state) }
    }

    fn serialize(&self, state: fmi2FMUstate) -> Result<Vec<c_char>, String> {
        let mut size = 0usize;
        expect_ok(
            unsafe { (self.lib.serialized_fmu_state_size)(self.c, state, &mut size) },
            "fmi2SerializedFMUstateSize",
        )?;
        if size == 0 {
            return Err("fmi2SerializedFMUstateSize reported 0 bytes".to_owned());
        }
        let mut bytes = vec![0 as c_char; size];
        expect_ok(
            unsafe { (self.lib.serialize_fmu_state)(self.c, state, bytes.as_mut_ptr(), size) },
            "fmi2SerializeFMUstate",
        )?;
        Ok(bytes)
    }

    fn deserialize(&self, bytes: &[c_char], state: &mut fmi2FMUstate) -> fmi2Status {
        let p = if bytes.is_empty() {
            ptr::null()
        } else {
            bytes.as_ptr()
        };
        unsafe { (self.lib.de_serialize_fmu_state)(self.c, p, bytes.len(), state) }
    }

    /// Steps to the end of `k` steps, saves a state and serializes it.
    fn serialized_state_after(&mut self, k: usize) -> Result<Vec<c_char>, String> {
        self.trajectory(0, k)?;
        let mut s: fmi2FMUstate = ptr::null_mut();
        expect_ok(self.get_state(&mut s), "fmi2GetFMUstate")?;
        let bytes = self.serialize(s);
        expect_ok(self.free_state(&mut s), "fmi2FreeFMUstate")?;
        bytes
    }
}

pub(super) fn run(cfg: &HarnessConfig) -> Report {
    let mut ck = Checker { checks: Vec::new() };

    let lib = match Library::load(&cfg.library).map_err(|e| match e {
        LoadError::Open(why) => format!("cannot load {}: {why}", cfg.library.display()),
        missing => format!("{} {missing}", cfg.library.display()),
    }) {
        Ok(lib) => {
            ck.check("exports all 34 fmi2 functions", || Ok(()));
            lib
        }
        Err(e) => {
            ck.check("exports all 34 fmi2 functions", || Err(e));
            return Report { checks: ck.checks };
        }
    };
    let uri = match fmi2::uri::file_uri(&cfg.resources) {
        Ok(u) => u,
        Err(e) => {
            ck.check("resources folder is an absolute path", || Err(e));
            return Report { checks: ck.checks };
        }
    };
    let ctx = Ctx {
        cfg,
        lib: &lib,
        guid: CString::new(cfg.guid.clone()).unwrap_or_default(),
        uri: CString::new(uri).unwrap_or_default(),
    };

    platform_checks(&mut ck, &ctx);
    instantiate_checks(&mut ck, &ctx);
    null_component_checks(&mut ck, &ctx);
    illegal_state_checks(&mut ck, &ctx);
    argument_checks(&mut ck, &ctx);
    non_finite_input_checks(&mut ck, &ctx);
    fmu_state_checks(&mut ck, &ctx);
    serialization_checks(&mut ck, &ctx);
    life_cycle_checks(&mut ck, &ctx);
    status_and_logging_checks(&mut ck, &ctx);

    Report { checks: ck.checks }
}

fn platform_checks(ck: &mut Checker, ctx: &Ctx) {
    let c_string = |p: *const c_char| {
        if p.is_null() {
            None
        } else {
            // SAFETY: the FMU returns a static NUL-terminated string.
            Some(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
        }
    };
    ck.check("fmi2GetTypesPlatform returns \"default\"", || {
        // SAFETY: no arguments.
        match c_string(unsafe { (ctx.lib.get_types_platform)() }) {
            Some(s) if s == "default" => Ok(()),
            other => Err(format!("got {other:?}")),
        }
    });
    ck.check("fmi2GetVersion returns \"2.0\"", || {
        // SAFETY: no arguments.
        match c_string(unsafe { (ctx.lib.get_version)() }) {
            Some(s) if s == "2.0" => Ok(()),
            other => Err(format!("got {other:?}")),
        }
    });
    ck.check("library file stem is the model identifier", || {
        let stem = ctx
            .lib
            .path()
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let id = &ctx.cfg.model_identifier;
        if stem == *id || stem == format!("lib{id}") {
            Ok(())
        } else {
            Err(format!("file stem '{stem}' vs modelIdentifier '{id}'"))
        }
    });
    ck.check("valid instantiation reaches step mode and steps", || {
        let mut s = ctx.stepping()?;
        s.trajectory(0, 3).map(|_| ())
    });
}

fn instantiate_checks(ck: &mut Checker, ctx: &Ctx) {
    let refused = |args: InstantiateArgs, needs_log: bool| -> Outcome {
        let log = LogCapture::new();
        let c = ctx.instantiate_with(&args, &log);
        if !c.is_null() {
            // SAFETY: a live instance returned by fmi2Instantiate.
            unsafe { (ctx.lib.free_instance)(c) };
            return Err("fmi2Instantiate returned an instance".to_owned());
        }
        if needs_log {
            expect_logged_error(&log.take(), "fmi2Instantiate")?;
        }
        Ok(())
    };
    ck.check(
        "fmi2Instantiate refuses a wrong GUID with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.guid = Some(c"{00000000-0000-0000-0000-000000000000}".to_owned());
            refused(a, true)
        },
    );
    ck.check(
        "fmi2Instantiate refuses fmuType fmi2ModelExchange with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.fmu_type = fmi2ModelExchange;
            refused(a, true)
        },
    );
    ck.check(
        "fmi2Instantiate refuses an unknown fmuType with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.fmu_type = 42;
            refused(a, true)
        },
    );
    ck.check("fmi2Instantiate refuses a NULL logger", || {
        let mut a = ctx.valid_args();
        a.logger = false;
        refused(a, false)
    });
    ck.check("fmi2Instantiate refuses NULL callback functions", || {
        let mut a = ctx.valid_args();
        a.functions = false;
        refused(a, false)
    });
    ck.check(
        "fmi2Instantiate refuses a missing resources folder with a logged reason",
        || {
            let missing = ctx
                .cfg
                .resources
                .join(format!("no-such-folder-{}", std::process::id()));
            let uri = fmi2::uri::file_uri(&missing)?;
            let mut a = ctx.valid_args();
            a.uri = Some(CString::new(uri).map_err(|e| e.to_string())?);
            refused(a, true)
        },
    );
    ck.check(
        "fmi2Instantiate refuses a NULL fmuResourceLocation with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.uri = None;
            refused(a, true)
        },
    );
    ck.check(
        "fmi2Instantiate refuses a non-file resource URI with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.uri = Some(c"http://example.invalid/resources".to_owned());
            refused(a, true)
        },
    );
    ck.check(
        "fmi2Instantiate refuses a NULL GUID with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.guid = None;
            refused(a, true)
        },
    );
    ck.check(
        "fmi2Instantiate refuses a NULL instanceName with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.name = None;
            refused(a, true)
        },
    );
    ck.check(
        "fmi2Instantiate refuses an empty instanceName with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.name = Some(c"".to_owned());
            refused(a, true)
        },
    );
    ck.check("fmi2Instantiate copies its string arguments", || {
        let mut a = ctx.valid_args();
        a.name = Some(c"copied-name".to_owned());
        let mut s = ctx.slave_with(&a)?;
        // Overwrite the caller's buffers; the instance must not depend on them.
        drop(a);
        let garbage = vec![b'#'; "copied-name".len() + 1];
        std::hint::black_box(&garbage);
        s.init(None)?;
        s.trajectory(0, 2)?;
        expect(
            s.do_step(-1e9, 1.0),
            &[Status::Error],
            "fmi2DoStep at a wrong time",
        )?;
        let logged = s.log.take();
        match logged.iter().find(|r| r.is_error()) {
            Some(r) if r.instance == "copied-name" => Ok(()),
            Some(r) => Err(format!("logged with instance name '{}'", r.instance)),
            None => Err("no error logged".to_owned()),
        }
    });
}

fn null_component_checks(ck: &mut Checker, ctx: &Ctx) {
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

/// Fresh instance → `prepare` → `call` must give fmi2Error with a logged message.
fn illegal(
    ck: &mut Checker,
    ctx: &Ctx,
    name: &str,
    prepare: impl FnOnce(&mut Slave) -> Outcome,
    call: impl FnOnce(&mut Slave) -> fmi2Status,
) {
    ck.check(
        format!("illegal call: {name} → fmi2Error with a logged message"),
        || {
            let mut s = ctx.slave()?;
            prepare(&mut s)?;
            s.log.take();
            let status = call(&mut s);
            expect(status, &[Status::Error], name)?;
            expect_logged_error(&s.log.take(), name)
        },
    );
}

fn to_init_mode(s: &mut Slave) -> Outcome {
    expect_ok(s.setup(None), "fmi2SetupExperiment")?;
    expect_ok(s.enter(), "fmi2EnterInitializationMode")
}

fn to_step_mode(s: &mut Slave) -> Outcome {
    s.init(None)
}

fn to_terminated(s: &mut Slave) -> Outcome {
    s.init(None)?;
    s.trajectory(0, 1)?;
    expect_ok(s.terminate(), "fmi2Terminate")
}

fn nothing(_: &mut Slave) -> Outcome {
    Ok(())
}

fn illegal_state_checks(ck: &mut Checker, ctx: &Ctx) {
    let h = ctx.cfg.step_size;
    let out = ctx.cfg.output_vr;
    let inp = ctx.cfg.input_vr;
    illegal(ck, ctx, "fmi2DoStep in Instantiated", nothing, |s| {
        s.do_step(s.t, h)
    });
    illegal(
        ck,
        ctx,
        "fmi2DoStep in InitializationMode",
        to_init_mode,
        |s| s.do_step(s.t, h),
    );
    illegal(
        ck,
        ctx,
        "fmi2DoStep after fmi2Terminate",
        to_terminated,
        |s| s.do_step(s.t, h),
    );
    illegal(ck, ctx, "fmi2GetReal in Instantiated", nothing, |s| {
        s.get(out).0
    });
    illegal(
        ck,
        ctx,
        "fmi2SetReal after fmi2Terminate",
        to_terminated,
        |s| s.set(inp, 1.0),
    );
    illegal(ck, ctx, "fmi2Terminate twice", to_terminated, |s| {
        s.terminate()
    });
    illegal(ck, ctx, "fmi2Terminate in Instantiated", nothing, |s| {
        s.terminate()
    });
    illegal(
        ck,
        ctx,
        "fmi2Terminate in InitializationMode",
        to_init_mode,
        |s| s.terminate(),
    );
    illegal(
        ck,
        ctx,
        "fmi2ExitInitializationMode in Instantiated",
        nothing,
        |s| s.exit(),
    );
    illegal(
        ck,
        ctx,
        "fmi2EnterInitializationMode twice",
        to_init_mode,
        |s| s.enter(),
    );
    illegal(
        ck,
        ctx,
        "fmi2EnterInitializationMode in StepComplete",
        to_step_mode,
        |s| s.enter(),
    );
    illegal(
        ck,
        ctx,
        "fmi2SetupExperiment in StepComplete",
        to_step_mode,
        |s| s.setup(None),
    );
    illegal(
        ck,
        ctx,
        "fmi2SetupExperiment in InitializationMode",
        to_init_mode,
        |s| s.setup(None),
    );
    illegal(
        ck,
        ctx,
        "fmi2CancelStep in StepComplete (synchronous FMU)",
        to_step_mode,
        |s| unsafe { (s.lib.cancel_step)(s.c) },
    );
    illegal(
        ck,
        ctx,
        "fmi2GetBooleanStatus in Instantiated",
        nothing,
        |s| {
            let mut v = 0;
            unsafe { (s.lib.get_boolean_status)(s.c, fmi2Terminated, &mut v) }
        },
    );
    illegal(
        ck,
        ctx,
        "fmi2GetRealStatus in InitializationMode",
        to_init_mode,
        |s| {
            let mut v = 0.0;
            unsafe { (s.lib.get_real_status)(s.c, fmi2LastSuccessfulTime, &mut v) }
        },
    );
    illegal(
        ck,
        ctx,
        "fmi2GetDirectionalDerivative (not provided)",
        to_step_mode,
        |s| {
            let (vr, dv) = (out, 1.0);
            let mut r = 0.0;
            unsafe { (s.lib.get_directional_derivative)(s.c, &vr, 1, &inp, 1, &dv, &mut r) }
        },
    );
    illegal(
        ck,
        ctx,
        "fmi2SetRealInputDerivatives (canInterpolateInputs=false)",
        to_step_mode,
        |s| {
            let (order, v) = (1, 0.0);
            unsafe { (s.lib.set_real_input_derivatives)(s.c, &inp, 1, &order, &v) }
        },
    );
    illegal(
        ck,
        ctx,
        "fmi2GetRealOutputDerivatives (maxOutputDerivativeOrder=0)",
        to_step_mode,
        |s| {
            let order = 1;
            let mut v = 0.0;
            unsafe { (s.lib.get_real_output_derivatives)(s.c, &out, 1, &order, &mut v) }
        },
    );

    ck.check(
        "after an error only recovery calls are accepted; fmi2Reset recovers",
        || {
            let mut s = ctx.slave()?;
            expect(
                s.do_step(s.t, h),
                &[Status::Error],
                "fmi2DoStep in Instantiated",
            )?;
            expect(
                s.setup(None),
                &[Status::Error],
                "fmi2SetupExperiment after an error",
            )?;
            expect(
                s.set(inp, 1.0),
                &[Status::Error],
                "fmi2SetReal after an error",
            )?;
            expect_ok(s.reset(), "fmi2Reset after an error")?;
            s.init(None)?;
            s.trajectory(0, 2).map(|_| ())
        },
    );
}

fn argument_checks(ck: &mut Checker, ctx: &Ctx) {
    let h = ctx.cfg.step_size;
    let bad_step = |ck: &mut Checker, name: &str, dt: f64, step: f64| {
        ck.check(
            format!("fmi2DoStep refuses {name} with fmi2Error and a logged message"),
            || {
                let mut s = ctx.stepping()?;
                s.trajectory(0, 2)?;
                s.log.take();
                expect(s.do_step(s.t + dt, step), &[Status::Error], "fmi2DoStep")?;
                expect_logged_error(&s.log.take(), "fmi2DoStep")
            },
        );
    };
    bad_step(
        ck,
        "a communication point ahead of the FMU's time",
        10.0 * h,
        h,
    );
    bad_step(ck, "a communication point behind the FMU's time", -h, h);
    bad_step(ck, "h = 0", 0.0, 0.0);
    bad_step(ck, "h < 0", 0.0, -h);
    bad_step(ck, "h = NaN", 0.0, f64::NAN);
    bad_step(ck, "h = +inf", 0.0, f64::INFINITY);
    bad_step(ck, "a NaN communication point", f64::NAN, h);

    ck.check("fmi2DoStep refuses a step past the stop time", || {
        let mut s = ctx.slave()?;
        let stop = ctx.cfg.start_time + 2.0 * h;
        s.init(Some(stop))?;
        expect_ok(s.step(), "fmi2DoStep #1")?;
        expect_ok(s.step(), "fmi2DoStep #2 (ends at the stop time)")?;
        s.log.take();
        expect(s.step(), &[Status::Error], "fmi2DoStep past the stop time")?;
        expect_logged_error(&s.log.take(), "fmi2DoStep past the stop time")
    });

    ck.check(
        "fmi2DoStep accepts a communication point within rounding of its time",
        || {
            let mut s = ctx.stepping()?;
            s.trajectory(0, 3)?;
            let t = s.t * (1.0 + 1e-15) + 1e-16;
            expect_ok(s.do_step(t, h), "fmi2DoStep at t(1+1e-15)")
        },
    );

    let null_array = |ck: &mut Checker, name: &str, call: fn(&Slave, u32) -> fmi2Status| {
        ck.check(format!("{name} → fmi2Error"), || {
            let s = ctx.stepping()?;
            expect(call(&s, ctx.cfg.output_vr), &[Status::Error], name)
        });
    };
    null_array(
        ck,
        "fmi2GetReal with value[] = NULL, nvr = 1",
        |s, vr| unsafe { (s.lib.get_real)(s.c, &vr, 1, ptr::null_mut()) },
    );
    null_array(ck, "fmi2GetReal with vr[] = NULL, nvr = 1", |s, _| unsafe {
        let mut v = 0.0;
        (s.lib.get_real)(s.c, ptr::null(), 1, &mut v)
    });
    null_array(
        ck,
        "fmi2SetReal with value[] = NULL, nvr = 1",
        |s, _| unsafe {
            let vr = s.cfg.input_vr;
            (s.lib.set_real)(s.c, &vr, 1, ptr::null())
        },
    );
    null_array(ck, "fmi2GetFMUstate with FMUstate = NULL", |s, _| unsafe {
        (s.lib.get_fmu_state)(s.c, ptr::null_mut())
    });
    null_array(ck, "fmi2SetFMUstate with FMUstate = NULL", |s, _| {
        s.set_state(ptr::null_mut())
    });
    null_array(ck, "fmi2GetReal of an unknown value reference", |s, _| {
        s.get(0xFFFF_FFF0).0
    });

    ck.check("empty arrays (nvr = 0, NULL pointers) are fmi2OK", || {
        let s = ctx.stepping()?;
        // SAFETY: nvr = 0, nothing is read or written.
        let get = unsafe { (s.lib.get_real)(s.c, ptr::null(), 0, ptr::null_mut()) };
        let set = unsafe { (s.lib.set_real)(s.c, ptr::null(), 0, ptr::null()) };
        expect_ok(get, "fmi2GetReal(nvr = 0)")?;
        expect_ok(set, "fmi2SetReal(nvr = 0)")
    });
}

fn non_finite_input_checks(ck: &mut Checker, ctx: &Ctx) {
    let vr = ctx.cfg.input_vr;
    let phases: [(&str, Prepare); 3] = [
        ("Instantiated", nothing),
        ("InitializationMode", to_init_mode),
        ("StepComplete", to_step_mode),
    ];
    for (phase, prepare) in phases {
        for value in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            ck.check(
                format!("fmi2SetReal(input, {value}) in {phase} → not fmi2OK, logged with the value reference"),
                || {
                    let mut s = ctx.slave()?;
                    prepare(&mut s)?;
                    s.log.take();
                    expect(s.set(vr, value), &[Status::Error, Status::Discard], "fmi2SetReal")?;
                    let log = s.log.take();
                    let hit = log.iter().find(|r| {
                        matches!(r.status, Some(Status::Discard | Status::Error | Status::Fatal))
                    });
                    match hit {
                        Some(r) if r.message.contains(&vr.to_string()) => Ok(()),
                        Some(r) => Err(format!(
                            "the message does not name value reference {vr}: {}",
                            r.message
                        )),
                        None => Err(format!("no message logged ({})", describe(&log))),
                    }
                },
            );
        }
    }
}

fn fmu_state_checks(ck: &mut Checker, ctx: &Ctx) {
    ck.check(
        "GetFMUstate → DoStep → SetFMUstate → DoStep is bit-identical",
        || {
            let mut s = ctx.stepping()?;
            s.trajectory(0, 3)?;
            let t_saved = s.t;
            let mut state: fmi2FMUstate = ptr::null_mut();
            expect_ok(s.get_state(&mut state), "fmi2GetFMUstate")?;
            if state.is_null() {
                return Err("fmi2GetFMUstate returned OK but no state".to_owned());
            }
            let first = s.trajectory(3, 4)?;
            expect_ok(s.set_state(state), "fmi2SetFMUstate")?;
            let (st, t_restored) = s.last_successful_time();
            expect_ok(st, "fmi2GetRealStatus(fmi2LastSuccessfulTime)")?;
            if t_restored.to_bits() != t_saved.to_bits() {
                return Err(format!(
                    "time after restore {t_restored}, saved at {t_saved}"
                ));
            }
            s.t = t_saved;
            let second = s.trajectory(3, 4)?;
            expect_ok(s.free_state(&mut state), "fmi2FreeFMUstate")?;
            if !state.is_null() {
                return Err("fmi2FreeFMUstate did not set the state to NULL".to_owned());
            }
            if first != second {
                return Err(format!("outputs differ: {first:?} vs {second:?}"));
            }
            Ok(())
        },
    );

    ck.check(
        "fmi2GetFMUstate into an existing state overwrites it",
        || {
            let mut s = ctx.stepping()?;
            s.trajectory(0, 2)?;
            let mut state: fmi2FMUstate = ptr::null_mut();
            expect_ok(s.get_state(&mut state), "fmi2GetFMUstate (new)")?;
            s.trajectory(2, 3)?;
            let t_second = s.t;
            expect_ok(s.get_state(&mut state), "fmi2GetFMUstate (overwrite)")?;
            let reference = s.trajectory(5, 3)?;
            expect_ok(s.set_state(state), "fmi2SetFMUstate")?;
            s.t = t_second;
            let again = s.trajectory(5, 3)?;
            expect_ok(s.free_state(&mut state), "fmi2FreeFMUstate")?;
            if reference != again {
                return Err(
                    "restoring the overwritten state did not reproduce the run from its time"
                        .to_owned(),
                );
            }
            Ok(())
        },
    );

    ck.check("fmi2FreeFMUstate ignores NULL", || {
        let s = ctx.stepping()?;
        let mut state: fmi2FMUstate = ptr::null_mut();
        expect_ok(s.free_state(&mut state), "fmi2FreeFMUstate(&NULL)")?;
        // SAFETY: a NULL pointer-to-state must be ignored as well.
        let st = unsafe { (s.lib.free_fmu_state)(s.c, ptr::null_mut()) };
        expect_ok(st, "fmi2FreeFMUstate(NULL)")
    });

    ck.check(
        "fmi2SetFMUstate recovers an instance from the Error state",
        || {
            let mut reference = ctx.stepping()?;
            reference.trajectory(0, 3)?;
            let expected = reference.trajectory(3, 3)?;

            let mut s = ctx.stepping()?;
            s.trajectory(0, 3)?;
            let t_saved = s.t;
            let mut state: fmi2FMUstate = ptr::null_mut();
            expect_ok(s.get_state(&mut state), "fmi2GetFMUstate")?;
            expect(
                s.do_step(s.t + 1.0, ctx.cfg.step_size),
                &[Status::Error],
                "fmi2DoStep at a wrong time",
            )?;
            expect(s.step(), &[Status::Error], "fmi2DoStep in the Error state")?;
            expect_ok(s.set_state(state), "fmi2SetFMUstate in the Error state")?;
            s.t = t_saved;
            let got = s.trajectory(3, 3)?;
            expect_ok(s.free_state(&mut state), "fmi2FreeFMUstate")?;
            if got != expected {
                return Err("the recovered run differs from an undisturbed run".to_owned());
            }
            Ok(())
        },
    );

    ck.check(
        "an FMU state taken in InitializationMode restores InitializationMode",
        || {
            let mut s = ctx.slave()?;
            to_init_mode(&mut s)?;
            let mut state: fmi2FMUstate = ptr::null_mut();
            expect_ok(s.get_state(&mut state), "fmi2GetFMUstate")?;
            expect_ok(s.exit(), "fmi2ExitInitializationMode")?;
            s.trajectory(0, 2)?;
            expect_ok(s.set_state(state), "fmi2SetFMUstate")?;
            expect_ok(s.free_state(&mut state), "fmi2FreeFMUstate")?;
            expect_ok(s.exit(), "fmi2ExitInitializationMode after restoring")
        },
    );
}

fn serialization_checks(ck: &mut Checker, ctx: &Ctx) {
    ck.check(
        "serialize → deserialize into a fresh instance continues bit-identically",
        || {
            let mut a = ctx.stepping()?;
            let bytes = a.serialized_state_after(4)?;
            let mut b = ctx.slave()?;
            let mut state: fmi2FMUstate = ptr::null_mut();
            expect_ok(b.deserialize(&bytes, &mut state), "fmi2DeSerializeFMUstate")?;
            expect_ok(b.set_state(state), "fmi2SetFMUstate (deserialized)")?;
            expect_ok(b.free_state(&mut state), "fmi2FreeFMUstate")?;
            let (st, tb) = b.last_successful_time();
            expect_ok(st, "fmi2GetRealStatus(fmi2LastSuccessfulTime)")?;
            if tb.to_bits() != a.t.to_bits() {
                return Err(format!(
                    "time {tb} after deserializing, {} in the source",
                    a.t
                ));
            }
            b.t = a.t;
            let ya = a.trajectory(4, 5)?;
            let yb = b.trajectory(4, 5)?;
            if ya != yb {
                return Err(format!("outputs differ: {ya:?} vs {yb:?}"));
            }
            Ok(())
        },
    );

    ck.check("serialization is deterministic", || {
        let mut a = ctx.stepping()?;
        let mut b = ctx.stepping()?;
        let x = a.serialized_state_after(3)?;
        let y = b.serialized_state_after(3)?;
        if x == y {
            Ok(())
        } else {
            Err("two identical runs serialize to different bytes".to_owned())
        }
    });

    let refuse = |ck: &mut Checker, name: &str, mangle: fn(Vec<c_char>) -> Vec<c_char>| {
        ck.check(
            format!("fmi2DeSerializeFMUstate refuses {name} with a logged message"),
            || {
                let mut a = ctx.stepping()?;
                let bytes = mangle(a.serialized_state_after(2)?);
                let b = ctx.slave()?;
                let mut state: fmi2FMUstate = ptr::null_mut();
                let status = b.deserialize(&bytes, &mut state);
                if !state.is_null() {
                    let _ = b.free_state(&mut state);
                }
                expect(status, &[Status::Error], "fmi2DeSerializeFMUstate")?;
                expect_logged_error(&b.log.take(), "fmi2DeSerializeFMUstate")
            },
        );
    };
    refuse(ck, "foreign bytes", |b| {
        (0..b.len())
            .map(|i| (i.wrapping_mul(2654435761) >> 7) as c_char)
            .collect()
    });
    refuse(ck, "truncated bytes", |mut b| {
        b.pop();
        b
    });
    refuse(ck, "bytes with one flipped bit", |mut b| {
        let mid = b.len() / 2;
        b[mid] ^= 0x10;
        b
    });
    refuse(ck, "zero bytes", |_| Vec::new());

    ck.check(
        "fmi2SerializeFMUstate refuses a buffer of the wrong size",
        || {
            let mut s = ctx.stepping()?;
            s.trajectory(0, 1)?;
            let mut state: fmi2FMUstate = ptr::null_mut();
            expect_ok(s.get_state(&mut state), "fmi2GetFMUstate")?;
            let mut size = 0usize;
            // SAFETY: valid instance, state and out pointer.
            expect_ok(
                unsafe { (s.lib.serialized_fmu_state_size)(s.c, state, &mut size) },
                "fmi2SerializedFMUstateSize",
            )?;
            let mut buf = vec![0 as c_char; size + 1];
            // SAFETY: the buffer holds size - 1 bytes at least.
            let st = unsafe { (s.lib.serialize_fmu_state)(s.c, state, buf.as_mut_ptr(), size - 1) };
            let _ = s.free_state(&mut state);
            expect(st, &[Status::Error], "fmi2SerializeFMUstate with size - 1")
        },
    );
}

fn life_cycle_checks(ck: &mut Checker, ctx: &Ctx) {
    ck.check("fmi2Reset reproduces a fresh run bit-identically", || {
        let mut s = ctx.stepping()?;
        let first = s.trajectory(0, 5)?;
        expect_ok(s.reset(), "fmi2Reset")?;
        s.init(None)?;
        let second = s.trajectory(0, 5)?;
        if first == second {
            Ok(())
        } else {
            Err(format!("{first:?} vs {second:?}"))
        }
    });

    ck.check("fmi2Reset after fmi2Terminate allows a new run", || {
        let mut s = ctx.slave()?;
        to_terminated(&mut s)?;
        expect_ok(s.reset(), "fmi2Reset")?;
        s.init(None)?;
        s.trajectory(0, 2).map(|_| ())
    });

    ck.check("two interleaved instances do not interfere", || {
        let mut lone = ctx.stepping()?;
        let expected = lone.trajectory(0, 6)?;
        drop(lone);
        let mut a = ctx.stepping()?;
        let mut b = ctx.stepping()?;
        let mut ya = Vec::new();
        for k in 0..6 {
            ya.extend(a.trajectory(k, 1)?);
            // b runs with different inputs in between.
            expect_ok(
                b.set(ctx.cfg.input_vr, -3.0 * ctx.cfg.input_value),
                "fmi2SetReal (b)",
            )?;
            expect_ok(b.step(), "fmi2DoStep (b)")?;
            expect_ok(b.get(ctx.cfg.output_vr).0, "fmi2GetReal (b)")?;
        }
        if ya != expected {
            return Err("instance a was influenced by instance b".to_owned());
        }
        Ok(())
    });

    ck.check("fmi2FreeInstance in each life-cycle state", || {
        let states: [(&str, Prepare); 4] = [
            ("Instantiated", nothing),
            ("InitializationMode", to_init_mode),
            ("StepComplete", to_step_mode),
            ("Terminated", to_terminated),
        ];
        for (name, prepare) in states {
            let mut s = ctx.slave()?;
            prepare(&mut s).map_err(|e| format!("{name}: {e}"))?;
            drop(s); // frees the instance
        }
        Ok(())
    });
}

fn status_and_logging_checks(ck: &mut Checker, ctx: &Ctx) {
    ck.check(
        "fmi2GetRealStatus(fmi2LastSuccessfulTime) is the end of the last step",
        || {
            let mut s = ctx.stepping()?;
            s.trajectory(0, 4)?;
            let (st, t) = s.last_successful_time();
            expect_ok(st, "fmi2GetRealStatus")?;
            if t.to_bits() == s.t.to_bits() {
                Ok(())
            } else {
                Err(format!("{t} vs {}", s.t))
            }
        },
    );

    ck.check(
        "fmi2GetBooleanStatus(fmi2Terminated) is false after successful steps",
        || {
            let mut s = ctx.stepping()?;
            s.trajectory(0, 2)?;
            let mut v = -1;
            // SAFETY: valid instance and out pointer.
            expect_ok(
                unsafe { (s.lib.get_boolean_status)(s.c, fmi2Terminated, &mut v) },
                "fmi2GetBooleanStatus",
            )?;
            if v == fmi2False {
                Ok(())
            } else {
                Err(format!("got {v}"))
            }
        },
    );

    ck.check(
        "fmi2GetStatus(fmi2DoStepStatus) of a synchronous FMU is not fmi2OK",
        || {
            let mut s = ctx.stepping()?;
            s.trajectory(0, 1)?;
            let mut v = -1;
            // SAFETY: valid instance and out pointer.
            let st = unsafe { (s.lib.get_status)(s.c, fmi2DoStepStatus, &mut v) };
            expect(
                st,
                &[Status::Discard, Status::Error],
                "fmi2GetStatus(fmi2DoStepStatus)",
            )
        },
    );

    ck.check(
        "errors are logged with debug logging off; events only with it on",
        || {
            let mut quiet_args = ctx.valid_args();
            quiet_args.logging_on = false;
            let mut quiet = ctx.slave_with(&quiet_args)?;
            quiet.init(None)?;
            quiet.trajectory(0, 1)?;
            let ok_messages = quiet
                .log
                .take()
                .into_iter()
                .filter(|r| r.status == Some(Status::Ok))
                .count();
            if ok_messages != 0 {
                return Err(format!(
                    "{ok_messages} fmi2OK messages with loggingOn = false"
                ));
            }
            expect(
                quiet.do_step(quiet.t + 1.0, 1.0),
                &[Status::Error],
                "fmi2DoStep at a wrong time",
            )?;
            expect_logged_error(&quiet.log.take(), "fmi2DoStep with loggingOn = false")?;

            let mut loud_args = ctx.valid_args();
            loud_args.logging_on = true;
            let loud = ctx.slave_with(&loud_args)?;
            if loud.log.take().iter().any(|r| r.status == Some(Status::Ok)) {
                Ok(())
            } else {
                Err("nothing was logged at instantiation with loggingOn = true".to_owned())
            }
        },
    );

    ck.check(
        "fmi2SetDebugLogging switches categories; NULL categories[] with n > 0 is an error",
        || {
            let s = ctx.slave()?;
            let all = [c"logAll".as_ptr()];
            // SAFETY: valid instance; arrays of the stated length.
            unsafe {
                expect_ok(
                    (s.lib.set_debug_logging)(s.c, fmi2True, 0, ptr::null()),
                    "SetDebugLogging(on, all)",
                )?;
                expect_ok(
                    (s.lib.set_debug_logging)(s.c, fmi2True, 1, all.as_ptr()),
                    "SetDebugLogging(on, logAll)",
                )?;
                expect_ok(
                    (s.lib.set_debug_logging)(s.c, fmi2False, 0, ptr::null()),
                    "SetDebugLogging(off)",
                )?;
                expect(
                    (s.lib.set_debug_logging)(s.c, fmi2True, 2, ptr::null()),
                    &[Status::Error],
                    "SetDebugLogging(on, 2, NULL)",
                )
            }
        },
    );
}
