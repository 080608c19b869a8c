//! Exported functions, platform and version strings, the library's name, and one
//! valid run.

use std::ffi::{c_char, CStr};

use super::slave::Ctx;
use super::Checker;

pub(super) fn platform_checks(ck: &mut Checker, ctx: &Ctx) {
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
