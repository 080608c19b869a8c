//! The status functions and debug-logging control.

use std::ptr;

use super::expect::{expect, expect_logged_error, expect_ok};
use super::slave::Ctx;
use super::Checker;
use fmi2::types::*;

pub(super) fn status_and_logging_checks(ck: &mut Checker, ctx: &Ctx) {
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
