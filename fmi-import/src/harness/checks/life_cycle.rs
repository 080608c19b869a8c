//! `fmi2Reset`, independent instances, and `fmi2FreeInstance` in every state.

use super::expect::expect_ok;
use super::slave::{nothing, to_init_mode, to_step_mode, to_terminated, Ctx};
use super::{Checker, Prepare};

pub(super) fn life_cycle_checks(ck: &mut Checker, ctx: &Ctx) {
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
