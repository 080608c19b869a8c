//! Pass 3 helpers shared by `<SimpleType>` and `<ScalarVariable>`: picking the one type
//! element and converting its Real and Integer attributes.

use super::raw::RawTypeElement;
use super::values::{opt_bool, opt_f64, opt_i32, R};
use crate::types::{IntegerAttributes, RealAttributes};

pub(super) fn real_attributes(e: &RawTypeElement, el: &str) -> R<RealAttributes> {
    Ok(RealAttributes {
        quantity: e.quantity.clone(),
        unit: e.unit.clone(),
        display_unit: e.display_unit.clone(),
        relative_quantity: opt_bool(&e.relative_quantity, "relativeQuantity", el)?,
        min: opt_f64(&e.min, "min", el)?,
        max: opt_f64(&e.max, "max", el)?,
        nominal: opt_f64(&e.nominal, "nominal", el)?,
        unbounded: opt_bool(&e.unbounded, "unbounded", el)?,
    })
}

pub(super) fn integer_attributes(e: &RawTypeElement, el: &str) -> R<IntegerAttributes> {
    Ok(IntegerAttributes {
        quantity: e.quantity.clone(),
        min: opt_i32(&e.min, "min", el)?,
        max: opt_i32(&e.max, "max", el)?,
    })
}

/// The one type element of a `<SimpleType>` or `<ScalarVariable>`.
pub(super) fn single_type_element(
    elements: [(&'static str, Option<RawTypeElement>); 5],
    el: &str,
) -> R<(&'static str, RawTypeElement)> {
    let mut found: Vec<(&'static str, RawTypeElement)> = elements
        .into_iter()
        .filter_map(|(name, e)| e.map(|e| (name, e)))
        .collect();
    match found.len() {
        1 => Ok(found.remove(0)),
        0 => Err(format!(
            "{el}: has no type element (one of <Real>, <Integer>, <Boolean>, <String>, <Enumeration>)"
        )),
        _ => Err(format!(
            "{el}: has more than one type element ({})",
            found
                .iter()
                .map(|(n, _)| format!("<{n}>"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}
