//! Bad arguments: communication points, step sizes, the stop time, NULL arrays,
//! unknown value references, and non-finite inputs in every phase.

use std::ptr;

use super::expect::{describe, expect, expect_logged_error, expect_ok};
use super::slave::{nothing, to_init_mode, to_step_mode, Ctx, Slave};
use super::{Checker, Prepare};
use fmi2::types::*;

pub(super) fn argument_checks(ck: &mut Checker, ctx: &Ctx) {
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

pub(super) fn non_finite_input_checks(ck: &mut Checker, ctx: &Ctx) {
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
