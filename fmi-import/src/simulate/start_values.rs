//! The `--set` start values: which variables FMPy sets before and during initialization
//! mode, and setting them from their text.

use super::SimulateError;
use crate::FmiCalls;
use model_description::{
    Causality, Initial, ModelDescription, ScalarVariable, Variability, VariableKind,
};

/// FMPy's `settable_in_instantiated`.
pub(super) fn settable_in_instantiated(v: &ScalarVariable) -> bool {
    v.causality == Causality::Input
        || (v.variability != Variability::Constant
            && matches!(
                v.initial_or_default(),
                Some(Initial::Approx | Initial::Exact)
            ))
}

/// FMPy's `settable_in_initialization_mode`.
pub(super) fn settable_in_initialization_mode(v: &ScalarVariable) -> bool {
    v.causality == Causality::Input
        || (v.causality != Causality::Parameter && v.variability == Variability::Tunable)
        || (v.variability != Variability::Constant
            && v.initial_or_default() == Some(Initial::Exact))
}

/// Set the start values whose variables pass `settable`; remove them from `pending`.
pub(super) fn apply_start_values(
    instance: &mut dyn FmiCalls,
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
                let x: f64 = (text.parse().ok())
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| bad("a finite number"))?;
                instance.set_real(&vr, &[x]).map_err(SimulateError::Call)?;
            }
            VariableKind::Integer(_) | VariableKind::Enumeration(_) => {
                let i: i32 = text.parse().map_err(|_| bad("a 32-bit integer"))?;
                instance
                    .set_integer(&vr, &[i])
                    .map_err(SimulateError::Call)?;
            }
            VariableKind::Boolean(_) => {
                let b = match text.to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(bad("true or false")),
                };
                instance
                    .set_boolean(&vr, &[b])
                    .map_err(SimulateError::Call)?;
            }
            VariableKind::String(_) => {
                instance
                    .set_string(&vr, &[text.as_str()])
                    .map_err(SimulateError::Call)?;
            }
        }
    }
    Ok(())
}
