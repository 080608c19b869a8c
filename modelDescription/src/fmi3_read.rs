//! Reading an FMI 3.0 `modelDescription.xml` into a [`ModelDescription`], for the
//! Co-Simulation FMUs the importer runs: what the document says in FMI 2.0's terms, and a
//! refusal naming the line and the element for what has none.
//!
//! | FMI 3.0 | read as |
//! |---|---|
//! | `instantiationToken` | `guid` |
//! | `<Float64>` | a Real variable (`derivative` by value reference → index) |
//! | `<Int32>`, `<Boolean>`, `<String>` (`start` or `<Start value>`) | Integer, Boolean, String |
//! | `<Output>`, `<ContinuousStateDerivative>`, `<InitialUnknown>` (dependencies by value reference) | `outputs`, `derivatives`, `initial_unknowns` (by index) |
//! | `canGetAndSetFMUState`, `canSerializeFMUState`, `providesDirectionalDerivatives` | the FMI 2.0 flags |
//! | `<Float64Type>` | a Real type definition |
//!
//! `fmi_version` is kept as written (`"3.0"`). Refused: the other variable types (Float32,
//! 8/16/64-bit and unsigned integers, Enumeration, Binary, Clock), arrays (`<Dimension>`),
//! clocked variables, a ModelStructure entry naming no variable. An FMU without
//! `<CoSimulation>` reads with `co_simulation = None` (the importer refuses it, naming
//! the interfaces it has).

use crate::error::Error;
use crate::types::*;
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::HashMap;

fn attr(e: &BytesStart<'_>, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.local_name().as_ref() == key)
        .and_then(|a| {
            a.normalized_value(quick_xml::XmlVersion::Implicit1_0)
                .ok()
                .map(|v| v.into_owned())
        })
}

fn flag(e: &BytesStart<'_>, key: &str) -> bool {
    attr(e, key).as_deref() == Some("true")
}

fn line_of(text: &str, pos: usize) -> usize {
    text[..pos.min(text.len())].matches('\n').count() + 1
}

/// A number attribute, or the message naming it.
fn num<T: std::str::FromStr>(e: &BytesStart<'_>, key: &str) -> Result<Option<T>, String> {
    attr(e, key)
        .map(|v| {
            v.trim()
                .parse()
                .map_err(|_| format!("{key}=\"{v}\" is not a valid number"))
        })
        .transpose()
}

fn boolean(e: &BytesStart<'_>, key: &str) -> Result<Option<bool>, String> {
    match attr(e, key).as_deref() {
        None => Ok(None),
        Some("true") | Some("1") => Ok(Some(true)),
        Some("false") | Some("0") => Ok(Some(false)),
        Some(v) => Err(format!("{key}=\"{v}\" is not true or false")),
    }
}

fn real_attributes(e: &BytesStart<'_>) -> Result<RealAttributes, String> {
    Ok(RealAttributes {
        quantity: attr(e, "quantity"),
        unit: attr(e, "unit"),
        display_unit: attr(e, "displayUnit"),
        relative_quantity: boolean(e, "relativeQuantity")?,
        min: num(e, "min")?,
        max: num(e, "max")?,
        nominal: num(e, "nominal")?,
        unbounded: boolean(e, "unbounded")?,
    })
}

/// A variable element's common attributes and its kind.
fn variable(e: &BytesStart<'_>, element: &str) -> Result<ScalarVariable, String> {
    let name = attr(e, "name").ok_or("has no name")?;
    let vr =
        num(e, "valueReference")?.ok_or_else(|| format!("\"{name}\" has no valueReference"))?;
    let keyword = |key: &str, default: &str| attr(e, key).unwrap_or_else(|| default.to_owned());
    let causality: Causality = keyword("causality", "local")
        .parse()
        .map_err(|m| format!("\"{name}\": {m}"))?;
    let default_variability = if element == "Float64" {
        "continuous"
    } else {
        "discrete"
    };
    let variability: Variability = keyword("variability", default_variability)
        .parse()
        .map_err(|m| format!("\"{name}\": {m}"))?;
    let initial = attr(e, "initial")
        .map(|i| i.parse::<Initial>().map_err(|m| format!("\"{name}\": {m}")))
        .transpose()?;
    let declared_type = attr(e, "declaredType");
    let kind = match element {
        "Float64" => VariableKind::Real(RealVariable {
            declared_type,
            attributes: real_attributes(e)?,
            start: num(e, "start")?,
            // a value reference until every variable is read (see `resolve`)
            derivative: num(e, "derivative")?,
            reinit: boolean(e, "reinit")?,
        }),
        "Int32" => VariableKind::Integer(IntegerVariable {
            declared_type,
            attributes: IntegerAttributes {
                quantity: attr(e, "quantity"),
                min: num(e, "min")?,
                max: num(e, "max")?,
            },
            start: num(e, "start")?,
        }),
        "Boolean" => VariableKind::Boolean(BooleanVariable {
            declared_type,
            start: boolean(e, "start")?,
        }),
        _ => VariableKind::String(StringVariable {
            declared_type,
            start: attr(e, "start"),
        }),
    };
    if attr(e, "clocks").is_some() {
        return Err(format!("\"{name}\" is clocked; clocks are not supported"));
    }
    Ok(ScalarVariable {
        name,
        value_reference: vr,
        description: attr(e, "description"),
        causality,
        variability,
        initial,
        can_handle_multiple_set_per_time_instant: boolean(e, "canHandleMultipleSetPerTimeInstant")?,
        kind,
    })
}

/// The variable types FMI 3.0 has that the importer does not run.
const OTHER_TYPES: &[&str] = &[
    "Float32",
    "Int8",
    "UInt8",
    "Int16",
    "UInt16",
    "UInt32",
    "Int64",
    "UInt64",
    "Enumeration",
    "Binary",
    "Clock",
];

/// A ModelStructure entry as read: its value reference and dependencies (by value
/// reference), to become indices.
struct RawUnknown {
    line: usize,
    vr: u32,
    dependencies: Option<Vec<u32>>,
    kinds: Option<Vec<DependencyKind>>,
}

fn unknown(e: &BytesStart<'_>, line: usize) -> Result<RawUnknown, String> {
    let vr = num(e, "valueReference")?.ok_or("has no valueReference")?;
    let dependencies = attr(e, "dependencies")
        .map(|d| {
            d.split_whitespace()
                .map(|v| {
                    v.parse()
                        .map_err(|_| format!("dependencies: \"{v}\" is not a value reference"))
                })
                .collect::<Result<Vec<u32>, String>>()
        })
        .transpose()?;
    let kinds = attr(e, "dependenciesKind")
        .map(|k| {
            k.split_whitespace()
                .map(|v| v.parse::<DependencyKind>())
                .collect::<Result<Vec<_>, _>>()
        })
        .transpose()?;
    Ok(RawUnknown {
        line,
        vr,
        dependencies,
        kinds,
    })
}

/// Parse an FMI 3.0 description (see the module docs); `origin` names it in messages.
pub fn parse_fmi3(xml: &str, origin: &str) -> Result<ModelDescription, Error> {
    let mut md = ModelDescription::empty("", "", "");
    let mut structure: Vec<(&'static str, RawUnknown)> = Vec::new();
    // FMI 3.0's <Alias> elements, variables of their own after all others (as FMPy lists them)
    let mut aliases: Vec<ScalarVariable> = Vec::new();
    let mut reader = Reader::from_str(xml);
    let mut stack: Vec<String> = Vec::new();
    loop {
        let pos = reader.buffer_position() as usize;
        let event = reader.read_event().map_err(|e| {
            let line = line_of(xml, reader.error_position() as usize);
            Error::new(origin, format!("line {line}: malformed XML: {e}"))
        })?;
        let line = line_of(xml, pos);
        let at = |m: String| Error::new(origin, format!("line {line}: {m}"));
        match event {
            Event::Start(ref e) | Event::Empty(ref e) => {
                let name = e.local_name().as_ref().to_owned();
                let parent = stack.last().map(String::as_str);
                match (parent, name.as_str()) {
                    (None, "fmiModelDescription") => root(&mut md, e).map_err(at)?,
                    (None, other) => return Err(at(format!("the root element is <{other}>, not <fmiModelDescription>"))),
                    (Some("fmiModelDescription"), "CoSimulation") => {
                        md.co_simulation = Some(co_simulation(e).map_err(at)?);
                    }
                    (Some("fmiModelDescription"), "ModelExchange") => {
                        md.model_exchange = Some(ModelExchange {
                            model_identifier: attr(e, "modelIdentifier").unwrap_or_default(),
                            ..Default::default()
                        });
                    }
                    (Some("UnitDefinitions"), "Unit") => md.unit_definitions.push(Unit {
                        name: attr(e, "name").ok_or_else(|| at("<Unit> has no name".into()))?,
                        ..Default::default()
                    }),
                    (Some("Unit"), "DisplayUnit") => {
                        let unit = md.unit_definitions.last_mut().expect("inside a unit");
                        unit.display_units.push(DisplayUnit {
                            name: attr(e, "name").ok_or_else(|| at("<DisplayUnit> has no name".into()))?,
                            factor: num(e, "factor").map_err(at)?.unwrap_or(1.0),
                            offset: num(e, "offset").map_err(at)?.unwrap_or(0.0),
                        });
                    }
                    (Some("Unit"), "BaseUnit") => {
                        let unit = md.unit_definitions.last_mut().expect("inside a unit");
                        unit.base_unit = Some(base_unit(e).map_err(at)?);
                    }
                    (Some("TypeDefinitions"), "Float64Type") => md.type_definitions.push(SimpleType {
                        name: attr(e, "name").ok_or_else(|| at("<Float64Type> has no name".into()))?,
                        description: attr(e, "description"),
                        kind: SimpleTypeKind::Real(real_attributes(e).map_err(at)?),
                    }),
                    (Some("TypeDefinitions"), other) => {
                        return Err(at(format!("type definition <{other}>: only Float64 types are supported")))
                    }
                    (Some("LogCategories"), "Category") => md.log_categories.push(LogCategory {
                        name: attr(e, "name").unwrap_or_default(),
                        description: attr(e, "description"),
                    }),
                    (Some("fmiModelDescription"), "DefaultExperiment") => {
                        md.default_experiment = Some(DefaultExperiment {
                            start_time: num(e, "startTime").map_err(at)?,
                            stop_time: num(e, "stopTime").map_err(at)?,
                            tolerance: num(e, "tolerance").map_err(at)?,
                            step_size: num(e, "stepSize").map_err(at)?,
                        });
                    }
                    (Some("ModelVariables"), "Float64" | "Int32" | "Boolean" | "String") => {
                        let v = variable(e, &name).map_err(|m| at(format!("<{name}> {m}")))?;
                        md.model_variables.push(v);
                    }
                    (Some("ModelVariables"), other) if OTHER_TYPES.contains(&other) => {
                        return Err(at(format!(
                            "variable \"{}\" is of type {other}; the importer runs Float64, Int32, Boolean and String variables",
                            attr(e, "name").unwrap_or_default()
                        )))
                    }
                    (Some("Float64" | "Int32" | "Boolean" | "String"), "Dimension") => {
                        let v = md.model_variables.last().map(|v| v.name.clone()).unwrap_or_default();
                        return Err(at(format!("variable \"{v}\" is an array; arrays are not supported")));
                    }
                    (Some("Float64" | "Int32" | "Boolean" | "String"), "Alias") => {
                        let of = md.model_variables.last().expect("inside a variable");
                        aliases.push(alias(of, e).map_err(at)?);
                    }
                    (Some("String"), "Start") => {
                        if let Some(VariableKind::String(s)) = md.model_variables.last_mut().map(|v| &mut v.kind) {
                            s.start = attr(e, "value");
                        }
                    }
                    (Some("ModelStructure"), kind @ ("Output" | "ContinuousStateDerivative" | "InitialUnknown")) => {
                        let list = match kind {
                            "Output" => "Output",
                            "ContinuousStateDerivative" => "ContinuousStateDerivative",
                            _ => "InitialUnknown",
                        };
                        structure.push((list, unknown(e, line).map_err(|m| at(format!("<{kind}> {m}")))?));
                    }
                    _ => {}
                }
                if matches!(event, Event::Start(_)) {
                    stack.push(name);
                }
            }
            Event::End(_) => {
                stack.pop();
            }
            Event::Eof => break,
            _ => {}
        }
    }
    if md.fmi_version.is_empty() {
        return Err(Error::new(origin, "no <fmiModelDescription> element"));
    }
    md.model_variables.extend(aliases);
    resolve(&mut md, structure).map_err(|m| Error::new(origin, m))?;
    Ok(md)
}

/// An `<Alias>` of `of`: the same variable (value reference, causality, variability,
/// initial) under its own name, description and display unit; the start value stays with
/// `of` (at most one variable of an alias set has one).
fn alias(of: &ScalarVariable, e: &BytesStart<'_>) -> Result<ScalarVariable, String> {
    let mut v = of.clone();
    v.name = attr(e, "name").ok_or_else(|| format!("an <Alias> of \"{}\" has no name", of.name))?;
    v.description = attr(e, "description");
    match &mut v.kind {
        VariableKind::Real(r) => {
            r.start = None;
            r.derivative = None;
            if let Some(unit) = attr(e, "displayUnit") {
                r.attributes.display_unit = Some(unit);
            }
        }
        VariableKind::Integer(i) => i.start = None,
        VariableKind::Boolean(b) => b.start = None,
        VariableKind::String(s) => s.start = None,
        VariableKind::Enumeration(n) => n.start = None,
    }
    Ok(v)
}

/// The root's attributes.
fn root(md: &mut ModelDescription, e: &BytesStart<'_>) -> Result<(), String> {
    md.fmi_version = attr(e, "fmiVersion").ok_or("<fmiModelDescription> has no fmiVersion")?;
    if !md.fmi_version.starts_with("3.") {
        return Err(format!("fmiVersion=\"{}\" is not FMI 3", md.fmi_version));
    }
    md.model_name = attr(e, "modelName").ok_or("<fmiModelDescription> has no modelName")?;
    md.guid =
        attr(e, "instantiationToken").ok_or("<fmiModelDescription> has no instantiationToken")?;
    md.description = attr(e, "description");
    md.author = attr(e, "author");
    md.version = attr(e, "version");
    md.copyright = attr(e, "copyright");
    md.license = attr(e, "license");
    md.generation_tool = attr(e, "generationTool");
    md.generation_date_and_time = attr(e, "generationDateAndTime");
    if let Some(c) = attr(e, "variableNamingConvention") {
        md.variable_naming_convention = c.parse()?;
    }
    Ok(())
}

fn co_simulation(e: &BytesStart<'_>) -> Result<CoSimulation, String> {
    Ok(CoSimulation {
        model_identifier: attr(e, "modelIdentifier")
            .ok_or("<CoSimulation> has no modelIdentifier")?,
        needs_execution_tool: flag(e, "needsExecutionTool"),
        can_handle_variable_communication_step_size: flag(
            e,
            "canHandleVariableCommunicationStepSize",
        ),
        max_output_derivative_order: num(e, "maxOutputDerivativeOrder")?.unwrap_or(0),
        can_be_instantiated_only_once_per_process: flag(e, "canBeInstantiatedOnlyOncePerProcess"),
        can_get_and_set_fmu_state: flag(e, "canGetAndSetFMUState"),
        can_serialize_fmu_state: flag(e, "canSerializeFMUState"),
        provides_directional_derivative: flag(e, "providesDirectionalDerivatives"),
        ..Default::default()
    })
}

fn base_unit(e: &BytesStart<'_>) -> Result<BaseUnit, String> {
    let exponent = |k: &str| num::<i32>(e, k).map(Option::unwrap_or_default);
    Ok(BaseUnit {
        kg: exponent("kg")?,
        m: exponent("m")?,
        s: exponent("s")?,
        a: exponent("A")?,
        k: exponent("K")?,
        mol: exponent("mol")?,
        cd: exponent("cd")?,
        rad: exponent("rad")?,
        factor: num(e, "factor")?.unwrap_or(1.0),
        offset: num(e, "offset")?.unwrap_or(0.0),
    })
}

/// Value references to 1-based indices: `derivative` and the ModelStructure entries.
fn resolve(
    md: &mut ModelDescription,
    structure: Vec<(&'static str, RawUnknown)>,
) -> Result<(), String> {
    let mut index: HashMap<u32, u32> = HashMap::new();
    for (i, v) in md.model_variables.iter().enumerate() {
        index.entry(v.value_reference).or_insert(i as u32 + 1);
    }
    let index_of = |vr: u32, what: &str| {
        index
            .get(&vr)
            .copied()
            .ok_or_else(|| format!("{what}: value reference {vr} names no variable"))
    };
    let mut derivatives = Vec::new();
    for v in &md.model_variables {
        if let VariableKind::Real(RealVariable {
            derivative: Some(d),
            ..
        }) = &v.kind
        {
            derivatives.push(index_of(
                *d,
                &format!("variable \"{}\" derivative", v.name),
            )?);
        } else {
            derivatives.push(0);
        }
    }
    for (v, d) in md.model_variables.iter_mut().zip(derivatives) {
        if let VariableKind::Real(r) = &mut v.kind {
            r.derivative = (d > 0).then_some(d);
        }
    }
    for (list, raw) in structure {
        let what = format!("line {}: <{list}>", raw.line);
        let dependencies = raw
            .dependencies
            .map(|d| {
                d.iter()
                    .map(|&vr| index_of(vr, &what))
                    .collect::<Result<Vec<_>, _>>()
            })
            .transpose()?;
        let u = Unknown {
            index: index_of(raw.vr, &what)?,
            dependencies,
            dependencies_kind: raw.kinds,
        };
        match list {
            "Output" => md.model_structure.outputs.push(u),
            "ContinuousStateDerivative" => md.model_structure.derivatives.push(u),
            _ => md.model_structure.initial_unknowns.push(u),
        }
    }
    // an alias (a later variable with a value reference already seen) is an unknown where
    // its variable is, with the same dependencies
    let s = &mut md.model_structure;
    for (i, v) in md.model_variables.iter().enumerate() {
        let (own, first) = (i as u32 + 1, index[&v.value_reference]);
        if own == first {
            continue;
        }
        for list in [&mut s.outputs, &mut s.derivatives, &mut s.initial_unknowns] {
            if let Some(u) = list.iter().find(|u| u.index == first).cloned() {
                list.push(Unknown { index: own, ..u });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const FMI2: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="m" guid="{g}">
  <CoSimulation modelIdentifier="m" canGetAndSetFMUstate="true" canHandleVariableCommunicationStepSize="true"/>
  <UnitDefinitions><Unit name="m"/><Unit name="s"><BaseUnit s="1"/></Unit></UnitDefinitions>
  <ModelVariables>
    <ScalarVariable name="u" valueReference="7" causality="input" variability="continuous"><Real start="0" unit="m"/></ScalarVariable>
    <ScalarVariable name="x" valueReference="3" causality="output" variability="continuous" initial="exact"><Real start="1"/></ScalarVariable>
    <ScalarVariable name="dx" valueReference="5" causality="local" variability="continuous"><Real derivative="2"/></ScalarVariable>
    <ScalarVariable name="n" valueReference="9" causality="parameter" variability="fixed"><Integer start="4"/></ScalarVariable>
    <ScalarVariable name="on" valueReference="1" causality="parameter" variability="fixed"><Boolean start="true"/></ScalarVariable>
    <ScalarVariable name="label" valueReference="2" causality="parameter" variability="fixed"><String start="hi"/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="2" dependencies="1" dependenciesKind="dependent"/></Outputs>
    <Derivatives><Unknown index="3" dependencies="1 2"/></Derivatives>
    <InitialUnknowns><Unknown index="2" dependencies=""/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn the_fmi3_writing_reads_back_as_the_fmi2_description() {
        let two = ModelDescription::parse(FMI2, "m.xml").unwrap();
        let three = parse_fmi3(&two.to_fmi3_xml_string().unwrap(), "m3.xml").unwrap();
        assert_eq!(three.fmi_version, "3.0");
        // FMI 3.0 adds the independent variable time, first
        let time = &three.model_variables[0];
        assert_eq!(
            (time.name.as_str(), time.causality),
            ("time", Causality::Independent)
        );
        let mut expected = two.clone();
        expected.fmi_version = "3.0".into();
        expected.model_variables.insert(0, time.clone());
        let shift = |u: &mut Unknown| {
            u.index += 1;
            if let Some(d) = &mut u.dependencies {
                d.iter_mut().for_each(|i| *i += 1);
            }
        };
        let s = &mut expected.model_structure;
        s.outputs
            .iter_mut()
            .chain(&mut s.derivatives)
            .chain(&mut s.initial_unknowns)
            .for_each(shift);
        if let VariableKind::Real(r) = &mut expected.model_variables[3].kind {
            r.derivative = Some(3);
        }
        assert_eq!(three, expected);
    }

    #[test]
    fn what_the_importer_does_not_run_is_refused_with_the_line() {
        let base = ModelDescription::parse(FMI2, "m.xml")
            .unwrap()
            .to_fmi3_xml_string()
            .unwrap();
        for (from, to, needle) in [
            (
                r#"<Int32 name="n""#,
                r#"<Int64 name="n""#,
                "variable \"n\" is of type Int64",
            ),
            (
                r#"<Float64 name="u" valueReference="7" causality="input" variability="continuous" unit="m" start="0.0"/>"#,
                r#"<Float64 name="u" valueReference="7" causality="input" variability="continuous" start="0.0"><Dimension start="2"/></Float64>"#,
                "variable \"u\" is an array",
            ),
            (
                r#"dependencies="7""#,
                r#"dependencies="8""#,
                "value reference 8 names no variable",
            ),
        ] {
            assert!(base.contains(from), "{from}");
            let e = parse_fmi3(&base.replace(from, to), "m3.xml")
                .unwrap_err()
                .to_string();
            assert!(e.contains(needle) && e.contains("line "), "{e}");
        }
    }
}
