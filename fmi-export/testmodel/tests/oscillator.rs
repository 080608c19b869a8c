//! Direct checks of the test model through its C ABI: the numbers it computes and the
//! model-specific paths of the plumbing (discard, non-finite outputs, causality).

mod common;

use std::ffi::CString;
use std::ptr;

use fmi_export::types::*;
use fmi_import::harness::{Library, LogCapture, LogMessage};
use testmodel::vr;

/// One instance with captured logging.
struct Fmu {
    lib: Library,
    log: LogCapture,
    c: fmi2Component,
    t: f64,
}

impl Fmu {
    fn new() -> Fmu {
        Self::with_logging(false)
    }

    fn with_logging(logging_on: bool) -> Fmu {
        let lib = Library::load(&common::library()).expect("load");
        let log = LogCapture::new();
        let callbacks = log.callbacks();
        let guid = CString::new(common::guid()).unwrap();
        let uri = CString::new(fmi_export::uri::file_uri(&common::resources()).unwrap()).unwrap();
        let c = unsafe {
            (lib.instantiate)(
                c"osc".as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                uri.as_ptr(),
                &callbacks,
                fmi2False,
                fmi2Boolean::from(logging_on),
            )
        };
        assert!(!c.is_null(), "{:?}", log.take());
        Fmu {
            lib,
            log,
            c,
            t: 0.0,
        }
    }

    fn set(&self, r: u32, v: f64) -> fmi2Status {
        unsafe { (self.lib.set_real)(self.c, &r, 1, &v) }
    }

    fn get(&self, r: u32) -> (fmi2Status, f64) {
        let mut v = f64::NAN;
        let s = unsafe { (self.lib.get_real)(self.c, &r, 1, &mut v) };
        (s, v)
    }

    fn value(&self, r: u32) -> f64 {
        let (s, v) = self.get(r);
        assert_eq!(s, fmi2OK, "GetReal({r}): {:?}", self.log.records());
        v
    }

    fn enter(&self) {
        unsafe {
            assert_eq!(
                (self.lib.setup_experiment)(self.c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
                fmi2OK
            );
            assert_eq!((self.lib.enter_initialization_mode)(self.c), fmi2OK);
        }
    }

    fn exit(&self) -> fmi2Status {
        unsafe { (self.lib.exit_initialization_mode)(self.c) }
    }

    fn step(&mut self, h: f64) -> fmi2Status {
        let s = unsafe { (self.lib.do_step)(self.c, self.t, h, fmi2False) };
        if s == fmi2OK {
            self.t += h;
        }
        s
    }

    fn errors(&self) -> Vec<LogMessage> {
        self.log
            .take()
            .into_iter()
            .filter(|r| r.status != Some(Status::Ok))
            .collect()
    }
}

impl Drop for Fmu {
    fn drop(&mut self) {
        unsafe { (self.lib.free_instance)(self.c) }
    }
}

/// Closed-form solution of m x'' + c x' + k x = F (constant F, underdamped).
fn exact(m: f64, c: f64, k: f64, f: f64, x0: f64, v0: f64, t: f64) -> (f64, f64) {
    let w0 = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    assert!(zeta < 1.0);
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let sigma = zeta * w0;
    let xp = f / k;
    let a = x0 - xp;
    let b = (v0 + sigma * a) / wd;
    let e = (-sigma * t).exp();
    let (s, co) = (wd * t).sin_cos();
    let x = xp + e * (a * co + b * s);
    let v = e * ((-sigma * a + wd * b) * co + (-sigma * b - wd * a) * s);
    (x, v)
}

#[test]
fn do_step_matches_the_closed_form_solution() {
    let mut fmu = Fmu::new();
    fmu.enter();
    assert_eq!(fmu.set(vr::FORCE, 3.0), fmi2OK);
    assert_eq!(fmu.exit(), fmi2OK);
    // Config: m = 2, k = 50, c = 0.4, x0 = 0.1, v0 = 0. Variable step sizes.
    let steps = [0.01, 0.003, 0.0125, 0.02];
    let mut worst: f64 = 0.0;
    for i in 0..200 {
        let h = steps[i % steps.len()];
        assert_eq!(fmu.step(h), fmi2OK);
        let (x, v) = exact(2.0, 0.4, 50.0, 3.0, 0.1, 0.0, fmu.t);
        worst = worst
            .max((fmu.value(vr::X) - x).abs())
            .max((fmu.value(vr::V) - v).abs() / 5.0);
    }
    assert!(fmu.t > 2.0);
    assert!(worst < 1e-9, "max deviation from the closed form {worst:e}");
    // Energy output consistent with the state.
    let (x, v) = (fmu.value(vr::X), fmu.value(vr::V));
    let e = 0.5 * 2.0 * v * v + 0.5 * 50.0 * x * x;
    assert!((fmu.value(vr::ENERGY) - e).abs() <= 1e-15 * e.max(1.0));
}

#[test]
fn parameters_set_before_initialization_take_effect() {
    let mut fmu = Fmu::new();
    // In Instantiated.
    assert_eq!(fmu.set(vr::MASS, 0.5), fmi2OK);
    assert_eq!(fmu.set(vr::DAMPING, 0.0), fmi2OK);
    fmu.enter();
    // In InitializationMode; outputs already show the initial state.
    assert_eq!(fmu.set(vr::X0, -0.2), fmi2OK);
    assert_eq!(fmu.set(vr::V0, 1.0), fmi2OK);
    assert_eq!(fmu.value(vr::X), -0.2);
    assert_eq!(fmu.value(vr::MASS), 0.5);
    assert_eq!(fmu.exit(), fmi2OK);
    for _ in 0..100 {
        assert_eq!(fmu.step(0.01), fmi2OK);
    }
    let (x, v) = exact(0.5, 0.0, 50.0, 0.0, -0.2, 1.0, fmu.t);
    assert!((fmu.value(vr::X) - x).abs() < 1e-9);
    assert!((fmu.value(vr::V) - v).abs() < 1e-8);
}

#[test]
fn causality_is_enforced_by_the_model() {
    let fmu = Fmu::new();
    fmu.enter();
    assert_eq!(fmu.exit(), fmi2OK);
    assert_eq!(
        fmu.set(vr::FORCE, 1.0),
        fmi2OK,
        "inputs may be set in step mode"
    );
    assert_eq!(fmu.set(vr::MASS, 3.0), fmi2Error);
    let errors = fmu.errors();
    assert!(
        errors
            .iter()
            .any(|r| r.message.contains("fixed parameter") && r.message.contains("fmi2SetReal")),
        "{errors:?}"
    );

    let fmu = Fmu::new();
    assert_eq!(fmu.set(vr::X, 1.0), fmi2Error);
    assert!(fmu.errors()[0].message.contains("output"));

    let fmu = Fmu::new();
    fmu.enter();
    let mut i = 0;
    assert_eq!(
        unsafe { (fmu.lib.get_integer)(fmu.c, &0, 1, &mut i) },
        fmi2Error
    );
    assert!(fmu.errors()[0]
        .message
        .contains("unknown Integer value reference 0"));
}

#[test]
fn a_discarded_step_reports_terminated_and_keeps_the_last_good_time() {
    let mut fmu = Fmu::new();
    fmu.enter();
    assert_eq!(fmu.set(vr::X_MAX, 0.105), fmi2OK);
    assert_eq!(fmu.set(vr::FORCE, 10.0), fmi2OK); // equilibrium at 0.2 > x_max
    assert_eq!(fmu.exit(), fmi2OK);

    let mut saved: fmi2FMUstate = ptr::null_mut();
    let mut discarded = None;
    for i in 0..100 {
        unsafe { assert_eq!((fmu.lib.get_fmu_state)(fmu.c, &mut saved), fmi2OK) };
        let x_before = fmu.value(vr::X);
        let s = fmu.step(0.01);
        if s == fmi2Discard {
            discarded = Some((i, x_before));
            break;
        }
        assert_eq!(s, fmi2OK);
    }
    let (i, x_before) = discarded.expect("the amplitude limit must be hit");
    assert!(i > 0);
    let log = fmu.errors();
    assert!(
        log.iter()
            .any(|r| r.status == Some(Status::Discard) && r.message.contains("x_max")),
        "{log:?}"
    );

    let mut terminated = fmi2False;
    let mut last = f64::NAN;
    unsafe {
        assert_eq!(
            (fmu.lib.get_boolean_status)(fmu.c, fmi2Terminated, &mut terminated),
            fmi2OK
        );
        assert_eq!(
            (fmu.lib.get_real_status)(fmu.c, fmi2LastSuccessfulTime, &mut last),
            fmi2OK
        );
    }
    assert_eq!(terminated, fmi2True);
    assert_eq!(last, fmu.t, "time must not advance on a discarded step");
    assert_eq!(
        fmu.value(vr::X),
        x_before,
        "the state must not change either"
    );

    // StepFailed: no further DoStep, but the saved state restores step mode.
    unsafe {
        assert_eq!((fmu.lib.set_fmu_state)(fmu.c, saved), fmi2OK);
        (fmu.lib.get_boolean_status)(fmu.c, fmi2Terminated, &mut terminated);
    }
    assert_eq!(terminated, fmi2False);
    // Pull back hard enough that the next step stays within x_max.
    assert_eq!(fmu.set(vr::FORCE, -100.0), fmi2OK);
    assert_eq!(fmu.step(0.001), fmi2OK, "{:?}", fmu.errors());
    assert!(fmu.value(vr::X) < x_before + 1e-3);
    unsafe {
        assert_eq!((fmu.lib.free_fmu_state)(fmu.c, &mut saved), fmi2OK);
        assert_eq!((fmu.lib.terminate)(fmu.c), fmi2OK);
    }
}

#[test]
fn terminate_is_allowed_after_a_discard() {
    let mut fmu = Fmu::new();
    fmu.enter();
    assert_eq!(fmu.set(vr::X_MAX, 0.1), fmi2OK);
    assert_eq!(fmu.set(vr::FORCE, 100.0), fmi2OK);
    assert_eq!(fmu.exit(), fmi2OK);
    assert_eq!(fmu.step(0.1), fmi2Discard);
    let t = fmu.t;
    assert_eq!(
        unsafe { (fmu.lib.do_step)(fmu.c, t, 0.1, fmi2False) },
        fmi2Error
    );
    // The illegal DoStep moved the instance to Error; Reset recovers.
    assert_eq!(unsafe { (fmu.lib.terminate)(fmu.c) }, fmi2Error);
    assert_eq!(unsafe { (fmu.lib.reset)(fmu.c) }, fmi2OK);

    let mut fmu = Fmu::new();
    fmu.enter();
    assert_eq!(fmu.set(vr::X_MAX, 0.1), fmi2OK);
    assert_eq!(fmu.set(vr::FORCE, 100.0), fmi2OK);
    assert_eq!(fmu.exit(), fmi2OK);
    assert_eq!(fmu.step(0.1), fmi2Discard);
    assert_eq!(unsafe { (fmu.lib.terminate)(fmu.c) }, fmi2OK);
}

#[test]
fn a_non_finite_output_is_an_error_naming_the_value_reference() {
    let fmu = Fmu::new();
    fmu.enter();
    assert_eq!(fmu.set(vr::X_MAX, 1e300), fmi2OK);
    assert_eq!(fmu.set(vr::X0, 1e200), fmi2OK);
    assert_eq!(fmu.exit(), fmi2OK);
    assert_eq!(fmu.value(vr::X), 1e200);
    let (s, e) = fmu.get(vr::ENERGY);
    assert_eq!(s, fmi2Error);
    assert!(e.is_infinite());
    let errors = fmu.errors();
    assert!(
        errors
            .iter()
            .any(|r| r.message.contains("value reference 3") && r.message.contains("inf")),
        "{errors:?}"
    );
}

#[test]
fn instantiation_is_logged_only_with_debug_logging_and_model_categories_are_known() {
    let fmu = Fmu::with_logging(true);
    let records = fmu.log.take();
    assert!(
        records
            .iter()
            .any(|r| r.category == "logModel" && r.message.contains("mass: 2.0")),
        "{records:?}"
    );
    assert!(records
        .iter()
        .any(|r| r.category == "logEvents" && r.message.contains("instantiated testmodel")));

    let quiet = Fmu::new();
    assert!(quiet.log.take().is_empty());

    // Known categories (plumbing + model): OK; an unknown one: Warning, still usable.
    let cats = [c"logEvents".as_ptr(), c"logModel".as_ptr()];
    unsafe {
        assert_eq!(
            (quiet.lib.set_debug_logging)(quiet.c, fmi2True, 2, cats.as_ptr()),
            fmi2OK
        );
        let typo = [c"logEvnets".as_ptr()];
        assert_eq!(
            (quiet.lib.set_debug_logging)(quiet.c, fmi2True, 1, typo.as_ptr()),
            fmi2Warning
        );
    }
    let warn = quiet.log.take();
    assert!(warn
        .iter()
        .any(|r| r.status == Some(Status::Warning) && r.message.contains("logEvnets")));
    quiet.enter();
    assert!(quiet
        .log
        .take()
        .iter()
        .any(|r| r.message.contains("initialization mode")));
}

#[test]
fn resource_uri_spellings_are_accepted_and_guid_follows_the_resources() {
    let lib = Library::load(&common::library()).unwrap();
    let log = LogCapture::new();
    let callbacks = log.callbacks();
    let guid = CString::new(common::guid()).unwrap();
    let dir = common::resources();
    let plain = dir.to_str().unwrap().to_owned();
    for location in [
        format!("file://{plain}"),
        format!("file://{plain}/"),
        format!("file:{plain}"),
        format!("file://localhost{plain}"),
        plain.clone(),
    ] {
        let loc = CString::new(location.clone()).unwrap();
        let c = unsafe {
            (lib.instantiate)(
                c"u".as_ptr(),
                fmi2CoSimulation,
                guid.as_ptr(),
                loc.as_ptr(),
                &callbacks,
                0,
                0,
            )
        };
        assert!(!c.is_null(), "{location}: {:?}", log.take());
        unsafe { (lib.free_instance)(c) };
    }

    // A copy of the resources in a folder with a space (percent-encoded in the URI) and
    // an edited config: the GUID changes with the bytes of config.txt.
    let tmp = std::env::temp_dir().join(format!("fmi testmodel {}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let original = std::fs::read_to_string(dir.join("config.txt")).unwrap();
    let edited = original.replace("mass = 2.0", "mass = 4.0");
    assert_ne!(original, edited);
    std::fs::write(tmp.join("config.txt"), &edited).unwrap();
    let uri = CString::new(fmi_export::uri::file_uri(&tmp).unwrap()).unwrap();
    assert!(uri.to_str().unwrap().contains("%20"));
    let instantiate = |g: &CString| unsafe {
        (lib.instantiate)(
            c"u".as_ptr(),
            fmi2CoSimulation,
            g.as_ptr(),
            uri.as_ptr(),
            &callbacks,
            0,
            0,
        )
    };
    assert!(
        instantiate(&guid).is_null(),
        "old GUID must not match edited resources"
    );
    assert!(log
        .take()
        .iter()
        .any(|r| r.message.contains("GUID mismatch")));
    let new_guid = CString::new(testmodel::guid_for(edited.as_bytes())).unwrap();
    let c = instantiate(&new_guid);
    assert!(!c.is_null(), "{:?}", log.take());
    let m = {
        let mut v = 0.0;
        unsafe {
            (lib.enter_initialization_mode)(c);
            (lib.get_real)(c, &vr::MASS, 1, &mut v);
            (lib.free_instance)(c);
        }
        v
    };
    assert_eq!(m, 4.0);
    std::fs::remove_dir_all(&tmp).unwrap();
}

#[test]
fn serialized_state_of_another_build_is_refused() {
    // Same model identifier, different GUID (edited resources) → refused by the header.
    let mut a = Fmu::new();
    a.enter();
    assert_eq!(a.exit(), fmi2OK);
    assert_eq!(a.step(0.01), fmi2OK);
    let mut st: fmi2FMUstate = ptr::null_mut();
    let mut size = 0;
    unsafe {
        (a.lib.get_fmu_state)(a.c, &mut st);
        (a.lib.serialized_fmu_state_size)(a.c, st, &mut size);
    }
    let mut bytes = vec![0 as std::ffi::c_char; size];
    unsafe {
        assert_eq!(
            (a.lib.serialize_fmu_state)(a.c, st, bytes.as_mut_ptr(), size),
            fmi2OK
        );
        (a.lib.free_fmu_state)(a.c, &mut st);
    }

    let tmp = std::env::temp_dir().join(format!("fmi-testmodel-build-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    let edited = std::fs::read_to_string(common::resources().join("config.txt"))
        .unwrap()
        .replace("damping = 0.4", "damping = 0.5");
    std::fs::write(tmp.join("config.txt"), &edited).unwrap();
    let log = LogCapture::new();
    let callbacks = log.callbacks();
    let guid = CString::new(testmodel::guid_for(edited.as_bytes())).unwrap();
    let uri = CString::new(fmi_export::uri::file_uri(&tmp).unwrap()).unwrap();
    let c = unsafe {
        (a.lib.instantiate)(
            c"b".as_ptr(),
            fmi2CoSimulation,
            guid.as_ptr(),
            uri.as_ptr(),
            &callbacks,
            0,
            0,
        )
    };
    assert!(!c.is_null());
    let mut restored: fmi2FMUstate = ptr::null_mut();
    let s = unsafe { (a.lib.de_serialize_fmu_state)(c, bytes.as_ptr(), size, &mut restored) };
    unsafe { (a.lib.free_instance)(c) };
    std::fs::remove_dir_all(&tmp).unwrap();
    assert_eq!(s, fmi2Error);
    assert!(restored.is_null());
    assert!(log
        .take()
        .iter()
        .any(|r| r.message.contains("GUID differs")));
}
