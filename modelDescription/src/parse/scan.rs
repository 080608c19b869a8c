//! Pass 1 of reading: the streaming well-formedness scan that checks the root element,
//! cuts out `<VendorAnnotations>` verbatim and records the line of every element that
//! messages name.

use crate::error::Error;
use crate::types::SourceLines;
use quick_xml::events::Event;
use quick_xml::Reader;

/// 1-based line and column of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = &text.as_bytes()[..offset];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |p| p + 1);
    let column = String::from_utf8_lossy(&before[line_start..])
        .chars()
        .count()
        + 1;
    (line, column)
}

/// Pass 1: well-formedness, root element, verbatim `<VendorAnnotations>`, element lines.
pub(super) fn scan(xml: &str, origin: &str) -> Result<(Option<String>, SourceLines), Error> {
    let mut reader = Reader::from_str(xml);
    reader.config_mut().check_end_names = true;
    let mut depth = 0usize;
    let mut root_seen = false;
    let mut vendor: Option<String> = None;
    let mut vendor_start: Option<usize> = None;
    let mut lines = SourceLines::default();
    // names of the open elements below the root, and the line count up to `counted`
    let mut open: Vec<String> = Vec::new();
    let (mut line, mut counted) = (1usize, 0usize);
    loop {
        let before = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| {
            let (line, column) = line_column(xml, reader.error_position() as usize);
            Error::new(
                origin,
                format!("malformed XML at line {line}, column {column}: {e}"),
            )
        })?;
        match event {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let name = e.name();
                let name: &str = name.as_ref();
                line += xml.as_bytes()[counted..before]
                    .iter()
                    .filter(|&&b| b == b'\n')
                    .count();
                counted = before;
                record_line(&mut lines, depth, &open, name, line);
                if depth == 0 {
                    if root_seen {
                        return Err(Error::new(origin, "more than one root element"));
                    }
                    root_seen = true;
                    if name != "fmiModelDescription" {
                        return Err(Error::new(
                            origin,
                            format!("the root element is <{name}>, expected <fmiModelDescription>"),
                        ));
                    }
                } else if depth == 1 && name == "VendorAnnotations" {
                    if vendor.is_some() || vendor_start.is_some() {
                        return Err(Error::new(
                            origin,
                            "more than one <VendorAnnotations> element",
                        ));
                    }
                    if matches!(event, Event::Empty(_)) {
                        let end = reader.buffer_position() as usize;
                        vendor = Some(xml[before..end].trim().to_owned());
                    } else {
                        vendor_start = Some(before);
                    }
                }
                if matches!(event, Event::Start(_)) {
                    if depth > 0 {
                        open.push(name.to_owned());
                    }
                    depth += 1;
                }
            }
            Event::End(ref e) => {
                depth = depth.saturating_sub(1);
                open.pop();
                let name = e.name();
                let name: &str = name.as_ref();
                if depth == 1 && name == "VendorAnnotations" {
                    if let Some(start) = vendor_start.take() {
                        let end = reader.buffer_position() as usize;
                        vendor = Some(xml[start..end].trim().to_owned());
                    }
                }
            }
            Event::Text(ref t) if depth == 0 && !AsRef::<str>::as_ref(t).trim().is_empty() => {
                return Err(Error::new(origin, "text outside the root element"));
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if !root_seen {
        return Err(Error::new(
            origin,
            "no <fmiModelDescription> element (empty document)",
        ));
    }
    if depth != 0 {
        return Err(Error::new(origin, "the document ends inside an element"));
    }
    Ok((vendor, lines))
}

/// Note the line of an element that messages name: `open` holds the names of the open
/// elements between the root and this one.
fn record_line(lines: &mut SourceLines, depth: usize, open: &[String], name: &str, line: usize) {
    let parents: Vec<&str> = open.iter().map(String::as_str).collect();
    match (depth, parents.as_slice(), name) {
        (0, [], _) => lines.root = Some(line),
        (1, [], "ModelExchange") => lines.model_exchange = Some(line),
        (1, [], "CoSimulation") => lines.co_simulation = Some(line),
        (1, [], "DefaultExperiment") => lines.default_experiment = Some(line),
        (1, [], "ModelStructure") => lines.model_structure = Some(line),
        (2, ["UnitDefinitions"], "Unit") => lines.units.push(line),
        (2, ["TypeDefinitions"], "SimpleType") => lines.types.push(line),
        (2, ["LogCategories"], "Category") => lines.categories.push(line),
        (2, ["ModelVariables"], "ScalarVariable") => lines.variables.push(line),
        (3, ["ModelStructure", "Outputs"], "Unknown") => lines.outputs.push(line),
        (3, ["ModelStructure", "Derivatives"], "Unknown") => lines.derivatives.push(line),
        (3, ["ModelStructure", "InitialUnknowns"], "Unknown") => lines.initial_unknowns.push(line),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_column_counts_from_one() {
        let text = "ab\ncd\nef";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 4), (2, 2));
        assert_eq!(line_column(text, 6), (3, 1));
    }
}
