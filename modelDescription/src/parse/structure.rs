//! Pass 3 for `<ModelStructure>`: converting the `<Unknown>` lists.

use super::raw::{RawModelStructure, RawUnknown, RawUnknowns};
use super::values::{at, keyword, parse_int, required, R};
use crate::types::*;

/// `<ModelStructure>`: its three `<Unknown>` lists.
pub(super) fn convert_model_structure(
    raw_structure: RawModelStructure,
    lines: &SourceLines,
) -> R<ModelStructure> {
    Ok(ModelStructure {
        outputs: convert_unknowns(raw_structure.outputs, "Outputs", &lines.outputs)?,
        derivatives: convert_unknowns(
            raw_structure.derivatives,
            "Derivatives",
            &lines.derivatives,
        )?,
        initial_unknowns: convert_unknowns(
            raw_structure.initial_unknowns,
            "InitialUnknowns",
            &lines.initial_unknowns,
        )?,
    })
}

fn parse_index_list(value: &str, attribute: &str, el: &str) -> R<Vec<u32>> {
    value
        .split_ascii_whitespace()
        .map(|t| parse_int(t, attribute, el, "a list of unsigned integers"))
        .collect()
}

fn convert_unknowns(raw: Option<RawUnknowns>, list: &str, lines: &[usize]) -> R<Vec<Unknown>> {
    raw.map(|u| u.unknowns)
        .unwrap_or_default()
        .into_iter()
        .enumerate()
        .map(|(i, u)| {
            let el = format!("<ModelStructure>/<{list}>/<Unknown> {}", i + 1);
            convert_unknown(u, &el).map_err(at(lines.get(i).copied()))
        })
        .collect()
}

fn convert_unknown(u: RawUnknown, el: &str) -> R<Unknown> {
    let index = required(u.index, "index", el)?;
    let index = parse_int(&index, "index", el, "an unsigned integer")?;
    let dependencies = u
        .dependencies
        .as_deref()
        .map(|d| parse_index_list(d, "dependencies", el))
        .transpose()?;
    let dependencies_kind = u
        .dependencies_kind
        .as_deref()
        .map(|d| {
            d.split_ascii_whitespace()
                .map(|k| keyword::<DependencyKind>(k, el))
                .collect::<R<Vec<_>>>()
        })
        .transpose()?;
    Ok(Unknown {
        index,
        dependencies,
        dependencies_kind,
    })
}
