//! `fmi2Instantiate` refusing invalid arguments, and copying valid ones.

use std::ffi::CString;

use super::expect::{expect, expect_logged_error};
use super::slave::{Ctx, InstantiateArgs};
use super::{Checker, Outcome};
use crate::harness::LogCapture;
use fmi2::types::*;

pub(super) fn instantiate_checks(ck: &mut Checker, ctx: &Ctx) {
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
        "fmi2Instantiate refuses an empty GUID with a logged reason",
        || {
            let mut a = ctx.valid_args();
            a.guid = Some(c"".to_owned());
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
