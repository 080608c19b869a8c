//! Reading `modelDescription.xml`.
//!
//! Reading happens in three passes over the text:
//!
//! 1. A streaming pass with the quick-xml reader checks that the text is well-formed XML
//!    whose root is `<fmiModelDescription>`, reports syntax errors with line and column,
//!    cuts out the `<VendorAnnotations>` element verbatim (it may hold any XML), and
//!    records the line of every element later messages name ([`SourceLines`]).
//! 2. serde (quick-xml's deserializer) maps the document onto private "raw" structs whose
//!    attributes are all optional strings. Elements and attributes the raw structs do not
//!    name (vendor extensions, `<Annotations>` inside variables, FMI 2.0.x additions) are
//!    skipped, so real-world descriptions never fail on them.
//! 3. A conversion turns the raw structs into [`ModelDescription`], checking every value
//!    (numbers, booleans, keywords, required attributes) and naming the element — for
//!    variables the variable's name and 1-based index — and its line in each error.
//!
//! Semantic rules (legal causality/variability combinations, ModelStructure
//! completeness, …) are not checked here but by [`ModelDescription::validate`], so that
//! tools can read and inspect descriptions that break them.

mod convert;
mod interface;
mod raw;
mod scan;
mod structure;
mod type_element;
mod values;
mod variables;

use crate::error::Error;
use crate::types::ModelDescription;
use convert::convert;
use raw::RawModelDescription;
use scan::scan;
use std::path::Path;
use std::str::FromStr;

impl FromStr for ModelDescription {
    type Err = Error;

    /// Parse a description from XML text (errors name the origin `modelDescription.xml`;
    /// use [`ModelDescription::parse`] to give a better name).
    fn from_str(xml: &str) -> Result<Self, Error> {
        Self::parse(xml, "modelDescription.xml")
    }
}

impl ModelDescription {
    /// Read and parse the file at `path`; errors name the path.
    pub fn from_path(path: impl AsRef<Path>) -> Result<Self, Error> {
        let path = path.as_ref();
        let origin = path.display().to_string();
        let bytes = std::fs::read(path)
            .map_err(|e| Error::new(&origin, format!("cannot read the file: {e}")))?;
        let text = std::str::from_utf8(&bytes).map_err(|e| {
            Error::new(
                &origin,
                format!(
                    "the file is not UTF-8 text (invalid byte at offset {})",
                    e.valid_up_to()
                ),
            )
        })?;
        Self::parse(text, &origin)
    }

    /// Parse XML text; `origin` (a file name or other description of where the text came
    /// from) is named in every error.
    pub fn parse(xml: &str, origin: &str) -> Result<Self, Error> {
        let xml = xml.strip_prefix('\u{feff}').unwrap_or(xml);
        if is_fmi3(xml) {
            return crate::fmi3_read::parse_fmi3(xml, origin);
        }
        let (vendor_annotations, lines) = scan(xml, origin)?;
        let raw: RawModelDescription = quick_xml::de::from_str(xml)
            .map_err(|e| Error::new(origin, format!("unexpected document structure: {e}")))?;
        let mut md = convert(raw, &lines).map_err(|m| Error::new(origin, m))?;
        md.vendor_annotations = vendor_annotations;
        md.source_lines = lines;
        Ok(md)
    }
}

/// Whether the root element says `fmiVersion="3…"` (read by [`crate::fmi3_read`]).
fn is_fmi3(xml: &str) -> bool {
    let Some(start) = xml.find("<fmiModelDescription") else {
        return false;
    };
    let tag = &xml[start..];
    let tag = &tag[..tag.find('>').unwrap_or(tag.len())];
    tag.split("fmiVersion")
        .nth(1)
        .map(|rest| rest.trim_start().trim_start_matches('=').trim_start())
        .is_some_and(|v| v.starts_with("\"3") || v.starts_with("'3"))
}
