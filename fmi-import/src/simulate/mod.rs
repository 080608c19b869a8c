//! The single-FMU runner behind `tbi simulate`: run one FMI 2.0 or 3.0 Co-Simulation FMU alone.
//!
//! The run reproduces `fmpy simulate` (FMPy 0.3.x, `simulate_fmu` → `simulateCS`) step
//! for step, so that both give the same CSV for the same FMU:
//!
//! - **Times.** Start: `--start-time`, else DefaultExperiment `startTime`, else 0. Stop:
//!   `--stop-time`, else DefaultExperiment `stopTime`, else start + 1.
//! - **Communication step** (FMPy's *output interval*): `--step-size`, else
//!   DefaultExperiment `stepSize` doubled until the run has at most 1000 steps, else
//!   [`auto_interval`]`(stop − start)`: 10^(round(log10(span)) − 3), scaled by 5, 4, 2,
//!   1/2, 1/4 or 1/5 to give 500 to 1000 steps. Communication points are
//!   `start + n·step` (not accumulated sums). A last step that would overshoot the stop
//!   time is shortened to end on it if the FMU can handle variable step sizes, and
//!   skipped otherwise.
//! - **Initialisation.** `fmi2SetupExperiment(tolerance = DefaultExperiment tolerance,
//!   start, stop)`; `--set` values of variables settable in the *instantiated* state;
//!   `fmi2EnterInitializationMode`; the remaining `--set` values that are settable in
//!   *initialization mode*; inputs at the start time; `fmi2ExitInitializationMode`.
//! - **Inputs** (`--input CSV`): first column time (non-decreasing), then one column per
//!   variable, matched by name. Columns of inputs and of tunable variables are applied
//!   before each `fmi2DoStep` at the step's start time. Continuous Real inputs are
//!   interpolated linearly and held constant outside the table; a repeated time marks a
//!   jump, and the value after it applies from that time on. Discrete variables hold the
//!   last value at or before the time. If the FMU can handle variable step sizes, steps
//!   are shortened to end on jump times and on changes of discrete columns.
//! - **Recorded variables**: the outputs (all of them); if there are none, the first five
//!   continuous states (ModelStructure/Derivatives); if there are none, the first five
//!   variables. Columns are `time`, then Real, Integer (and Enumeration), then Boolean
//!   variables, each group in ModelVariables order. A row is recorded after
//!   initialisation and after every step.
//! - **CSV**: a header of quoted names (`"time","x"`), then rows of Python-formatted
//!   numbers (shortest round-trip repr: `0.1`, `1e-05`, `1.0`), integers, and
//!   `True`/`False`.
//! - **End.** When `fmi2DoStep` returns `fmi2Discard` and `fmi2GetBooleanStatus(
//!   fmi2Terminated)` is true, a last row is recorded at `fmi2LastSuccessfulTime` and the
//!   run ends normally (as FMPy does). A `fmi2Discard` without that request ends the run
//!   too (FMPy would retry the same step forever): the rows so far are written and the
//!   command fails, saying so.
//!
//! With [`simulate_isolated_into`] the FMU runs in a worker process
//! ([`crate::remote`]): its library is never loaded by the caller, and a crash, an `exit`
//! or a hang past the time limit ends the worker with a [`SimulateError::Call`] naming the
//! call and the time, after the rows computed before were written.
//!
//! Deliberate differences from FMPy's command line: `--set` names a variable per option
//! (`--set k=2`) and an unknown or unsettable name is an error (FMPy ignores it); the
//! result file defaults to `<FMU file stem>_out.csv` in the working directory (the FMI
//! cross-check naming; `fmpy simulate` writes a file only with `--output-file`), `-`
//! writes to standard output; a NaN or infinite Real is an error naming the variable.
//!
//! The module holds the types of a run and FMPy's number helpers; the run itself is in
//! its submodules: `run` (the options, [`simulate`], [`simulate_into`],
//! [`simulate_isolated_into`] and the stepping loop), `input` ([`InputTable`] and how inputs are applied), `start_values` (`--set`),
//! `record` (the recorded variables) and `csv` (the CSV layout, [`python_float_repr`]).

mod csv;
mod input;
mod record;
mod run;
mod start_values;

pub use csv::python_float_repr;
pub use input::InputTable;
pub use run::{simulate, simulate_into, simulate_isolated_into, SimulationOptions, MAX_STEPS};

use crate::FmiError;
use std::io;

/// Failures of a single-FMU run.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    #[error(transparent)]
    Fmi(#[from] FmiError),
    /// Invalid arguments or inputs (the message names the option, file or variable).
    #[error("{0}")]
    Invalid(String),
    /// An FMI call failed, in this process or in the FMU's worker (which may have crashed,
    /// exited, hung past the time limit or been ended by a signal); the message names the
    /// FMU, the call and, for a worker, the time.
    #[error("{0}")]
    Call(String),
    #[error("{path}: {error}")]
    Io { path: String, error: io::Error },
    /// The FMU discarded a step without asking to terminate; the rows up to `time` were
    /// written.
    #[error("{fmu}: fmi2DoStep returned fmi2Discard at t={time} without requesting termination; the simulation stopped there (results up to t={time} were written to {output})")]
    Discarded {
        fmu: String,
        time: f64,
        output: String,
    },
}

/// One recorded value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i32),
    Boolean(bool),
}

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RunEnd {
    /// The stop time was reached.
    Completed,
    /// The FMU discarded a step and requested termination at `time`.
    Terminated { time: f64 },
    /// The FMU discarded a step at `time` without requesting termination.
    Discarded { time: f64 },
    /// `stop_requested` said so at `time`.
    Stopped { time: f64 },
}

/// The recorded trajectories.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationResult {
    /// `time`, then the recorded variables.
    pub columns: Vec<String>,
    /// One row per sample: the time, then one value per recorded variable.
    pub rows: Vec<(f64, Vec<Value>)>,
    pub end: RunEnd,
}

/// Python's `math.isclose(a, b)` with its defaults (rel_tol = 1e-9, abs_tol = 0).
pub fn isclose(a: f64, b: f64) -> bool {
    if a == b {
        return true;
    }
    if a.is_infinite() || b.is_infinite() {
        return false;
    }
    let diff = (b - a).abs();
    diff <= (1e-9 * b).abs() || diff <= (1e-9 * a).abs()
}

/// FMPy's `auto_interval(t)`: a "nice" interval dividing `t` into 500 to 1000 steps.
pub fn auto_interval(t: f64) -> f64 {
    let mut h = 10f64.powf(t.log10().round_ties_even() - 3.0);
    let n = t / h;
    if n >= 2500.0 {
        h *= 5.0;
    } else if n >= 2000.0 {
        h *= 4.0;
    } else if n >= 1000.0 {
        h *= 2.0;
    } else if n <= 200.0 {
        h /= 5.0;
    } else if n <= 250.0 {
        h /= 4.0;
    } else if n <= 500.0 {
        h /= 2.0;
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_interval_matches_fmpy() {
        // values of fmpy.util.auto_interval
        assert_eq!(auto_interval(1.0), 0.002);
        assert_eq!(auto_interval(3.0), 0.005);
        assert_eq!(auto_interval(10.0), 0.02);
        assert_eq!(auto_interval(2.0), 0.004);
        assert_eq!(auto_interval(100.0), 0.2);
    }

    #[test]
    fn isclose_matches_python() {
        assert!(isclose(1.0, 1.0 + 1e-10));
        assert!(!isclose(1.0, 1.0 + 1e-8));
        assert!(!isclose(0.0, 1e-300));
        assert!(isclose(f64::INFINITY, f64::INFINITY));
        assert!(!isclose(f64::INFINITY, 1e308));
    }
}
