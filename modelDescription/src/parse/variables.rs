//! Pass 3 for `<ModelVariables>`: converting one `<ScalarVariable>`.

use super::raw::RawScalarVariable;
use super::type_element::{integer_attributes, real_attributes, single_type_element};
use super::values::{keyword, opt_bool, opt_f64, opt_i32, opt_u32, parse_int, required, R};
use crate::types::*;

pub(super) fn convert_variable(v: RawScalarVariable, index: usize) -> R<ScalarVariable> {
    let name = required(v.name, "name", &format!("<ScalarVariable> {index}"))?;
    let el = format!("<ScalarVariable> {index} \"{name}\"");
    let vr = required(v.value_reference, "valueReference", &el)?;
    let value_reference = parse_int(&vr, "valueReference", &el, "an unsigned 32-bit integer")?;
    let causality = match v.causality.as_deref() {
        None => Causality::Local,
        Some(c) => keyword(c, &el)?,
    };
    let variability = match v.variability.as_deref() {
        None => Variability::Continuous,
        Some(c) => keyword(c, &el)?,
    };
    let initial = v.initial.as_deref().map(|c| keyword(c, &el)).transpose()?;
    let can_handle_multiple_set_per_time_instant = opt_bool(
        &v.can_handle_multiple_set_per_time_instant,
        "canHandleMultipleSetPerTimeInstant",
        &el,
    )?;
    let (type_name, e) = single_type_element(
        [
            ("Real", v.real),
            ("Integer", v.integer),
            ("Boolean", v.boolean),
            ("String", v.string),
            ("Enumeration", v.enumeration),
        ],
        &el,
    )?;
    let tel = format!("{el}/{type_name}");
    let kind = match type_name {
        "Real" => VariableKind::Real(RealVariable {
            declared_type: e.declared_type.clone(),
            attributes: real_attributes(&e, &tel)?,
            start: opt_f64(&e.start, "start", &tel)?,
            derivative: opt_u32(&e.derivative, "derivative", &tel)?,
            reinit: opt_bool(&e.reinit, "reinit", &tel)?,
        }),
        "Integer" => VariableKind::Integer(IntegerVariable {
            declared_type: e.declared_type.clone(),
            attributes: integer_attributes(&e, &tel)?,
            start: opt_i32(&e.start, "start", &tel)?,
        }),
        "Boolean" => VariableKind::Boolean(BooleanVariable {
            declared_type: e.declared_type.clone(),
            start: opt_bool(&e.start, "start", &tel)?,
        }),
        "String" => VariableKind::String(StringVariable {
            declared_type: e.declared_type.clone(),
            start: e.start.clone(),
        }),
        _ => VariableKind::Enumeration(EnumerationVariable {
            declared_type: required(e.declared_type.clone(), "declaredType", &tel)?,
            attributes: integer_attributes(&e, &tel)?,
            start: opt_i32(&e.start, "start", &tel)?,
        }),
    };
    Ok(ScalarVariable {
        name,
        value_reference,
        description: v.description,
        causality,
        variability,
        initial,
        can_handle_multiple_set_per_time_instant,
        kind,
    })
}
