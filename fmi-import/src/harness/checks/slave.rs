//! The context the checks share, one FMU instance driven like a master, and the
//! preparers that bring a fresh instance into a life-cycle state.

use std::ffi::CString;
use std::ptr;

use super::expect::{describe, expect_ok};
use super::Outcome;
use crate::harness::{HarnessConfig, Library, LogCapture};
use fmi2::types::*;

/// Everything the checks share.
pub(super) struct Ctx<'a> {
    pub(super) cfg: &'a HarnessConfig,
    pub(super) lib: &'a Library,
    pub(super) guid: CString,
    pub(super) uri: CString,
}

/// Arguments of one `fmi2Instantiate` call (valid unless changed).
pub(super) struct InstantiateArgs {
    pub(super) name: Option<CString>,
    pub(super) fmu_type: fmi2Type,
    pub(super) guid: Option<CString>,
    pub(super) uri: Option<CString>,
    pub(super) logger: bool,
    pub(super) functions: bool,
    pub(super) logging_on: bool,
}

impl Ctx<'_> {
    pub(super) fn valid_args(&self) -> InstantiateArgs {
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

    pub(super) fn instantiate_with(
        &self,
        args: &InstantiateArgs,
        log: &LogCapture,
    ) -> fmi2Component {
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
    pub(super) fn slave(&self) -> Result<Slave<'_>, String> {
        self.slave_with(&self.valid_args())
    }

    pub(super) fn slave_with(&self, args: &InstantiateArgs) -> Result<Slave<'_>, String> {
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
    pub(super) fn stepping(&self) -> Result<Slave<'_>, String> {
        let mut s = self.slave()?;
        s.init(None)?;
        Ok(s)
    }
}

/// One FMU instance driven like a master does; freed on drop (before its logger).
pub(super) struct Slave<'a> {
    pub(super) lib: &'a Library,
    pub(super) cfg: &'a HarnessConfig,
    pub(super) c: fmi2Component,
    /// The master's time.
    pub(super) t: f64,
    pub(super) log: LogCapture,
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
    pub(super) fn setup(&self, stop: Option<f64>) -> fmi2Status {
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

    pub(super) fn enter(&self) -> fmi2Status {
        unsafe { (self.lib.enter_initialization_mode)(self.c) }
    }

    pub(super) fn exit(&self) -> fmi2Status {
        unsafe { (self.lib.exit_initialization_mode)(self.c) }
    }

    pub(super) fn terminate(&self) -> fmi2Status {
        unsafe { (self.lib.terminate)(self.c) }
    }

    pub(super) fn reset(&mut self) -> fmi2Status {
        self.t = self.cfg.start_time;
        unsafe { (self.lib.reset)(self.c) }
    }

    /// SetupExperiment, Enter/ExitInitializationMode, all fmi2OK.
    pub(super) fn init(&mut self, stop: Option<f64>) -> Outcome {
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

    pub(super) fn set(&self, vr: u32, value: f64) -> fmi2Status {
        unsafe { (self.lib.set_real)(self.c, &vr, 1, &value) }
    }

    pub(super) fn get(&self, vr: u32) -> (fmi2Status, f64) {
        let mut v = f64::NAN;
        let s = unsafe { (self.lib.get_real)(self.c, &vr, 1, &mut v) };
        (s, v)
    }

    pub(super) fn do_step(&self, t: f64, h: f64) -> fmi2Status {
        unsafe { (self.lib.do_step)(self.c, t, h, fmi2False) }
    }

    /// One communication step from the master's time; advances it on fmi2OK.
    pub(super) fn step(&mut self) -> fmi2Status {
        let h = self.cfg.step_size;
        let s = self.do_step(self.t, h);
        if s == fmi2OK {
            self.t += h;
        }
        s
    }

    pub(super) fn last_successful_time(&self) -> (fmi2Status, f64) {
        let mut v = f64::NAN;
        let s = unsafe { (self.lib.get_real_status)(self.c, fmi2LastSuccessfulTime, &mut v) };
        (s, v)
    }

    /// `n` steps with the input `input_value·(1 + k/8)` for the `k`-th step; returns
    /// (time bits, output bits) after each step.
    pub(super) fn trajectory(
        &mut self,
        first_k: usize,
        n: usize,
    ) -> Result<Vec<(u64, u64)>, String> {
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
}

pub(super) fn to_init_mode(s: &mut Slave) -> Outcome {
    expect_ok(s.setup(None), "fmi2SetupExperiment")?;
    expect_ok(s.enter(), "fmi2EnterInitializationMode")
}

pub(super) fn to_step_mode(s: &mut Slave) -> Outcome {
    s.init(None)
}

pub(super) fn to_terminated(s: &mut Slave) -> Outcome {
    s.init(None)?;
    s.trajectory(0, 1)?;
    expect_ok(s.terminate(), "fmi2Terminate")
}

pub(super) fn nothing(_: &mut Slave) -> Outcome {
    Ok(())
}
