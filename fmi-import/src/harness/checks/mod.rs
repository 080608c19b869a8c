//! The checks run by [`super::run`], one module per group:
//!
//! * [`platform`]: all functions exported, `fmi2GetTypesPlatform`, `fmi2GetVersion`, the
//!   library's file stem, and one valid run;
//! * [`instantiate`]: `fmi2Instantiate` refuses invalid arguments and copies valid ones;
//! * [`null_component`]: every component-taking function called with NULL;
//! * [`illegal_state`]: calls in illegal life-cycle states, and recovery by `fmi2Reset`;
//! * [`arguments`]: bad arguments to `fmi2DoStep`, `fmi2GetReal`, `fmi2SetReal`, … and
//!   non-finite inputs in every phase;
//! * [`fmu_state`]: `fmi2GetFMUstate`/`fmi2SetFMUstate`/`fmi2FreeFMUstate` and
//!   serialization;
//! * [`life_cycle`]: `fmi2Reset`, interleaved instances, `fmi2FreeInstance` in every state;
//! * [`logging`]: the status functions and debug-logging control.
//!
//! [`expect`] compares return codes and log records with what a check wants; [`slave`]
//! holds the shared context, the instance wrapper and the life-cycle preparers.

mod arguments;
mod expect;
mod fmu_state;
mod illegal_state;
mod instantiate;
mod life_cycle;
mod logging;
mod null_component;
mod platform;
mod slave;

use std::ffi::CString;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::{Check, HarnessConfig, Library, Report};
use crate::library::LoadError;
use slave::{Ctx, Slave};

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

    platform::platform_checks(&mut ck, &ctx);
    instantiate::instantiate_checks(&mut ck, &ctx);
    null_component::null_component_checks(&mut ck, &ctx);
    illegal_state::illegal_state_checks(&mut ck, &ctx);
    arguments::argument_checks(&mut ck, &ctx);
    arguments::non_finite_input_checks(&mut ck, &ctx);
    fmu_state::fmu_state_checks(&mut ck, &ctx);
    fmu_state::serialization_checks(&mut ck, &ctx);
    life_cycle::life_cycle_checks(&mut ck, &ctx);
    logging::status_and_logging_checks(&mut ck, &ctx);

    Report { checks: ck.checks }
}
