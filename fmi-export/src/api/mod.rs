//! The FMI 2.0 functions as generic Rust functions over the model type.
//!
//! [`crate::export_fmi2!`] emits one `extern "C"` symbol per function that forwards to the
//! function of the same name here, so all checking exists once. Each function
//!
//! 1. runs inside `catch_unwind`, so no panic crosses the C boundary: a panic is logged
//!    (`logStatusError`) and reported as `fmi2Error`, the instance moves to `Error`;
//! 2. resolves the component pointer (NULL → `fmi2Error` without dereferencing; see the
//!    safety section);
//! 3. checks the call against the state table ([`crate::state`]): an illegal call is
//!    logged and answered with `fmi2Error`, the instance moves to `Error`;
//! 4. checks pointer/length arguments (a NULL array with `n > 0` → `fmi2Error`);
//! 5. runs the body in [`crate::instance::Instance`]; any `fmi2Error` is logged with the
//!    function name and moves the instance to `Error`.
//!
//! # Ownership of the component pointer
//!
//! `instantiate` boxes an [`Instance`] and returns the raw pointer; the importer owns it
//! until it passes it to `free_instance`, which drops the box. Every other function
//! borrows the instance mutably for the duration of the call (FMI 2.0 forbids calling
//! one instance from several threads at once). Different instances share nothing, so they
//! may be used from different threads.
//!
//! [`Instance`]: crate::instance::Instance
//!
//! # Safety
//!
//! The functions are `unsafe`: their pointer arguments are trusted as the standard
//! requires of the importer (arrays of the stated length, NUL-terminated strings, a
//! component returned by `instantiate` of the same FMU and not yet freed). NULL is always
//! detected. Beyond that, the first two words of a component or FMU-state object are a
//! magic number and a model-type tag, checked before the object is used; this catches a
//! pointer of another FMU, a state passed as a component or an object freed while its
//! memory is still mapped, but it cannot make an arbitrary pointer safe.
//!
//! # Where the functions are
//!
//! Every function is re-exported here, at the path [`crate::export_fmi2!`] names; they
//! are written in submodules by FMI function group: `instantiate` (platform, version,
//! `fmi2Instantiate`, `fmi2FreeInstance`), `lifecycle` (debug logging, experiment set-up,
//! initialization, terminate, reset), `values` (get and set of variables), `fmu_state`
//! (FMU states and their serialization) and `slave` (derivatives, stepping and status).
//! The frame they share (panic catching, pointer resolution, state and argument checks)
//! is in `frame`.

mod fmu_state;
#[doc(hidden)]
pub mod frame;
mod instantiate;
mod lifecycle;
mod slave;
mod values;

pub use fmu_state::{
    de_serialize_fmu_state, free_fmu_state, get_fmu_state, serialize_fmu_state,
    serialized_fmu_state_size, set_fmu_state,
};
pub(crate) use instantiate::build;
pub use instantiate::{free_instance, get_types_platform, get_version, instantiate};
pub use lifecycle::{
    enter_initialization_mode, exit_initialization_mode, reset, set_debug_logging,
    setup_experiment, terminate,
};
pub use slave::{
    cancel_step, do_step, get_boolean_status, get_directional_derivative, get_integer_status,
    get_real_output_derivatives, get_real_status, get_status, get_string_status,
    set_real_input_derivatives,
};
pub use values::{
    get_boolean, get_integer, get_real, get_string, set_boolean, set_integer, set_real, set_string,
};

/// The generic functions driven directly (no shared object) with a mock model; the
/// logger is the binding's C shim (a dev-dependency feature).
#[cfg(test)]
mod tests {
    use super::frame::instance;
    use super::*;
    use crate::model::{FmuModel, Log, Phase, StepOutcome};
    use crate::state::State;
    use crate::types::*;
    use fmi2::logger::LogCapture;
    use std::ffi::CString;
    use std::path::Path;
    use std::ptr;

    /// `y = u · t`; panics for `h > 1`, errors for `h > 0.5`.
    #[derive(Clone)]
    struct Mock {
        u: f64,
        t: f64,
    }

    impl FmuModel for Mock {
        fn instantiate(resources: &Path, _log: &dyn Log) -> Result<Self, crate::ModelError> {
            if resources.ends_with("broken") {
                panic!("cannot cope with {}", resources.display());
            }
            Ok(Mock { u: 0.0, t: 0.0 })
        }
        fn guid(&self) -> String {
            "mock-guid".to_owned()
        }
        fn exit_initialization(&mut self) -> Result<(), crate::ModelError> {
            Ok(())
        }
        fn set_real(
            &mut self,
            vr: u32,
            value: f64,
            _phase: Phase,
        ) -> Result<(), crate::ModelError> {
            match vr {
                0 => {
                    self.u = value;
                    Ok(())
                }
                _ => Err(crate::ModelError::UnknownVariable { kind: "Real", vr }),
            }
        }
        fn get_real(&mut self, vr: u32) -> Result<f64, crate::ModelError> {
            match vr {
                1 => Ok(self.u * self.t),
                _ => Err(crate::ModelError::UnknownVariable { kind: "Real", vr }),
            }
        }
        fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, crate::ModelError> {
            assert!(h <= 1.0, "step {h} too large for the mock");
            if h > 0.5 {
                return Err("h > 0.5".into());
            }
            self.t = t + h;
            Ok(StepOutcome::Ok)
        }
        fn reset(&mut self) -> Result<(), crate::ModelError> {
            *self = Mock { u: 0.0, t: 0.0 };
            Ok(())
        }
        fn serialize_state(&self) -> Vec<u8> {
            [self.u, self.t]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect()
        }
        fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), crate::ModelError> {
            let v: Vec<f64> = bytes
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect();
            (self.u, self.t) = (v[0], v[1]);
            Ok(())
        }
    }

    /// A second model type (for cross-FMU pointer checks).
    #[derive(Clone)]
    struct Other(Mock);

    impl FmuModel for Other {
        fn instantiate(resources: &Path, log: &dyn Log) -> Result<Self, crate::ModelError> {
            Mock::instantiate(resources, log).map(Other)
        }
        fn guid(&self) -> String {
            self.0.guid()
        }
        fn exit_initialization(&mut self) -> Result<(), crate::ModelError> {
            Ok(())
        }
        fn set_real(&mut self, vr: u32, value: f64, phase: Phase) -> Result<(), crate::ModelError> {
            self.0.set_real(vr, value, phase)
        }
        fn get_real(&mut self, vr: u32) -> Result<f64, crate::ModelError> {
            self.0.get_real(vr)
        }
        fn do_step(&mut self, t: f64, h: f64) -> Result<StepOutcome, crate::ModelError> {
            self.0.do_step(t, h)
        }
        fn reset(&mut self) -> Result<(), crate::ModelError> {
            self.0.reset()
        }
        fn serialize_state(&self) -> Vec<u8> {
            self.0.serialize_state()
        }
        fn deserialize_state(&mut self, bytes: &[u8]) -> Result<(), crate::ModelError> {
            self.0.deserialize_state(bytes)
        }
    }

    fn new<M: FmuModel>(log: &LogCapture, location: &str) -> fmi2Component {
        let callbacks = log.callbacks();
        let loc = CString::new(location).unwrap();
        unsafe {
            instantiate::<M>(
                "mock",
                c"m".as_ptr(),
                fmi2CoSimulation,
                c"mock-guid".as_ptr(),
                loc.as_ptr(),
                &callbacks,
                fmi2False,
                fmi2False,
            )
        }
    }

    fn stepping<M: FmuModel>(log: &LogCapture) -> fmi2Component {
        let c = new::<M>(log, "file:///tmp/resources");
        assert!(!c.is_null());
        unsafe {
            assert_eq!(enter_initialization_mode::<M>(c), fmi2OK);
            assert_eq!(exit_initialization_mode::<M>(c), fmi2OK);
        }
        c
    }

    fn state_of(c: fmi2Component) -> State {
        unsafe { instance::<Mock>(c) }.unwrap().state()
    }

    #[test]
    fn a_panicking_model_gives_fmi2error_and_the_error_state() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        let status = unsafe { do_step::<Mock>(c, 0.0, 2.0, fmi2False) };
        assert_eq!(status, fmi2Error);
        assert_eq!(state_of(c), State::Error);
        let records = log.take();
        assert!(records
            .iter()
            .any(|r| r.is_error() && r.message.contains("panic in the model: step 2 too large")));
        // Reset recovers the instance.
        unsafe {
            assert_eq!(reset::<Mock>(c), fmi2OK);
            assert_eq!(state_of(c), State::Instantiated);
            free_instance::<Mock>(c);
        }
    }

    #[test]
    fn an_empty_guid_is_refused_with_a_logged_reason() {
        let log = LogCapture::new();
        let callbacks = log.callbacks();
        let c = unsafe {
            instantiate::<Mock>(
                "mock",
                c"m".as_ptr(),
                fmi2CoSimulation,
                c"".as_ptr(),
                c"file:///tmp/resources".as_ptr(),
                &callbacks,
                fmi2False,
                fmi2False,
            )
        };
        assert!(c.is_null());
        assert!(log
            .take()
            .iter()
            .any(|r| r.is_error() && r.message.contains("fmuGUID is empty")));
    }

    #[test]
    fn a_panic_while_instantiating_gives_null_and_a_logged_reason() {
        let log = LogCapture::new();
        let c = new::<Mock>(&log, "file:///tmp/broken");
        assert!(c.is_null());
        assert!(log
            .take()
            .iter()
            .any(|r| r.is_error() && r.message.contains("panic while building the model")));
    }

    #[test]
    fn model_errors_and_illegal_calls_move_to_error() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        unsafe {
            assert_eq!(do_step::<Mock>(c, 0.0, 0.75, fmi2False), fmi2Error);
            assert_eq!(state_of(c), State::Error);
            let r = log.take();
            assert!(r.iter().any(|r| r.message == "fmi2DoStep: step from t = 0 by h = 0.75 failed: h > 0.5"), "{r:?}");
            // Time did not advance; in Error, GetReal still answers (debugging only).
            let mut y = f64::NAN;
            assert_eq!(get_real::<Mock>(c, &1, 1, &mut y), fmi2OK);
            assert_eq!(y, 0.0);
            assert_eq!(do_step::<Mock>(c, 0.0, 0.1, fmi2False), fmi2Error);
            assert!(log.take()[0]
                .message
                .contains("illegal call in state Error"));
            free_instance::<Mock>(c);
        }
    }

    #[test]
    fn time_tolerance_is_relative() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        unsafe {
            assert_eq!(do_step::<Mock>(c, 0.0, 0.5, fmi2False), fmi2OK);
            // 0.5 · (1 + 5e-13) is within 1e-12·max(1, 0.5) of 0.5.
            assert_eq!(
                do_step::<Mock>(c, 0.5 * (1.0 + 5e-13), 0.5, fmi2False),
                fmi2OK
            );
            let mut t = 0.0;
            assert_eq!(
                get_real_status::<Mock>(c, fmi2LastSuccessfulTime, &mut t),
                fmi2OK
            );
            assert_eq!(t, 0.5 * (1.0 + 5e-13) + 0.5);
            assert_eq!(do_step::<Mock>(c, t + 2e-12, 0.5, fmi2False), fmi2Error);
            free_instance::<Mock>(c);
        }
    }

    #[test]
    fn pointers_of_another_fmu_are_refused() {
        let log = LogCapture::new();
        let mock = stepping::<Mock>(&log);
        let other = stepping::<Other>(&log);
        unsafe {
            // A component of another model type is not dereferenced as this one.
            assert_eq!(do_step::<Mock>(other, 0.0, 0.1, fmi2False), fmi2Error);
            assert_eq!(do_step::<Other>(other, 0.0, 0.1, fmi2False), fmi2OK);
            // An FMU state of another model type is refused with a message.
            let mut s: fmi2FMUstate = ptr::null_mut();
            assert_eq!(get_fmu_state::<Other>(other, &mut s), fmi2OK);
            assert_eq!(set_fmu_state::<Mock>(mock, s), fmi2Error);
            assert!(log
                .take()
                .iter()
                .any(|r| r.message.contains("different FMU")));
            // A component passed as an FMU state is refused too.
            assert_eq!(set_fmu_state::<Other>(other, mock), fmi2Error);
            assert_eq!(free_fmu_state::<Other>(mock, &mut s), fmi2Error);
            let mut s2 = s;
            // `other` is in Error now (the refused SetFMUstate); freeing is still allowed.
            assert_eq!(free_fmu_state::<Other>(other, &mut s2), fmi2OK);
            assert!(s2.is_null());
            free_instance::<Mock>(mock);
            free_instance::<Other>(other);
        }
    }

    #[test]
    fn de_serialize_overwrites_an_existing_state() {
        let log = LogCapture::new();
        let c = stepping::<Mock>(&log);
        unsafe {
            assert_eq!(set_real::<Mock>(c, &0, 1, &2.0), fmi2OK);
            assert_eq!(do_step::<Mock>(c, 0.0, 0.25, fmi2False), fmi2OK);
            let mut s: fmi2FMUstate = ptr::null_mut();
            assert_eq!(get_fmu_state::<Mock>(c, &mut s), fmi2OK);
            let mut n = 0;
            assert_eq!(serialized_fmu_state_size::<Mock>(c, s, &mut n), fmi2OK);
            let mut bytes = vec![0 as fmi2Byte; n];
            assert_eq!(
                serialize_fmu_state::<Mock>(c, s, bytes.as_mut_ptr(), n),
                fmi2OK
            );
            assert_eq!(do_step::<Mock>(c, 0.25, 0.25, fmi2False), fmi2OK);
            let mut later: fmi2FMUstate = ptr::null_mut();
            assert_eq!(get_fmu_state::<Mock>(c, &mut later), fmi2OK);
            let kept = later;
            assert_eq!(
                de_serialize_fmu_state::<Mock>(c, bytes.as_ptr(), n, &mut later),
                fmi2OK
            );
            assert_eq!(later, kept, "overwritten in place");
            assert_eq!(set_fmu_state::<Mock>(c, later), fmi2OK);
            let mut y = 0.0;
            assert_eq!(get_real::<Mock>(c, &1, 1, &mut y), fmi2OK);
            assert_eq!(y, 2.0 * 0.25);
            free_fmu_state::<Mock>(c, &mut s);
            free_fmu_state::<Mock>(c, &mut later);
            free_instance::<Mock>(c);
        }
    }
}
