//! Calls in states where they are not allowed, and recovery from the Error state.

use super::expect::{expect, expect_logged_error, expect_ok};
use super::slave::{nothing, to_init_mode, to_step_mode, to_terminated, Ctx, Slave};
use super::{Checker, Outcome};
use fmi2::types::*;

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

pub(super) fn illegal_state_checks(ck: &mut Checker, ctx: &Ctx) {
    life_cycle_calls(ck, ctx);
    co_simulation_calls(ck, ctx);
    recovery_check(ck, ctx);
}

/// Life-cycle, value and stepping calls in states where they are not allowed.
fn life_cycle_calls(ck: &mut Checker, ctx: &Ctx) {
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
}

/// Status queries before the first step, and the derivative functions: illegal in a state
/// or not provided by the FMU.
fn co_simulation_calls(ck: &mut Checker, ctx: &Ctx) {
    let out = ctx.cfg.output_vr;
    let inp = ctx.cfg.input_vr;
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
    let directional = move |s: &mut Slave| {
        let (vr, dv) = (out, 1.0);
        let mut r = 0.0;
        unsafe { (s.lib.get_directional_derivative)(s.c, &vr, 1, &inp, 1, &dv, &mut r) }
    };
    if ctx.cfg.provides_directional_derivative {
        illegal(
            ck,
            ctx,
            "fmi2GetDirectionalDerivative in Instantiated",
            nothing,
            directional,
        );
        ck.check(
            "fmi2GetDirectionalDerivative at a communication point → fmi2OK".to_owned(),
            || {
                let mut s = ctx.slave()?;
                to_step_mode(&mut s)?;
                expect_ok(directional(&mut s), "fmi2GetDirectionalDerivative")
            },
        );
    } else {
        illegal(
            ck,
            ctx,
            "fmi2GetDirectionalDerivative (not provided)",
            to_step_mode,
            directional,
        );
    }
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
}

/// After an error only recovery calls are accepted, and `fmi2Reset` recovers.
fn recovery_check(ck: &mut Checker, ctx: &Ctx) {
    let h = ctx.cfg.step_size;
    let inp = ctx.cfg.input_vr;
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
