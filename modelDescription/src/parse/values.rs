//! Pass 3 helpers: checked conversion of single attribute values (required attributes,
//! booleans, `xs:double`, integers, keywords) and the line prefix of conversion errors.

use crate::types::SourceLines;
use std::str::FromStr;

/// The result of a conversion step: the error is the message without the origin.
pub(super) type R<T> = Result<T, String>;

/// The message of a conversion error about the element at `line`.
pub(super) fn at(line: Option<usize>) -> impl Fn(String) -> String {
    move |m| format!("{}{m}", SourceLines::prefix(line))
}

pub(super) fn required(value: Option<String>, attribute: &str, element: &str) -> R<String> {
    value.ok_or_else(|| format!("{element}: the required attribute {attribute} is missing"))
}

pub(super) fn parse_bool(value: &str, attribute: &str, element: &str) -> R<bool> {
    match value.trim() {
        "true" | "1" => Ok(true),
        "false" | "0" => Ok(false),
        other => Err(format!(
            "{element}: {attribute}=\"{other}\" is not a boolean (true, false, 1 or 0)"
        )),
    }
}

pub(super) fn opt_bool(value: &Option<String>, attribute: &str, element: &str) -> R<Option<bool>> {
    value
        .as_deref()
        .map(|v| parse_bool(v, attribute, element))
        .transpose()
}

pub(super) fn flag(value: &Option<String>, attribute: &str, element: &str) -> R<bool> {
    Ok(opt_bool(value, attribute, element)?.unwrap_or(false))
}

/// `xs:double`, which also allows `INF`, `-INF` and `NaN`.
pub(super) fn parse_f64(value: &str, attribute: &str, element: &str) -> R<f64> {
    let v = value.trim();
    let parsed = match v {
        "INF" => Ok(f64::INFINITY),
        "-INF" => Ok(f64::NEG_INFINITY),
        "NaN" => Ok(f64::NAN),
        _ if v.eq_ignore_ascii_case("inf")
            || v.eq_ignore_ascii_case("-inf")
            || v.eq_ignore_ascii_case("nan")
            || v.eq_ignore_ascii_case("infinity")
            || v.eq_ignore_ascii_case("-infinity")
            || v.eq_ignore_ascii_case("+infinity")
            || v.eq_ignore_ascii_case("+inf") =>
        {
            Err(())
        }
        _ => v.parse::<f64>().map_err(|_| ()),
    };
    parsed.map_err(|()| format!("{element}: {attribute}=\"{value}\" is not a number"))
}

pub(super) fn opt_f64(value: &Option<String>, attribute: &str, element: &str) -> R<Option<f64>> {
    value
        .as_deref()
        .map(|v| parse_f64(v, attribute, element))
        .transpose()
}

pub(super) fn parse_int<T: FromStr>(
    value: &str,
    attribute: &str,
    element: &str,
    what: &str,
) -> R<T> {
    value
        .trim()
        .parse::<T>()
        .map_err(|_| format!("{element}: {attribute}=\"{value}\" is not {what}"))
}

pub(super) fn opt_i32(value: &Option<String>, attribute: &str, element: &str) -> R<Option<i32>> {
    value
        .as_deref()
        .map(|v| parse_int(v, attribute, element, "a 32-bit integer"))
        .transpose()
}

pub(super) fn opt_u32(value: &Option<String>, attribute: &str, element: &str) -> R<Option<u32>> {
    value
        .as_deref()
        .map(|v| parse_int(v, attribute, element, "an unsigned 32-bit integer"))
        .transpose()
}

pub(super) fn keyword<T: FromStr<Err = String>>(value: &str, element: &str) -> R<T> {
    value.parse::<T>().map_err(|e| format!("{element}: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn xs_double_special_values() {
        assert_eq!(parse_f64("INF", "a", "e"), Ok(f64::INFINITY));
        assert_eq!(parse_f64("-INF", "a", "e"), Ok(f64::NEG_INFINITY));
        assert!(parse_f64("NaN", "a", "e").unwrap().is_nan());
        assert_eq!(parse_f64(" 1e-3 ", "a", "e"), Ok(1e-3));
        assert!(parse_f64("inf", "a", "e").is_err());
        assert!(parse_f64("1,5", "a", "e").is_err());
    }
}
