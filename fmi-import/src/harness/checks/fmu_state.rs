//! FMU states: get, set and free, and serialization into bytes and back.

use std::ffi::c_char;
use std::ptr;

use super::expect::{expect, expect_logged_error, expect_ok};
use super::slave::{to_init_mode, Ctx, Slave};
use super::Checker;
use fmi2::types::*;

// SAFETY (all methods): `self.c` is a live instance; pointers passed are valid for the
// stated lengths.
impl Slave<'_> {
    fn get_state(&self, state: &mut fmi2FMUstate) -> fmi2Status {
        unsafe { (self.lib.get_fmu_state)(self.c, state) }
    }

    pub(super) fn set_state(&self, state: fmi2FMUstate) -> fmi2Status {
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

pub(super) fn fmu_state_checks(ck: &mut Checker, ctx: &Ctx) {
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

pub(super) fn serialization_checks(ck: &mut Checker, ctx: &Ctx) {
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
