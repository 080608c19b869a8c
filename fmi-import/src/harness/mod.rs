//! A C-ABI conformance and misuse harness for FMI 2.0 Co-Simulation shared objects.
//!
//! [`run`] loads an FMU binary with [`Library`], drives it through the C functions
//! exactly as an importer would, and returns a [`Report`] of named checks. It covers what
//! an exporter must get right (see `shared/reference/fmi2.md`) and the contract of this
//! crate:
//!
//! * all 34 functions exported; `fmi2GetTypesPlatform` = `"default"`,
//!   `fmi2GetVersion` = `"2.0"`; the file stem is the model identifier;
//! * `fmi2Instantiate` returns NULL, with a logged reason where a logger exists, for a
//!   wrong GUID, a wrong or unknown `fmuType`, a NULL logger or callback struct, a missing
//!   resources folder (the FMU is expected to need its resources) and NULL/empty
//!   arguments;
//! * every component-taking function returns `fmi2Error` for a NULL component;
//! * calls in illegal states (DoStep before initialization, GetReal in Instantiated,
//!   SetReal after Terminate, Terminate twice, …) return `fmi2Error` with a logged
//!   message, and the instance then accepts only recovery calls until `fmi2Reset`;
//! * bad arguments (wrong communication point, `h ≤ 0` or non-finite, passing the stop
//!   time, NULL arrays, unknown value references) return `fmi2Error`;
//! * NaN/±∞ inputs in every phase return `fmi2Error` or `fmi2Discard`, never `fmi2OK`,
//!   with a logged message naming the value reference;
//! * `GetFMUstate → DoStep → SetFMUstate → DoStep` and serialize → deserialize into a
//!   fresh instance continue bit-identically; foreign, damaged or wrongly sized bytes are
//!   refused; `fmi2Reset` reproduces a fresh run; two instances do not interfere;
//! * status functions and debug-logging control behave as documented in
//!   `fmi_export::logging`.
//!
//! The harness only needs one input and one output value reference: it sets the input to
//! finite values near [`HarnessConfig::input_value`] and compares outputs bit for bit.
//! A crash of the FMU (segmentation fault, abort) ends the calling process; everything
//! else ends up in the report.
//!
//! # Use from a model crate's tests
//!
//! ```ignore
//! use fmi_import::harness::{run, HarnessConfig};
//!
//! #[test]
//! fn bridge_fmu_passes_the_harness() {
//!     let config = HarnessConfig::new(
//!         path_to_libbridge_so(),          // e.g. next to the test executable
//!         "bridge",
//!         bridge::guid_from_resources(&resources_dir),
//!         resources_dir,
//!         bridge::vr::CONTACT_FORCE,       // an input value reference
//!         bridge::vr::RAIL_DISPLACEMENT,   // an output value reference
//!     );
//!     let report = run(&config);
//!     assert!(report.all_passed(), "{report}");
//! }
//! ```
//!
//! [`LogCapture`] and [`Library`] are re-exported so tests can make their own calls with
//! captured logging (for a model's specific behaviour).

mod checks;

use std::fmt;
use std::path::PathBuf;

pub use crate::library::Library;
pub use fmi2::logger::{LogCapture, LogMessage};

/// What the harness needs to know about the FMU under test.
#[derive(Debug, Clone)]
pub struct HarnessConfig {
    /// The shared object (`…/libbridge.so` from cargo or `binaries/linux64/bridge.so`).
    pub library: PathBuf,
    /// `modelIdentifier` (the library's file stem, without a `lib` prefix).
    pub model_identifier: String,
    /// The GUID the FMU accepts.
    pub guid: String,
    /// The FMU's `resources` folder (passed as a `file:///` URI).
    pub resources: PathBuf,
    /// A Real input that may be set in every phase (Instantiated, initialization, step).
    pub input_vr: u32,
    /// A Real output.
    pub output_vr: u32,
    /// A finite value that is valid for the input (default 1.0); the harness uses
    /// `input_value · (1 + k/8)` for step `k`.
    pub input_value: f64,
    /// Start time passed to `fmi2SetupExperiment` (default 0.0).
    pub start_time: f64,
    /// Communication step size (default 1e-3).
    pub step_size: f64,
    /// `loggingOn` for the instances (default false, so the check that every error is
    /// logged also proves that errors are delivered with debug logging off).
    pub logging_on: bool,
    /// The FMU's `providesDirectionalDerivative` (default false): when true,
    /// `fmi2GetDirectionalDerivative` of the output by the input must succeed at a
    /// communication point, else it must fail there.
    pub provides_directional_derivative: bool,
}

impl HarnessConfig {
    /// A configuration with the defaults documented on the fields.
    pub fn new(
        library: impl Into<PathBuf>,
        model_identifier: impl Into<String>,
        guid: impl Into<String>,
        resources: impl Into<PathBuf>,
        input_vr: u32,
        output_vr: u32,
    ) -> HarnessConfig {
        HarnessConfig {
            library: library.into(),
            model_identifier: model_identifier.into(),
            guid: guid.into(),
            resources: resources.into(),
            input_vr,
            output_vr,
            input_value: 1.0,
            start_time: 0.0,
            step_size: 1e-3,
            logging_on: false,
            provides_directional_derivative: false,
        }
    }
}

/// One check: its name, whether it passed, and what was observed when it did not.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Check {
    pub name: String,
    pub passed: bool,
    pub message: String,
}

/// The outcome of [`run`].
#[derive(Debug, Clone, Default)]
pub struct Report {
    pub checks: Vec<Check>,
}

impl Report {
    /// True when there is at least one check and every check passed.
    pub fn all_passed(&self) -> bool {
        !self.checks.is_empty() && self.checks.iter().all(|c| c.passed)
    }

    /// The failed checks.
    pub fn failures(&self) -> impl Iterator<Item = &Check> {
        self.checks.iter().filter(|c| !c.passed)
    }

    /// The check called `name`, if any.
    pub fn get(&self, name: &str) -> Option<&Check> {
        self.checks.iter().find(|c| c.name == name)
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for c in &self.checks {
            if c.passed {
                writeln!(f, "  ok    {}", c.name)?;
            } else {
                writeln!(f, "  FAIL  {}: {}", c.name, c.message)?;
            }
        }
        let failed = self.failures().count();
        write!(
            f,
            "FMI harness: {} of {} checks passed",
            self.checks.len() - failed,
            self.checks.len()
        )
    }
}

/// Run every check against the FMU described by `config`.
///
/// The report is never empty: when the library cannot be loaded it holds that failure.
pub fn run(config: &HarnessConfig) -> Report {
    checks::run(config)
}
