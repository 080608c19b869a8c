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

use crate::error::Error;
use crate::types::*;
use quick_xml::events::Event;
use quick_xml::Reader;
use serde::Deserialize;
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
        let (vendor_annotations, lines) = scan(xml, origin)?;
        let raw: RawModelDescription = quick_xml::de::from_str(xml)
            .map_err(|e| Error::new(origin, format!("unexpected document structure: {e}")))?;
        let mut md = convert(raw, &lines).map_err(|m| Error::new(origin, m))?;
        md.vendor_annotations = vendor_annotations;
        md.source_lines = lines;
        Ok(md)
    }
}

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
fn scan(xml: &str, origin: &str) -> Result<(Option<String>, SourceLines), Error> {
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

/// The message of a conversion error about the element at `line`.
fn at(line: Option<usize>) -> impl Fn(String) -> String {
    move |m| format!("{}{m}", SourceLines::prefix(line))
}

// ---------------------------------------------------------------------------------------
// Pass 2: raw serde structs. Every attribute is an optional string so that pass 3 can
// give precise messages; unknown attributes and elements are ignored by serde.

#[derive(Deserialize)]
struct RawModelDescription {
    #[serde(rename = "@fmiVersion")]
    fmi_version: Option<String>,
    #[serde(rename = "@modelName")]
    model_name: Option<String>,
    #[serde(rename = "@guid")]
    guid: Option<String>,
    #[serde(rename = "@description")]
    description: Option<String>,
    #[serde(rename = "@author")]
    author: Option<String>,
    #[serde(rename = "@version")]
    version: Option<String>,
    #[serde(rename = "@copyright")]
    copyright: Option<String>,
    #[serde(rename = "@license")]
    license: Option<String>,
    #[serde(rename = "@generationTool")]
    generation_tool: Option<String>,
    #[serde(rename = "@generationDateAndTime")]
    generation_date_and_time: Option<String>,
    #[serde(rename = "@variableNamingConvention")]
    variable_naming_convention: Option<String>,
    #[serde(rename = "@numberOfEventIndicators")]
    number_of_event_indicators: Option<String>,
    #[serde(rename = "ModelExchange")]
    model_exchange: Option<RawInterface>,
    #[serde(rename = "CoSimulation")]
    co_simulation: Option<RawInterface>,
    #[serde(rename = "UnitDefinitions")]
    unit_definitions: Option<RawUnitDefinitions>,
    #[serde(rename = "TypeDefinitions")]
    type_definitions: Option<RawTypeDefinitions>,
    #[serde(rename = "LogCategories")]
    log_categories: Option<RawLogCategories>,
    #[serde(rename = "DefaultExperiment")]
    default_experiment: Option<RawDefaultExperiment>,
    #[serde(rename = "ModelVariables")]
    model_variables: Option<RawModelVariables>,
    #[serde(rename = "ModelStructure")]
    model_structure: Option<RawModelStructure>,
}

/// `<ModelExchange>` and `<CoSimulation>` share one raw shape.
#[derive(Deserialize)]
struct RawInterface {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: Option<String>,
    #[serde(rename = "@needsExecutionTool")]
    needs_execution_tool: Option<String>,
    #[serde(rename = "@completedIntegratorStepNotNeeded")]
    completed_integrator_step_not_needed: Option<String>,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    can_handle_variable_communication_step_size: Option<String>,
    #[serde(rename = "@canInterpolateInputs")]
    can_interpolate_inputs: Option<String>,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    max_output_derivative_order: Option<String>,
    #[serde(rename = "@canRunAsynchronuously")]
    can_run_asynchronuously: Option<String>,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    can_be_instantiated_only_once_per_process: Option<String>,
    #[serde(rename = "@canNotUseMemoryManagementFunctions")]
    can_not_use_memory_management_functions: Option<String>,
    #[serde(rename = "@canGetAndSetFMUstate")]
    can_get_and_set_fmu_state: Option<String>,
    #[serde(rename = "@canSerializeFMUstate")]
    can_serialize_fmu_state: Option<String>,
    #[serde(rename = "@providesDirectionalDerivative")]
    provides_directional_derivative: Option<String>,
    #[serde(rename = "SourceFiles")]
    source_files: Option<RawSourceFiles>,
}

#[derive(Deserialize)]
struct RawSourceFiles {
    #[serde(rename = "File", default)]
    files: Vec<RawNamed>,
}

#[derive(Deserialize)]
struct RawNamed {
    #[serde(rename = "@name")]
    name: Option<String>,
    #[serde(rename = "@description")]
    description: Option<String>,
}

#[derive(Deserialize)]
struct RawUnitDefinitions {
    #[serde(rename = "Unit", default)]
    units: Vec<RawUnit>,
}

#[derive(Deserialize)]
struct RawUnit {
    #[serde(rename = "@name")]
    name: Option<String>,
    #[serde(rename = "BaseUnit")]
    base_unit: Option<RawBaseUnit>,
    #[serde(rename = "DisplayUnit", default)]
    display_units: Vec<RawDisplayUnit>,
}

#[derive(Deserialize)]
struct RawBaseUnit {
    #[serde(rename = "@kg")]
    kg: Option<String>,
    #[serde(rename = "@m")]
    m: Option<String>,
    #[serde(rename = "@s")]
    s: Option<String>,
    #[serde(rename = "@A")]
    a: Option<String>,
    #[serde(rename = "@K")]
    k: Option<String>,
    #[serde(rename = "@mol")]
    mol: Option<String>,
    #[serde(rename = "@cd")]
    cd: Option<String>,
    #[serde(rename = "@rad")]
    rad: Option<String>,
    #[serde(rename = "@factor")]
    factor: Option<String>,
    #[serde(rename = "@offset")]
    offset: Option<String>,
}

#[derive(Deserialize)]
struct RawDisplayUnit {
    #[serde(rename = "@name")]
    name: Option<String>,
    #[serde(rename = "@factor")]
    factor: Option<String>,
    #[serde(rename = "@offset")]
    offset: Option<String>,
}

#[derive(Deserialize)]
struct RawTypeDefinitions {
    #[serde(rename = "SimpleType", default)]
    types: Vec<RawSimpleType>,
}

#[derive(Deserialize)]
struct RawSimpleType {
    #[serde(rename = "@name")]
    name: Option<String>,
    #[serde(rename = "@description")]
    description: Option<String>,
    #[serde(rename = "Real")]
    real: Option<RawTypeElement>,
    #[serde(rename = "Integer")]
    integer: Option<RawTypeElement>,
    #[serde(rename = "Boolean")]
    boolean: Option<RawTypeElement>,
    #[serde(rename = "String")]
    string: Option<RawTypeElement>,
    #[serde(rename = "Enumeration")]
    enumeration: Option<RawTypeElement>,
}

/// The type element of a `<SimpleType>` or a `<ScalarVariable>` (one raw shape for all
/// five base types; pass 3 reads the attributes that belong to the type).
#[derive(Deserialize)]
struct RawTypeElement {
    #[serde(rename = "@declaredType")]
    declared_type: Option<String>,
    #[serde(rename = "@quantity")]
    quantity: Option<String>,
    #[serde(rename = "@unit")]
    unit: Option<String>,
    #[serde(rename = "@displayUnit")]
    display_unit: Option<String>,
    #[serde(rename = "@relativeQuantity")]
    relative_quantity: Option<String>,
    #[serde(rename = "@min")]
    min: Option<String>,
    #[serde(rename = "@max")]
    max: Option<String>,
    #[serde(rename = "@nominal")]
    nominal: Option<String>,
    #[serde(rename = "@unbounded")]
    unbounded: Option<String>,
    #[serde(rename = "@start")]
    start: Option<String>,
    #[serde(rename = "@derivative")]
    derivative: Option<String>,
    #[serde(rename = "@reinit")]
    reinit: Option<String>,
    #[serde(rename = "Item", default)]
    items: Vec<RawItem>,
}

#[derive(Deserialize)]
struct RawItem {
    #[serde(rename = "@name")]
    name: Option<String>,
    #[serde(rename = "@value")]
    value: Option<String>,
    #[serde(rename = "@description")]
    description: Option<String>,
}

#[derive(Deserialize)]
struct RawLogCategories {
    #[serde(rename = "Category", default)]
    categories: Vec<RawNamed>,
}

#[derive(Deserialize)]
struct RawDefaultExperiment {
    #[serde(rename = "@startTime")]
    start_time: Option<String>,
    #[serde(rename = "@stopTime")]
    stop_time: Option<String>,
    #[serde(rename = "@tolerance")]
    tolerance: Option<String>,
    #[serde(rename = "@stepSize")]
    step_size: Option<String>,
}

#[derive(Deserialize)]
struct RawModelVariables {
    #[serde(rename = "ScalarVariable", default)]
    variables: Vec<RawScalarVariable>,
}

#[derive(Deserialize)]
struct RawScalarVariable {
    #[serde(rename = "@name")]
    name: Option<String>,
    #[serde(rename = "@valueReference")]
    value_reference: Option<String>,
    #[serde(rename = "@description")]
    description: Option<String>,
    #[serde(rename = "@causality")]
    causality: Option<String>,
    #[serde(rename = "@variability")]
    variability: Option<String>,
    #[serde(rename = "@initial")]
    initial: Option<String>,
    #[serde(rename = "@canHandleMultipleSetPerTimeInstant")]
    can_handle_multiple_set_per_time_instant: Option<String>,
    #[serde(rename = "Real")]
    real: Option<RawTypeElement>,
    #[serde(rename = "Integer")]
    integer: Option<RawTypeElement>,
    #[serde(rename = "Boolean")]
    boolean: Option<RawTypeElement>,
    #[serde(rename = "String")]
    string: Option<RawTypeElement>,
    #[serde(rename = "Enumeration")]
    enumeration: Option<RawTypeElement>,
}

#[derive(Deserialize)]
struct RawModelStructure {
    #[serde(rename = "Outputs")]
    outputs: Option<RawUnknowns>,
    #[serde(rename = "Derivatives")]
    derivatives: Option<RawUnknowns>,
    #[serde(rename = "InitialUnknowns")]
    initial_unknowns: Option<RawUnknowns>,
}

#[derive(Deserialize)]
struct RawUnknowns {
    #[serde(rename = "Unknown", default)]
    unknowns: Vec<RawUnknown>,
}

#[derive(Deserialize)]
struct RawUnknown {
    #[serde(rename = "@index")]
    index: Option<String>,
    #[serde(rename = "@dependencies")]
    dependencies: Option<String>,
    #[serde(rename = "@dependenciesKind")]
    dependencies_kind: Option<String>,
}

// ---------------------------------------------------------------------------------------
// Pass 3: conversion with checked values.

type R<T> = Result<T, String>;

fn required(value: Option<String>, attribute: &str, element: &str) -> R<String> {
    value.ok_or_else(|| format!("{element}: the required attribute {attribute} is missing"))
}

fn parse_bool(value: &str, attribute: &str, element: &str) -> R<bool> {
    match value.trim() {
        "true" | "1" => Ok(true),
        "false" | "0" => Ok(false),
        other => Err(format!(
            "{element}: {attribute}=\"{other}\" is not a boolean (true, false, 1 or 0)"
        )),
    }
}

fn opt_bool(value: &Option<String>, attribute: &str, element: &str) -> R<Option<bool>> {
    value
        .as_deref()
        .map(|v| parse_bool(v, attribute, element))
        .transpose()
}

fn flag(value: &Option<String>, attribute: &str, element: &str) -> R<bool> {
    Ok(opt_bool(value, attribute, element)?.unwrap_or(false))
}

/// `xs:double`, which also allows `INF`, `-INF` and `NaN`.
fn parse_f64(value: &str, attribute: &str, element: &str) -> R<f64> {
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

fn opt_f64(value: &Option<String>, attribute: &str, element: &str) -> R<Option<f64>> {
    value
        .as_deref()
        .map(|v| parse_f64(v, attribute, element))
        .transpose()
}

fn parse_int<T: FromStr>(value: &str, attribute: &str, element: &str, what: &str) -> R<T> {
    value
        .trim()
        .parse::<T>()
        .map_err(|_| format!("{element}: {attribute}=\"{value}\" is not {what}"))
}

fn opt_i32(value: &Option<String>, attribute: &str, element: &str) -> R<Option<i32>> {
    value
        .as_deref()
        .map(|v| parse_int(v, attribute, element, "a 32-bit integer"))
        .transpose()
}

fn opt_u32(value: &Option<String>, attribute: &str, element: &str) -> R<Option<u32>> {
    value
        .as_deref()
        .map(|v| parse_int(v, attribute, element, "an unsigned 32-bit integer"))
        .transpose()
}

fn keyword<T: FromStr<Err = String>>(value: &str, element: &str) -> R<T> {
    value.parse::<T>().map_err(|e| format!("{element}: {e}"))
}

fn convert(raw: RawModelDescription, lines: &SourceLines) -> R<ModelDescription> {
    let root = "<fmiModelDescription>";
    let in_root = at(lines.root);
    let fmi_version = required(raw.fmi_version, "fmiVersion", root).map_err(&in_root)?;
    if fmi_version != "2.0" {
        return Err(in_root(format!(
            "fmiVersion=\"{fmi_version}\" is not supported (only FMI 2.0 descriptions are read)"
        )));
    }
    let model_name = required(raw.model_name, "modelName", root).map_err(&in_root)?;
    let guid = required(raw.guid, "guid", root).map_err(&in_root)?;
    let variable_naming_convention = match raw.variable_naming_convention.as_deref() {
        None => VariableNamingConvention::Flat,
        Some(v) => keyword(v, root).map_err(&in_root)?,
    };
    let number_of_event_indicators = opt_u32(
        &raw.number_of_event_indicators,
        "numberOfEventIndicators",
        root,
    )
    .map_err(&in_root)?;

    let model_exchange = raw
        .model_exchange
        .map(|me| -> R<ModelExchange> {
            let el = "<ModelExchange>";
            Ok(ModelExchange {
                model_identifier: required(me.model_identifier.clone(), "modelIdentifier", el)?,
                needs_execution_tool: flag(&me.needs_execution_tool, "needsExecutionTool", el)?,
                completed_integrator_step_not_needed: flag(
                    &me.completed_integrator_step_not_needed,
                    "completedIntegratorStepNotNeeded",
                    el,
                )?,
                can_be_instantiated_only_once_per_process: flag(
                    &me.can_be_instantiated_only_once_per_process,
                    "canBeInstantiatedOnlyOncePerProcess",
                    el,
                )?,
                can_not_use_memory_management_functions: flag(
                    &me.can_not_use_memory_management_functions,
                    "canNotUseMemoryManagementFunctions",
                    el,
                )?,
                can_get_and_set_fmu_state: flag(
                    &me.can_get_and_set_fmu_state,
                    "canGetAndSetFMUstate",
                    el,
                )?,
                can_serialize_fmu_state: flag(
                    &me.can_serialize_fmu_state,
                    "canSerializeFMUstate",
                    el,
                )?,
                provides_directional_derivative: flag(
                    &me.provides_directional_derivative,
                    "providesDirectionalDerivative",
                    el,
                )?,
                source_files: source_files(me.source_files, el)?,
            })
        })
        .transpose()
        .map_err(at(lines.model_exchange))?;

    let co_simulation = raw
        .co_simulation
        .map(|cs| -> R<CoSimulation> {
            let el = "<CoSimulation>";
            Ok(CoSimulation {
                model_identifier: required(cs.model_identifier.clone(), "modelIdentifier", el)?,
                needs_execution_tool: flag(&cs.needs_execution_tool, "needsExecutionTool", el)?,
                can_handle_variable_communication_step_size: flag(
                    &cs.can_handle_variable_communication_step_size,
                    "canHandleVariableCommunicationStepSize",
                    el,
                )?,
                can_interpolate_inputs: flag(
                    &cs.can_interpolate_inputs,
                    "canInterpolateInputs",
                    el,
                )?,
                max_output_derivative_order: opt_u32(
                    &cs.max_output_derivative_order,
                    "maxOutputDerivativeOrder",
                    el,
                )?
                .unwrap_or(0),
                can_run_asynchronuously: flag(
                    &cs.can_run_asynchronuously,
                    "canRunAsynchronuously",
                    el,
                )?,
                can_be_instantiated_only_once_per_process: flag(
                    &cs.can_be_instantiated_only_once_per_process,
                    "canBeInstantiatedOnlyOncePerProcess",
                    el,
                )?,
                can_not_use_memory_management_functions: flag(
                    &cs.can_not_use_memory_management_functions,
                    "canNotUseMemoryManagementFunctions",
                    el,
                )?,
                can_get_and_set_fmu_state: flag(
                    &cs.can_get_and_set_fmu_state,
                    "canGetAndSetFMUstate",
                    el,
                )?,
                can_serialize_fmu_state: flag(
                    &cs.can_serialize_fmu_state,
                    "canSerializeFMUstate",
                    el,
                )?,
                provides_directional_derivative: flag(
                    &cs.provides_directional_derivative,
                    "providesDirectionalDerivative",
                    el,
                )?,
                source_files: source_files(cs.source_files, el)?,
            })
        })
        .transpose()
        .map_err(at(lines.co_simulation))?;

    let unit_definitions = raw
        .unit_definitions
        .map(|u| u.units)
        .unwrap_or_default()
        .into_iter()
        .enumerate()
        .map(|(i, u)| convert_unit(u, i + 1).map_err(at(lines.units.get(i).copied())))
        .collect::<R<Vec<_>>>()?;

    let type_definitions = raw
        .type_definitions
        .map(|t| t.types)
        .unwrap_or_default()
        .into_iter()
        .enumerate()
        .map(|(i, t)| convert_simple_type(t, i + 1).map_err(at(lines.types.get(i).copied())))
        .collect::<R<Vec<_>>>()?;

    let log_categories = raw
        .log_categories
        .map(|c| c.categories)
        .unwrap_or_default()
        .into_iter()
        .enumerate()
        .map(|(i, c)| {
            Ok(LogCategory {
                name: required(c.name, "name", &format!("<Category> {}", i + 1))
                    .map_err(at(lines.categories.get(i).copied()))?,
                description: c.description,
            })
        })
        .collect::<R<Vec<_>>>()?;

    let default_experiment = raw
        .default_experiment
        .map(|d| -> R<DefaultExperiment> {
            let el = "<DefaultExperiment>";
            Ok(DefaultExperiment {
                start_time: opt_f64(&d.start_time, "startTime", el)?,
                stop_time: opt_f64(&d.stop_time, "stopTime", el)?,
                tolerance: opt_f64(&d.tolerance, "tolerance", el)?,
                step_size: opt_f64(&d.step_size, "stepSize", el)?,
            })
        })
        .transpose()
        .map_err(at(lines.default_experiment))?;

    let raw_variables = raw
        .model_variables
        .ok_or_else(|| in_root("the required element <ModelVariables> is missing".into()))?
        .variables;
    let model_variables = raw_variables
        .into_iter()
        .enumerate()
        .map(|(i, v)| convert_variable(v, i + 1).map_err(at(lines.variables.get(i).copied())))
        .collect::<R<Vec<_>>>()?;

    let raw_structure = raw
        .model_structure
        .ok_or_else(|| in_root("the required element <ModelStructure> is missing".into()))?;
    let model_structure = ModelStructure {
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
    };

    Ok(ModelDescription {
        fmi_version,
        model_name,
        guid,
        description: raw.description,
        author: raw.author,
        version: raw.version,
        copyright: raw.copyright,
        license: raw.license,
        generation_tool: raw.generation_tool,
        generation_date_and_time: raw.generation_date_and_time,
        variable_naming_convention,
        number_of_event_indicators,
        model_exchange,
        co_simulation,
        unit_definitions,
        type_definitions,
        log_categories,
        default_experiment,
        vendor_annotations: None,
        model_variables,
        model_structure,
        source_lines: SourceLines::default(),
    })
}

fn source_files(raw: Option<RawSourceFiles>, element: &str) -> R<Vec<String>> {
    raw.map(|s| s.files)
        .unwrap_or_default()
        .into_iter()
        .map(|f| required(f.name, "name", &format!("{element}/SourceFiles/File")))
        .collect()
}

fn convert_unit(u: RawUnit, position: usize) -> R<Unit> {
    let name = required(u.name, "name", &format!("<Unit> {position}"))?;
    let el = format!("<Unit name=\"{name}\">");
    let base_unit = u
        .base_unit
        .map(|b| -> R<BaseUnit> {
            let el = format!("{el}/BaseUnit");
            let exp =
                |v: &Option<String>, a: &str| -> R<i32> { Ok(opt_i32(v, a, &el)?.unwrap_or(0)) };
            Ok(BaseUnit {
                kg: exp(&b.kg, "kg")?,
                m: exp(&b.m, "m")?,
                s: exp(&b.s, "s")?,
                a: exp(&b.a, "A")?,
                k: exp(&b.k, "K")?,
                mol: exp(&b.mol, "mol")?,
                cd: exp(&b.cd, "cd")?,
                rad: exp(&b.rad, "rad")?,
                factor: opt_f64(&b.factor, "factor", &el)?.unwrap_or(1.0),
                offset: opt_f64(&b.offset, "offset", &el)?.unwrap_or(0.0),
            })
        })
        .transpose()?;
    let display_units = u
        .display_units
        .into_iter()
        .map(|d| -> R<DisplayUnit> {
            let del = format!("{el}/DisplayUnit");
            Ok(DisplayUnit {
                name: required(d.name, "name", &del)?,
                factor: opt_f64(&d.factor, "factor", &del)?.unwrap_or(1.0),
                offset: opt_f64(&d.offset, "offset", &del)?.unwrap_or(0.0),
            })
        })
        .collect::<R<Vec<_>>>()?;
    Ok(Unit {
        name,
        base_unit,
        display_units,
    })
}

fn real_attributes(e: &RawTypeElement, el: &str) -> R<RealAttributes> {
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

fn integer_attributes(e: &RawTypeElement, el: &str) -> R<IntegerAttributes> {
    Ok(IntegerAttributes {
        quantity: e.quantity.clone(),
        min: opt_i32(&e.min, "min", el)?,
        max: opt_i32(&e.max, "max", el)?,
    })
}

/// The one type element of a `<SimpleType>` or `<ScalarVariable>`.
fn single_type_element(
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

fn convert_simple_type(t: RawSimpleType, position: usize) -> R<SimpleType> {
    let name = required(t.name, "name", &format!("<SimpleType> {position}"))?;
    let el = format!("<SimpleType name=\"{name}\">");
    let (type_name, e) = single_type_element(
        [
            ("Real", t.real),
            ("Integer", t.integer),
            ("Boolean", t.boolean),
            ("String", t.string),
            ("Enumeration", t.enumeration),
        ],
        &el,
    )?;
    let tel = format!("{el}/{type_name}");
    let kind = match type_name {
        "Real" => SimpleTypeKind::Real(real_attributes(&e, &tel)?),
        "Integer" => SimpleTypeKind::Integer(integer_attributes(&e, &tel)?),
        "Boolean" => SimpleTypeKind::Boolean,
        "String" => SimpleTypeKind::String,
        _ => SimpleTypeKind::Enumeration {
            attributes: integer_attributes(&e, &tel)?,
            items: e
                .items
                .into_iter()
                .map(|item| -> R<EnumerationItem> {
                    let iel = format!("{tel}/Item");
                    let value = required(item.value, "value", &iel)?;
                    Ok(EnumerationItem {
                        name: required(item.name, "name", &iel)?,
                        value: parse_int(&value, "value", &iel, "a 32-bit integer")?,
                        description: item.description,
                    })
                })
                .collect::<R<Vec<_>>>()?,
        },
    };
    Ok(SimpleType {
        name,
        description: t.description,
        kind,
    })
}

fn convert_variable(v: RawScalarVariable, index: usize) -> R<ScalarVariable> {
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
