//! Input signals: the CSV table ([`InputTable`]) and how a run applies it before each
//! step (`Inputs`, FMPy's `Input` class: interpolation, discrete holds and event times).

use super::{isclose, SimulateError};
use crate::FmiCalls;
use model_description::{Causality, ModelDescription, Variability, VariableKind};
use std::path::Path;

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
pub(super) struct Inputs<'a> {
    table: Option<&'a InputTable>,
    /// (kind, value reference, column)
    signals: Vec<(InputKind, u32, &'a [f64])>,
    /// Sorted event times, always ending with +inf.
    events: Vec<f64>,
}

impl<'a> Inputs<'a> {
    pub(super) fn new(
        md: &ModelDescription,
        table: Option<&'a InputTable>,
    ) -> Result<Self, SimulateError> {
        let mut signals = Vec::new();
        let mut events = vec![f64::INFINITY];
        let Some(table) = table else {
            return Ok(Self {
                table: None,
                signals,
                events,
            });
        };
        // a column that names nothing the run can set is a mistake, not a signal to drop
        let settable = |v: &&model_description::ScalarVariable| {
            v.causality == Causality::Input || v.variability == Variability::Tunable
        };
        if let Some(name) = table.names.iter().find(|n| {
            !md.model_variables
                .iter()
                .filter(settable)
                .any(|v| &v.name == *n)
        }) {
            return Err(SimulateError::Invalid(format!(
                "{}: column \"{name}\" names no input or tunable parameter of the FMU{}",
                table.origin,
                crate::names::did_you_mean(
                    name,
                    md.model_variables
                        .iter()
                        .filter(settable)
                        .map(|v| v.name.as_str())
                )
            )));
        }
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
    pub(super) fn next_event(&self, time: f64) -> f64 {
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
    pub(super) fn apply(
        &self,
        instance: &mut dyn FmiCalls,
        time: f64,
        after_event: bool,
    ) -> Result<(), SimulateError> {
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
            instance
                .set_real(&vrs, &values)
                .map_err(SimulateError::Call)?;
        }
        let (vrs, values) = collect(InputKind::DiscreteReal);
        if !vrs.is_empty() {
            instance
                .set_real(&vrs, &values)
                .map_err(SimulateError::Call)?;
        }
        let (vrs, values) = collect(InputKind::Integer);
        if !vrs.is_empty() {
            // numpy's float → int32 conversion truncates toward zero
            let ints: Vec<i32> = values.iter().map(|&v| v as i32).collect();
            instance
                .set_integer(&vrs, &ints)
                .map_err(SimulateError::Call)?;
        }
        let (vrs, values) = collect(InputKind::Boolean);
        if !vrs.is_empty() {
            let bools: Vec<bool> = values.iter().map(|&v| v as i32 != 0).collect();
            instance
                .set_boolean(&vrs, &bools)
                .map_err(SimulateError::Call)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
