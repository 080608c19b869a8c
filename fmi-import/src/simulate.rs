//! The single-FMU runner behind `tbi simulate`: run one FMI 2.0 Co-Simulation FMU alone.
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
//! Deliberate differences from FMPy's command line: `--set` names a variable per option
//! (`--set k=2`) and an unknown or unsettable name is an error (FMPy ignores it); the
//! result file defaults to `<FMU file stem>_out.csv` in the working directory (the FMI
//! cross-check naming; `fmpy simulate` writes a file only with `--output-file`), `-`
//! writes to standard output; a NaN or infinite Real is an error naming the variable.

use crate::{FmiError, Fmu, Instance, InstantiateOptions, StepResult};
use model_description::{
    Causality, Initial, ModelDescription, ScalarVariable, Variability, VariableKind,
};
use std::io::{self, Write};
use std::path::Path;
use std::sync::Arc;

/// Failures of a single-FMU run.
#[derive(Debug, thiserror::Error)]
pub enum SimulateError {
    #[error(transparent)]
    Fmi(#[from] FmiError),
    /// Invalid arguments or inputs (the message names the option, file or variable).
    #[error("{0}")]
    Invalid(String),
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

/// Most communication steps of one run.
pub const MAX_STEPS: f64 = 1e7;

/// Settings of one run; `None` fields take the defaults described in the module docs.
#[derive(Debug, Clone, Default)]
pub struct SimulationOptions {
    pub start_time: Option<f64>,
    pub stop_time: Option<f64>,
    /// The communication step size (FMPy's output interval).
    pub step_size: Option<f64>,
    pub relative_tolerance: Option<f64>,
    /// `(variable name, value as text)`, applied in ModelVariables order.
    pub start_values: Vec<(String, String)>,
    pub input: Option<InputTable>,
    /// Print the FMU's log messages to standard error.
    pub echo_log: bool,
    /// Asked before every step; `true` ends the run (`RunEnd::Stopped`) with the rows so
    /// far (e.g. after SIGINT).
    pub stop_requested: Option<fn() -> bool>,
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

impl SimulationResult {
    /// Write the result as FMPy's `write_csv` does.
    pub fn write_csv(&self, out: &mut impl Write) -> io::Result<()> {
        write_header(out, &self.columns)?;
        for (time, values) in &self.rows {
            write_row(out, *time, values)?;
        }
        Ok(())
    }
}

fn write_header(out: &mut (impl Write + ?Sized), columns: &[String]) -> io::Result<()> {
    let header: Vec<String> = columns.iter().map(|c| format!("\"{c}\"")).collect();
    writeln!(out, "{}", header.join(","))
}

fn write_row(out: &mut (impl Write + ?Sized), time: f64, values: &[Value]) -> io::Result<()> {
    let mut line = python_float_repr(time);
    for v in values {
        line.push(',');
        match v {
            Value::Real(x) => line.push_str(&python_float_repr(*x)),
            Value::Integer(i) => line.push_str(&i.to_string()),
            Value::Boolean(b) => line.push_str(if *b { "True" } else { "False" }),
        }
    }
    writeln!(out, "{line}")
}

/// Python's `repr(float)` (which numpy's `str(float64)` matches): the shortest digits
/// that read back to the same value, positional for decimal exponents −4 ≤ e < 16 (always
/// with a fractional part), scientific otherwise with a signed exponent of at least two
/// digits (`1e-05`, `1.5e+16`), and `nan`, `inf`, `-inf`.
pub fn python_float_repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x == 0.0 {
        return if x.is_sign_negative() {
            "-0.0".into()
        } else {
            "0.0".into()
        };
    }
    // Rust's `{:e}` gives the shortest round-trip digits: "-1.2345e-5".
    let sci = format!("{x:e}");
    let (mantissa, exponent) = sci.split_once('e').expect("LowerExp has an exponent");
    let exponent: i32 = exponent.parse().expect("LowerExp exponent is an integer");
    let negative = mantissa.starts_with('-');
    let digits: String = mantissa.chars().filter(|c| c.is_ascii_digit()).collect();
    let mut out = String::new();
    if negative {
        out.push('-');
    }
    if !(-4..16).contains(&exponent) {
        out.push_str(&digits[..1]);
        if digits.len() > 1 {
            out.push('.');
            out.push_str(&digits[1..]);
        }
        out.push_str(&format!(
            "e{}{:02}",
            if exponent < 0 { '-' } else { '+' },
            exponent.abs()
        ));
    } else if exponent >= 0 {
        let int_len = exponent as usize + 1;
        if digits.len() <= int_len {
            out.push_str(&digits);
            out.push_str(&"0".repeat(int_len - digits.len()));
            out.push_str(".0");
        } else {
            out.push_str(&digits[..int_len]);
            out.push('.');
            out.push_str(&digits[int_len..]);
        }
    } else {
        out.push_str("0.");
        out.push_str(&"0".repeat((-exponent - 1) as usize));
        out.push_str(&digits);
    }
    out
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

/// Input signals read from a CSV file (FMPy's `read_csv` layout).
#[derive(Debug, Clone, PartialEq)]
pub struct InputTable {
    /// The file name, for messages.
    pub origin: String,
    /// Column names after the time column.
    pub names: Vec<String>,
    /// The time column (non-decreasing).
    pub time: Vec<f64>,
    /// `columns[j][i]`: value of `names[j]` at `time[i]`.
    pub columns: Vec<Vec<f64>>,
}

impl InputTable {
    pub fn from_path(path: &Path) -> Result<Self, SimulateError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|error| SimulateError::Io {
            path: origin.clone(),
            error,
        })?;
        Self::parse(&text, &origin)
    }

    /// Parse CSV text: a header of (optionally double-quoted) names, then rows of numbers.
    pub fn parse(text: &str, origin: &str) -> Result<Self, SimulateError> {
        let invalid = |m: String| SimulateError::Invalid(format!("{origin}: {m}"));
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let (_, header) = lines
            .next()
            .ok_or_else(|| invalid("the file is empty".into()))?;
        let header: Vec<String> = header
            .split(',')
            .map(|n| n.trim().trim_matches('"').to_owned())
            .collect();
        if header.len() < 2 {
            return Err(invalid(
                "expected a time column and at least one signal column".into(),
            ));
        }
        let mut time = Vec::new();
        let mut columns = vec![Vec::new(); header.len() - 1];
        for (number, line) in lines {
            let fields: Vec<&str> = line.split(',').collect();
            if fields.len() != header.len() {
                return Err(invalid(format!(
                    "line {}: {} fields, expected {}",
                    number + 1,
                    fields.len(),
                    header.len()
                )));
            }
            for (j, field) in fields.iter().enumerate() {
                let value: f64 = field.trim().parse().map_err(|_| {
                    invalid(format!(
                        "line {}, column \"{}\": \"{}\" is not a number",
                        number + 1,
                        header[j],
                        field.trim()
                    ))
                })?;
                if j == 0 {
                    if !value.is_finite() {
                        return Err(invalid(format!(
                            "line {}: time {value} is not finite",
                            number + 1
                        )));
                    }
                    if time.last().is_some_and(|&last| value < last) {
                        return Err(invalid(format!(
                            "line {}: time {value} is less than the time before it",
                            number + 1
                        )));
                    }
                    time.push(value);
                } else {
                    columns[j - 1].push(value);
                }
            }
        }
        if time.is_empty() {
            return Err(invalid("no data rows".into()));
        }
        Ok(Self {
            origin: origin.to_owned(),
            names: header[1..].to_vec(),
            time,
            columns,
        })
    }

    fn column(&self, name: &str) -> Option<&[f64]> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|j| self.columns[j].as_slice())
    }
}

/// First index `i` with `t[i] >= value` (numpy `searchsorted`, side "left").
fn search_sorted_left(t: &[f64], value: f64) -> usize {
    t.partition_point(|&x| x < value)
}

/// FMPy's `Input.interpolate` for one column.
fn interpolate(time: f64, t: &[f64], y: &[f64], discrete: bool, after_event: bool) -> f64 {
    let n = t.len();
    if n < 2 {
        return y[0];
    }
    let mut i0 = search_sorted_left(t, time);
    if i0 == 0 {
        return y[0];
    }
    if i0 == n {
        return y[n - 1];
    }
    if discrete {
        let mut i = i0 - 1;
        if after_event {
            while i + 1 < n && (t[i + 1] < time || isclose(time, t[i + 1])) {
                i += 1;
            }
        }
        return y[i];
    }
    if isclose(time, t[i0]) && i0 < n - 1 && isclose(t[i0], t[i0 + 1]) {
        if after_event {
            while i0 < n - 1 && isclose(t[i0], t[i0 + 1]) {
                i0 += 1;
            }
        }
        return y[i0];
    }
    let (i0, i1) = (i0 - 1, i0);
    let (t0, t1) = (t[i0], t[i1]);
    let w0 = (t1 - time) / (t1 - t0);
    let w1 = 1.0 - w0;
    w0 * y[i0] + w1 * y[i1]
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum InputKind {
    ContinuousReal,
    DiscreteReal,
    Integer,
    Boolean,
}

/// The inputs of one run, as FMPy's `Input` class applies them.
struct Inputs<'a> {
    table: Option<&'a InputTable>,
    /// (kind, value reference, column)
    signals: Vec<(InputKind, u32, &'a [f64])>,
    /// Sorted event times, always ending with +inf.
    events: Vec<f64>,
}

impl<'a> Inputs<'a> {
    fn new(md: &ModelDescription, table: Option<&'a InputTable>) -> Result<Self, SimulateError> {
        let mut signals = Vec::new();
        let mut events = vec![f64::INFINITY];
        let Some(table) = table else {
            return Ok(Self {
                table: None,
                signals,
                events,
            });
        };
        for v in &md.model_variables {
            if v.causality != Causality::Input && v.variability != Variability::Tunable {
                continue;
            }
            let Some(column) = table.column(&v.name) else {
                if v.causality == Causality::Input {
                    eprintln!(
                        "tbi: warning: {}: no column for the input \"{}\"",
                        table.origin, v.name
                    );
                }
                continue;
            };
            let kind = match &v.kind {
                VariableKind::Real(_)
                    if !matches!(v.variability, Variability::Discrete | Variability::Tunable) =>
                {
                    InputKind::ContinuousReal
                }
                VariableKind::Real(_) => InputKind::DiscreteReal,
                VariableKind::Integer(_) | VariableKind::Enumeration(_) => InputKind::Integer,
                VariableKind::Boolean(_) => InputKind::Boolean,
                VariableKind::String(_) => {
                    return Err(SimulateError::Invalid(format!(
                        "{}: column \"{}\": String variables cannot be read from a CSV input",
                        table.origin, v.name
                    )))
                }
            };
            signals.push((kind, v.value_reference, column));
        }
        // FMPy's Input.findEvents
        let t = &table.time;
        if t.len() >= 2 {
            for i in 0..t.len() - 1 {
                if t[i + 1] - t[i] == 0.0 {
                    events.push(t[i]);
                }
            }
            for v in &md.model_variables {
                if !matches!(v.variability, Variability::Discrete | Variability::Tunable) {
                    continue;
                }
                if let Some(y) = table.column(&v.name) {
                    for i in 0..y.len() - 1 {
                        if y[i + 1] - y[i] != 0.0 {
                            events.push(t[i + 1]);
                        }
                    }
                }
            }
        }
        events.sort_by(f64::total_cmp);
        events.dedup();
        Ok(Self {
            table: Some(table),
            signals,
            events,
        })
    }

    /// The first input event after `time` (+inf if none).
    fn next_event(&self, time: f64) -> f64 {
        if self.table.is_none() {
            return f64::INFINITY;
        }
        self.events
            .iter()
            .copied()
            .find(|&e| e > time && !isclose(e, time))
            .unwrap_or(f64::INFINITY)
    }

    /// Set the inputs at `time` (continuous Reals first, then discrete groups by type).
    fn apply(&self, instance: &mut Instance, time: f64, after_event: bool) -> Result<(), FmiError> {
        let Some(table) = self.table else {
            return Ok(());
        };
        let t = &table.time;
        let collect = |kind: InputKind| -> (Vec<u32>, Vec<f64>) {
            self.signals
                .iter()
                .filter(|(k, _, _)| *k == kind)
                .map(|(_, vr, y)| {
                    let discrete = kind != InputKind::ContinuousReal;
                    (*vr, interpolate(time, t, y, discrete, after_event))
                })
                .unzip()
        };
        let (vrs, values) = collect(InputKind::ContinuousReal);
        if !vrs.is_empty() {
            instance.set_real(&vrs, &values)?;
        }
        let (vrs, values) = collect(InputKind::DiscreteReal);
        if !vrs.is_empty() {
            instance.set_real(&vrs, &values)?;
        }
        let (vrs, values) = collect(InputKind::Integer);
        if !vrs.is_empty() {
            // numpy's float → int32 conversion truncates toward zero
            let ints: Vec<i32> = values.iter().map(|&v| v as i32).collect();
            instance.set_integer(&vrs, &ints)?;
        }
        let (vrs, values) = collect(InputKind::Boolean);
        if !vrs.is_empty() {
            let bools: Vec<bool> = values.iter().map(|&v| v as i32 != 0).collect();
            instance.set_boolean(&vrs, &bools)?;
        }
        Ok(())
    }
}

/// FMPy's `settable_in_instantiated`.
fn settable_in_instantiated(v: &ScalarVariable) -> bool {
    v.causality == Causality::Input
        || (v.variability != Variability::Constant
            && matches!(
                v.initial_or_default(),
                Some(Initial::Approx | Initial::Exact)
            ))
}

/// FMPy's `settable_in_initialization_mode`.
fn settable_in_initialization_mode(v: &ScalarVariable) -> bool {
    v.causality == Causality::Input
        || (v.causality != Causality::Parameter && v.variability == Variability::Tunable)
        || (v.variability != Variability::Constant
            && v.initial_or_default() == Some(Initial::Exact))
}

/// Set the start values whose variables pass `settable`; remove them from `pending`.
fn apply_start_values(
    instance: &mut Instance,
    md: &ModelDescription,
    pending: &mut Vec<(String, String)>,
    settable: fn(&ScalarVariable) -> bool,
) -> Result<(), SimulateError> {
    for v in &md.model_variables {
        let Some(position) = pending.iter().position(|(name, _)| *name == v.name) else {
            continue;
        };
        if !settable(v) {
            continue;
        }
        let (_, text) = pending.remove(position);
        let bad = |what: &str| {
            SimulateError::Invalid(format!("--set {}={text}: \"{text}\" is not {what}", v.name))
        };
        let vr = [v.value_reference];
        match &v.kind {
            VariableKind::Real(_) => {
                let x: f64 = text.parse().map_err(|_| bad("a number"))?;
                instance.set_real(&vr, &[x])?;
            }
            VariableKind::Integer(_) | VariableKind::Enumeration(_) => {
                let i: i32 = text.parse().map_err(|_| bad("a 32-bit integer"))?;
                instance.set_integer(&vr, &[i])?;
            }
            VariableKind::Boolean(_) => {
                let b = match text.to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(bad("true or false")),
                };
                instance.set_boolean(&vr, &[b])?;
            }
            VariableKind::String(_) => {
                instance.set_string(&vr, &[text.as_str()])?;
            }
        }
    }
    Ok(())
}

/// The variables FMPy records by default (`_get_output_variables`).
fn default_recorded(md: &ModelDescription) -> Vec<&ScalarVariable> {
    let outputs: Vec<&ScalarVariable> = md.outputs().collect();
    if !outputs.is_empty() {
        return outputs;
    }
    let states: Vec<&ScalarVariable> = md
        .model_structure
        .derivatives
        .iter()
        .filter_map(|u| md.variable_at_index(u.index))
        .filter_map(|der| match &der.kind {
            VariableKind::Real(r) => r.derivative.and_then(|s| md.variable_at_index(s)),
            _ => None,
        })
        .take(5)
        .collect();
    if !states.is_empty() {
        return states;
    }
    md.model_variables.iter().take(5).collect()
}

/// What is read at each sample: value references per type, in column order.
struct Recorder<'a> {
    columns: Vec<String>,
    reals: Vec<u32>,
    integers: Vec<u32>,
    booleans: Vec<u32>,
    rows: Vec<(f64, Vec<Value>)>,
    /// Where rows go as they are sampled (then none are kept).
    sink: Option<&'a mut dyn Write>,
}

impl<'a> Recorder<'a> {
    fn new(md: &ModelDescription, sink: Option<&'a mut dyn Write>) -> Self {
        let wanted: Vec<&str> = default_recorded(md)
            .iter()
            .map(|v| v.name.as_str())
            .collect();
        let mut groups: [Vec<(&str, u32)>; 3] = Default::default();
        for v in &md.model_variables {
            if v.name == "time" || !wanted.contains(&v.name.as_str()) {
                continue;
            }
            let group = match v.kind {
                VariableKind::Real(_) => 0,
                VariableKind::Integer(_) | VariableKind::Enumeration(_) => 1,
                VariableKind::Boolean(_) => 2,
                VariableKind::String(_) => continue,
            };
            groups[group].push((&v.name, v.value_reference));
        }
        let mut columns = vec!["time".to_owned()];
        for g in &groups {
            columns.extend(g.iter().map(|(n, _)| (*n).to_owned()));
        }
        let vrs = |g: &Vec<(&str, u32)>| g.iter().map(|(_, vr)| *vr).collect();
        Self {
            columns,
            reals: vrs(&groups[0]),
            integers: vrs(&groups[1]),
            booleans: vrs(&groups[2]),
            rows: Vec::new(),
            sink,
        }
    }

    fn sample(&mut self, instance: &mut Instance, time: f64) -> Result<(), FmiError> {
        let mut row = Vec::with_capacity(self.columns.len() - 1);
        if !self.reals.is_empty() {
            let mut values = vec![0.0; self.reals.len()];
            instance.get_real(&self.reals, &mut values)?;
            row.extend(values.into_iter().map(Value::Real));
        }
        if !self.integers.is_empty() {
            let mut values = vec![0; self.integers.len()];
            instance.get_integer(&self.integers, &mut values)?;
            row.extend(values.into_iter().map(Value::Integer));
        }
        if !self.booleans.is_empty() {
            let mut values = vec![false; self.booleans.len()];
            instance.get_boolean(&self.booleans, &mut values)?;
            row.extend(values.into_iter().map(Value::Boolean));
        }
        match self.sink.as_mut() {
            Some(out) => write_row(out, time, &row).map_err(|e| FmiError::Unsupported {
                fmu: String::new(),
                message: format!("cannot write the result row at t = {time}: {e}"),
            })?,
            None => self.rows.push((time, row)),
        }
        Ok(())
    }
}

/// Run `fmu` once as described in the module documentation, keeping the rows in memory.
pub fn simulate(
    fmu: &Arc<Fmu>,
    options: &SimulationOptions,
) -> Result<SimulationResult, SimulateError> {
    run(fmu, options, None)
}

/// Run `fmu` once, writing the CSV (header, then each row as it is sampled) to `out`, so
/// that an interrupted or failed run keeps what was computed. The result holds no rows.
pub fn simulate_into(
    fmu: &Arc<Fmu>,
    options: &SimulationOptions,
    out: &mut dyn Write,
) -> Result<SimulationResult, SimulateError> {
    run(fmu, options, Some(out))
}

fn run(
    fmu: &Arc<Fmu>,
    options: &SimulationOptions,
    out: Option<&mut dyn Write>,
) -> Result<SimulationResult, SimulateError> {
    let md = fmu.model_description();
    let cs = md
        .co_simulation
        .as_ref()
        .expect("Fmu::load accepts only Co-Simulation FMUs");
    let experiment = md.default_experiment.clone().unwrap_or_default();
    let invalid = |m: String| SimulateError::Invalid(format!("{}: {m}", fmu.name()));

    let start_time = options.start_time.or(experiment.start_time).unwrap_or(0.0);
    let stop_time = options
        .stop_time
        .or(experiment.stop_time)
        .unwrap_or(start_time + 1.0);
    if !start_time.is_finite() || !stop_time.is_finite() {
        return Err(invalid(format!(
            "start time {start_time} and stop time {stop_time} must be finite"
        )));
    }
    if stop_time <= start_time {
        return Err(invalid(format!(
            "the stop time {stop_time} is not after the start time {start_time}"
        )));
    }
    let tolerance = options.relative_tolerance.or(experiment.tolerance);
    let step = match (options.step_size, experiment.step_size) {
        (Some(h), _) => h,
        (None, Some(h)) => {
            let mut h = h;
            while h > 0.0 && (stop_time - start_time) / h > 1000.0 {
                h *= 2.0;
            }
            h
        }
        (None, None) => auto_interval(stop_time - start_time),
    };
    if !(step.is_finite() && step > 0.0) {
        return Err(invalid(format!(
            "the step size {step} must be a positive number"
        )));
    }
    let steps = (stop_time - start_time) / step;
    if steps > MAX_STEPS {
        return Err(invalid(format!(
            "the step size {step:e} s would take {steps:.3e} steps from {start_time} to {stop_time} s, more than the limit of {MAX_STEPS:e}"
        )));
    }
    let can_vary = cs.can_handle_variable_communication_step_size;

    let mut pending = options.start_values.clone();
    for (name, _) in &pending {
        if md.variable(name).is_none() {
            return Err(invalid(format!(
                "--set {name}: the FMU has no variable \"{name}\""
            )));
        }
    }
    let inputs = Inputs::new(md, options.input.as_ref())?;

    let mut instance = fmu.instantiate(&InstantiateOptions {
        echo_log: options.echo_log,
        ..InstantiateOptions::default()
    })?;

    let mut time = start_time;
    instance.setup_experiment(tolerance, time, Some(stop_time))?;
    apply_start_values(&mut instance, md, &mut pending, settable_in_instantiated)?;
    instance.enter_initialization_mode()?;
    apply_start_values(
        &mut instance,
        md,
        &mut pending,
        settable_in_initialization_mode,
    )?;
    if let Some((name, _)) = pending.first() {
        let v = md.variable(name).expect("checked above");
        return Err(invalid(format!(
            "--set {name}: the variable cannot be set before or during initialisation (causality=\"{}\", variability=\"{}\")",
            v.causality, v.variability
        )));
    }
    inputs.apply(&mut instance, time, false)?;
    instance.exit_initialization_mode()?;

    let mut recorder = Recorder::new(md, out);
    if let Some(sink) = recorder.sink.as_mut() {
        write_header(sink, &recorder.columns).map_err(|error| SimulateError::Io {
            path: "the result".into(),
            error,
        })?;
    }
    recorder.sample(&mut instance, time)?;

    let mut end = RunEnd::Completed;
    let mut n_steps: u64 = 0;
    loop {
        if time > stop_time || isclose(time, stop_time) {
            break;
        }
        if options.stop_requested.is_some_and(|stop| stop()) {
            end = RunEnd::Stopped { time };
            break;
        }
        let next_regular = start_time + (n_steps + 1) as f64 * step;
        let mut next = next_regular;
        let next_input_event = inputs.next_event(time);
        if can_vary && next > next_input_event && !isclose(next, next_input_event) {
            next = next_input_event;
        }
        if next > stop_time && !isclose(next, stop_time) {
            if can_vary {
                next = stop_time;
            } else {
                break;
            }
        }
        inputs.apply(&mut instance, time, true)?;
        match instance.do_step(time, next - time, true)? {
            StepResult::Ok | StepResult::Warning => time = next,
            StepResult::Discard => {
                if instance.terminated()? {
                    time = instance.last_successful_time()?;
                    recorder.sample(&mut instance, time)?;
                    end = RunEnd::Terminated { time };
                } else {
                    end = RunEnd::Discarded { time };
                }
                break;
            }
        }
        recorder.sample(&mut instance, time)?;
        if isclose(time, next_regular) {
            n_steps += 1;
        }
    }
    instance.terminate()?;
    Ok(SimulationResult {
        columns: recorder.columns,
        rows: recorder.rows,
        end,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn float_repr_matches_python() {
        // expected strings produced by Python's repr() / numpy's str()
        let cases: [(f64, &str); 22] = [
            (0.0, "0.0"),
            (-0.0, "-0.0"),
            (1.0, "1.0"),
            (0.1, "0.1"),
            (1e-5, "1e-05"),
            (0.0001, "0.0001"),
            (123456789012345.6, "123456789012345.6"),
            (1e15, "1000000000000000.0"),
            (1e16, "1e+16"),
            (1.5e16, "1.5e+16"),
            (-2.5e-7, "-2.5e-07"),
            (1e100, "1e+100"),
            (1.7976931348623157e308, "1.7976931348623157e+308"),
            (5e-324, "5e-324"),
            (0.30000000000000004, "0.30000000000000004"),
            (100.0, "100.0"),
            (2.0 / 3.0, "0.6666666666666666"),
            (1e22, "1e+22"),
            (12345.678, "12345.678"),
            (-1e-4, "-0.0001"),
            (f64::NAN, "nan"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, expected) in cases {
            assert_eq!(python_float_repr(x), expected, "{x:e}");
        }
    }

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

    #[test]
    fn interpolation_follows_fmpy() {
        let t = [0.0, 1.0, 1.0, 2.0];
        let y = [0.0, 1.0, 5.0, 7.0];
        // before, after the table
        assert_eq!(interpolate(-1.0, &t, &y, false, false), 0.0);
        assert_eq!(interpolate(3.0, &t, &y, false, false), 7.0);
        // linear inside
        assert_eq!(interpolate(0.25, &t, &y, false, false), 0.25);
        assert_eq!(interpolate(1.5, &t, &y, false, false), 6.0);
        // at a jump: left value before the event, right value after it
        assert_eq!(interpolate(1.0, &t, &y, false, false), 1.0);
        assert_eq!(interpolate(1.0, &t, &y, false, true), 5.0);
        // discrete: hold the last sample at or before the time
        assert_eq!(interpolate(1.5, &t, &y, true, true), 5.0);
        assert_eq!(interpolate(0.5, &t, &y, true, true), 0.0);
        assert_eq!(interpolate(1.0, &t, &y, true, false), 0.0);
        assert_eq!(interpolate(1.0, &t, &y, true, true), 5.0);
        // a single sample holds everywhere
        assert_eq!(interpolate(9.0, &[0.0], &[3.0], false, false), 3.0);
    }

    #[test]
    fn input_csv_parsing() {
        let table =
            InputTable::parse("\"time\",\"F\",\"on\"\n0,1.5,0\n1,2e0,1\n\n", "in.csv").unwrap();
        assert_eq!(table.names, ["F", "on"]);
        assert_eq!(table.time, [0.0, 1.0]);
        assert_eq!(table.columns, [vec![1.5, 2.0], vec![0.0, 1.0]]);
        let e = InputTable::parse("time,F\n0,1\n1,x\n", "in.csv")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "in.csv: line 3, column \"F\": \"x\" is not a number");
        let e = InputTable::parse("time,F\n1,1\n0,1\n", "in.csv")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "in.csv: line 3: time 0 is less than the time before it");
        let e = InputTable::parse("time,F\n0,1,2\n", "in.csv")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "in.csv: line 2: 3 fields, expected 2");
        assert!(InputTable::parse("time,F\n", "in.csv").is_err());
    }

    #[test]
    fn csv_layout() {
        let result = SimulationResult {
            columns: vec!["time".into(), "x".into(), "n".into(), "b".into()],
            rows: vec![
                (
                    0.0,
                    vec![Value::Real(1.0), Value::Integer(0), Value::Boolean(false)],
                ),
                (
                    0.01,
                    vec![
                        Value::Real(-2.5e-7),
                        Value::Integer(-3),
                        Value::Boolean(true),
                    ],
                ),
            ],
            end: RunEnd::Completed,
        };
        let mut out = Vec::new();
        result.write_csv(&mut out).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "\"time\",\"x\",\"n\",\"b\"\n0.0,1.0,0,False\n0.01,-2.5e-07,-3,True\n"
        );
    }
}
