//! The FMI 3.0 exports through their C ABI, called as a careless importer would: every
//! misuse gets `fmi3Error` (or NULL from `fmi3Instantiate…`) with a logged reason naming
//! the FMI 3.0 function, and the instance recovers by `fmi3Reset`.
//!
//! * a NULL instance passed to every kind of function;
//! * instantiation without a logger, with an empty name, a wrong instantiation token, no
//!   resource path or event mode asked for; the Model Exchange interface;
//! * illegal call sequences (a step before initialization, leaving an initialization never
//!   entered), arrays (`nValues` ≠ `nValueReferences`), functions of types and modes the
//!   FMU does not have, NULL output arguments of `fmi3DoStep`;
//! * FMU states: NULL, a serialization buffer of the wrong size, foreign bytes.
//!
//! And what a correct call gives: `fmi3GetVersion` is "3.0", the independent variable
//! `time` reads the instance's time, `fmi3DoStep` reports its last successful time.

mod common;

use fmi3::functions::*;
use fmi3::*;
use std::ffi::{c_char, CStr, CString};
use std::path::{Path, PathBuf};
use std::ptr::{null, null_mut};
use std::sync::Mutex;
use tbi_tests::fmu::export_as;

/// Messages logged by the FMU: (status, text).
static LOG: Mutex<Vec<(fmi3Status, String)>> = Mutex::new(Vec::new());

unsafe extern "C" fn logger(
    _env: fmi3InstanceEnvironment,
    status: fmi3Status,
    _category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the FMU passes a NUL-terminated message.
    let text = unsafe { CStr::from_ptr(message) }
        .to_string_lossy()
        .into_owned();
    LOG.lock().unwrap().push((status, text));
}

/// The last logged message.
fn last_message() -> String {
    LOG.lock()
        .unwrap()
        .last()
        .map(|m| m.1.clone())
        .unwrap_or_default()
}

/// The FMU's library, its resources folder (with the trailing separator) and token.
struct Fmu3 {
    lib: libloading::Library,
    resources: CString,
    token: CString,
}

impl Fmu3 {
    fn unpack(fmu: &Path, into: &Path) -> Fmu3 {
        let _ = std::fs::remove_dir_all(into);
        let file = std::fs::File::open(fmu).unwrap();
        zip::ZipArchive::new(file).unwrap().extract(into).unwrap();
        let md = std::fs::read_to_string(into.join("modelDescription.xml")).unwrap();
        let token = md
            .split("instantiationToken=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let id = md
            .split("modelIdentifier=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let so: PathBuf = into.join(format!("binaries/x86_64-linux/{id}.so"));
        // SAFETY: the FMU's own library, whose symbols have the fmi3 signatures.
        let lib = unsafe { libloading::Library::new(&so) }.unwrap();
        let resources = format!("{}/", into.join("resources").display());
        Fmu3 {
            lib,
            resources: CString::new(resources).unwrap(),
            token: CString::new(token).unwrap(),
        }
    }

    fn f<T: Copy>(&self, name: &str) -> T {
        // SAFETY: the caller names the symbol's fmi3 typedef.
        unsafe {
            *self
                .lib
                .get::<T>(name.as_bytes())
                .unwrap_or_else(|e| panic!("{name}: {e}"))
        }
    }

    /// `fmi3InstantiateCoSimulation` with these arguments (NULL for `None`).
    fn instantiate(
        &self,
        name: &str,
        token: Option<&CStr>,
        resources: Option<&CStr>,
        event_mode: bool,
        log: bool,
    ) -> fmi3Instance {
        let f: fmi3InstantiateCoSimulationTYPE = self.f("fmi3InstantiateCoSimulation");
        let name = CString::new(name).unwrap();
        let opt = |s: Option<&CStr>| s.map_or(null(), CStr::as_ptr);
        let logger: fmi3LogMessageCallback = if log { Some(logger) } else { None };
        // SAFETY: valid strings or NULL; the logger lives for the process.
        unsafe {
            f(
                name.as_ptr(),
                opt(token),
                opt(resources),
                0,
                0,
                u8::from(event_mode),
                0,
                null(),
                0,
                null_mut(),
                logger,
                None,
            )
        }
    }

    fn good(&self) -> fmi3Instance {
        let i = self.instantiate(
            "abi3",
            Some(&self.token),
            Some(&self.resources),
            false,
            true,
        );
        assert!(!i.is_null(), "{}", last_message());
        i
    }

    fn only(&self, name: &str, i: fmi3Instance) -> fmi3Status {
        let f: fmi3InstanceOnlyTYPE = self.f(name);
        // SAFETY: the instance or NULL.
        unsafe { f(i) }
    }

    fn enter_init(&self, i: fmi3Instance) -> fmi3Status {
        let f: fmi3EnterInitializationModeTYPE = self.f("fmi3EnterInitializationMode");
        // SAFETY: the instance or NULL.
        unsafe { f(i, 0, 0.0, 0.0, 0, 0.0) }
    }

    fn step(&self, i: fmi3Instance, t: f64, h: f64, last: &mut f64) -> fmi3Status {
        let f: fmi3DoStepTYPE = self.f("fmi3DoStep");
        let (mut a, mut b, mut c) = (9u8, 9u8, 9u8);
        // SAFETY: writable outputs.
        unsafe { f(i, t, h, 0, &mut a, &mut b, &mut c, last) }
    }

    fn get_f64(&self, i: fmi3Instance, vrs: &[u32], values: &mut [f64]) -> fmi3Status {
        let f: fmi3GetTYPE<f64> = self.f("fmi3GetFloat64");
        // SAFETY: arrays of the stated lengths.
        unsafe {
            f(
                i,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        }
    }
}

/// The coach scenario's FMI 3.0 bridge and train, unpacked.
fn fmus() -> Vec<Fmu3> {
    let e = export_as(
        "abi3",
        &common::scenarios::coach2(),
        &["--fmi-version", "3"],
    );
    [&e.bridge, &e.train]
        .iter()
        .map(|fmu| Fmu3::unpack(fmu, &fmu.with_extension("unpacked")))
        .collect()
}

#[test]
fn misuse_gets_fmi3_error_and_a_reason() {
    for fmu in fmus() {
        // a NULL instance
        for name in [
            "fmi3ExitInitializationMode",
            "fmi3Terminate",
            "fmi3Reset",
            "fmi3EnterEventMode",
            "fmi3EnterStepMode",
        ] {
            assert_eq!(fmu.only(name, null_mut()), fmi3Error, "{name}(NULL)");
        }
        assert_eq!(fmu.enter_init(null_mut()), fmi3Error);
        let mut last = 0.0;
        assert_eq!(fmu.step(null_mut(), 0.0, 0.01, &mut last), fmi3Error);
        assert_eq!(fmu.get_f64(null_mut(), &[0], &mut [0.0]), fmi3Error);
        let get_state: fmi3GetFMUStateTYPE = fmu.f("fmi3GetFMUState");
        let mut state: fmi3FMUState = null_mut();
        // SAFETY: a NULL instance and a writable state pointer.
        assert_eq!(unsafe { get_state(null_mut(), &mut state) }, fmi3Error);
        let free: fmi3FreeInstanceTYPE = fmu.f("fmi3FreeInstance");
        // SAFETY: NULL is ignored.
        unsafe { free(null_mut()) };

        // instantiation refused
        let (token, res) = (Some(fmu.token.as_c_str()), Some(fmu.resources.as_c_str()));
        assert!(
            fmu.instantiate("a", token, res, false, false).is_null(),
            "no logger"
        );
        let wrong = CString::new("not-the-token").unwrap();
        for (name, token, res, event, why) in [
            ("", token, res, false, "instanceName is NULL or empty"),
            ("a", Some(wrong.as_c_str()), res, false, "GUID mismatch"),
            ("a", None, res, false, "instantiationToken is NULL"),
            ("a", token, None, false, "resourcePath is NULL"),
            ("a", token, res, true, "has no event mode"),
        ] {
            assert!(
                fmu.instantiate(name, token, res, event, true).is_null(),
                "{why}"
            );
            let m = last_message();
            assert!(
                m.starts_with("fmi3InstantiateCoSimulation: ") && m.contains(why),
                "{m}"
            );
        }

        let i = fmu.good();
        let version: fmi3GetVersionTYPE = fmu.f("fmi3GetVersion");
        // SAFETY: a static string.
        assert_eq!(
            unsafe { CStr::from_ptr(version()) }.to_str().unwrap(),
            "3.0"
        );
        // illegal sequences, each followed by a reset
        let misuse = |what: &str, status: fmi3Status, needle: &str| {
            assert_eq!(status, fmi3Error, "{what}");
            let m = last_message();
            assert!(m.contains(needle), "{what}: {m}");
            assert_eq!(fmu.only("fmi3Reset", i), fmi3OK, "{what}: reset");
        };
        misuse(
            "step before initialization",
            fmu.step(i, 0.0, 0.01, &mut last),
            "fmi3DoStep: illegal call in state",
        );
        misuse(
            "exit without enter",
            fmu.only("fmi3ExitInitializationMode", i),
            "fmi3ExitInitializationMode: illegal call",
        );
        misuse(
            "event mode",
            fmu.only("fmi3EnterEventMode", i),
            "fmi3EnterEventMode: the FMU has no event mode",
        );
        let get32: fmi3GetTYPE<f32> = fmu.f("fmi3GetFloat32");
        let mut v32 = [0.0f32];
        // SAFETY: arrays of the stated lengths.
        misuse(
            "Float32",
            unsafe { get32(i, [0].as_ptr(), 1, v32.as_mut_ptr(), 1) },
            "no Float32 variables",
        );
        assert_eq!(fmu.enter_init(i), fmi3OK, "{}", last_message());
        misuse(
            "an array",
            fmu.get_f64(i, &[0], &mut [0.0, 0.0]),
            "no array variables",
        );
        assert_eq!(fmu.enter_init(i), fmi3OK);
        assert_eq!(fmu.only("fmi3ExitInitializationMode", i), fmi3OK);
        let f: fmi3DoStepTYPE = fmu.f("fmi3DoStep");
        let (mut a, mut b) = (0u8, 0u8);
        // SAFETY: one NULL output, refused before it is written.
        misuse(
            "NULL earlyReturn",
            unsafe { f(i, 0.0, 0.01, 0, &mut a, &mut b, null_mut(), &mut last) },
            "earlyReturn is NULL",
        );
        let set_state: fmi3SetFMUStateTYPE = fmu.f("fmi3SetFMUState");
        // SAFETY: a NULL state, refused.
        misuse(
            "NULL state",
            unsafe { set_state(i, null_mut()) },
            "fmi3SetFMUState",
        );
        // serialized states: wrong size, foreign bytes
        assert_eq!(fmu.enter_init(i), fmi3OK);
        // SAFETY: a writable state pointer.
        assert_eq!(unsafe { get_state(i, &mut state) }, fmi3OK);
        let size_of: fmi3SerializedFMUStateSizeTYPE = fmu.f("fmi3SerializedFMUStateSize");
        let mut size = 0usize;
        // SAFETY: a live state.
        assert_eq!(unsafe { size_of(i, state, &mut size) }, fmi3OK);
        let serialize: fmi3SerializeFMUStateTYPE = fmu.f("fmi3SerializeFMUState");
        let mut bytes = vec![0u8; size + 1];
        // SAFETY: a buffer of size + 1 bytes, refused for its size.
        misuse(
            "wrong size",
            unsafe { serialize(i, state, bytes.as_mut_ptr(), size + 1) },
            "differs from the serialized size",
        );
        let deserialize: fmi3DeserializeFMUStateTYPE = fmu.f("fmi3DeserializeFMUState");
        let mut other: fmi3FMUState = null_mut();
        // SAFETY: foreign bytes of the stated length.
        misuse(
            "foreign bytes",
            unsafe { deserialize(i, b"not a state".as_ptr(), 11, &mut other) },
            "fmi3DeserializeFMUState",
        );
        let free_state: fmi3FreeFMUStateTYPE = fmu.f("fmi3FreeFMUState");
        // SAFETY: the live state, freed once.
        assert_eq!(unsafe { free_state(i, &mut state) }, fmi3OK);
        assert!(state.is_null());

        // a correct run: time and the last successful time
        assert_eq!(fmu.enter_init(i), fmi3OK);
        assert_eq!(fmu.only("fmi3ExitInitializationMode", i), fmi3OK);
        for k in 0..3 {
            assert_eq!(
                fmu.step(i, k as f64 * 0.01, 0.01, &mut last),
                fmi3OK,
                "{}",
                last_message()
            );
        }
        assert!((last - 0.03).abs() < 1e-15, "{last}");
        let mut t = [0.0];
        assert_eq!(fmu.get_f64(i, &[TIME_VALUE_REFERENCE], &mut t), fmi3OK);
        assert_eq!(t[0], last);
        assert_eq!(fmu.only("fmi3Terminate", i), fmi3OK);
        // SAFETY: the live instance, freed once.
        unsafe { free(i) };

        // the other interfaces
        let me: unsafe extern "C" fn(
            fmi3String,
            fmi3String,
            fmi3String,
            fmi3Boolean,
            fmi3Boolean,
            fmi3InstanceEnvironment,
            fmi3LogMessageCallback,
        ) -> fmi3Instance = fmu.f("fmi3InstantiateModelExchange");
        let name: *const c_char = c"me".as_ptr();
        // SAFETY: valid strings.
        let got = unsafe {
            me(
                name,
                fmu.token.as_ptr(),
                fmu.resources.as_ptr(),
                0,
                0,
                null_mut(),
                Some(logger),
            )
        };
        assert!(got.is_null());
        assert!(
            last_message().contains("implements Co-Simulation only"),
            "{}",
            last_message()
        );
    }
}
