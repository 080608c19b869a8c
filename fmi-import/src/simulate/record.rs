//! The recorded variables (FMPy's defaults) and the [`Recorder`] that samples them after
//! initialisation and after every step.

use super::csv::write_row;
use super::{SimulateError, Value};
use crate::FmiCalls;
use model_description::{ModelDescription, ScalarVariable, VariableKind};
use std::io::Write;

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
pub(super) struct Recorder<'a> {
    pub(super) columns: Vec<String>,
    reals: Vec<u32>,
    integers: Vec<u32>,
    booleans: Vec<u32>,
    pub(super) rows: Vec<(f64, Vec<Value>)>,
    /// Where rows go as they are sampled (then none are kept).
    pub(super) sink: Option<&'a mut dyn Write>,
}

impl<'a> Recorder<'a> {
    pub(super) fn new(md: &ModelDescription, sink: Option<&'a mut dyn Write>) -> Self {
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

    pub(super) fn sample(
        &mut self,
        instance: &mut dyn FmiCalls,
        time: f64,
    ) -> Result<(), SimulateError> {
        let mut row = Vec::with_capacity(self.columns.len() - 1);
        if !self.reals.is_empty() {
            let mut values = vec![0.0; self.reals.len()];
            instance
                .get_real(&self.reals, &mut values)
                .map_err(SimulateError::Call)?;
            row.extend(values.into_iter().map(Value::Real));
        }
        if !self.integers.is_empty() {
            let mut values = vec![0; self.integers.len()];
            instance
                .get_integer(&self.integers, &mut values)
                .map_err(SimulateError::Call)?;
            row.extend(values.into_iter().map(Value::Integer));
        }
        if !self.booleans.is_empty() {
            let mut values = vec![false; self.booleans.len()];
            instance
                .get_boolean(&self.booleans, &mut values)
                .map_err(SimulateError::Call)?;
            row.extend(values.into_iter().map(Value::Boolean));
        }
        match self.sink.as_mut() {
            Some(out) => write_row(out, time, &row).map_err(|e| {
                SimulateError::Invalid(format!("cannot write the result row at t = {time}: {e}"))
            })?,
            None => self.rows.push((time, row)),
        }
        Ok(())
    }
}
