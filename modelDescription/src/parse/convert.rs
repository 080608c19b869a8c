//! Pass 3 of reading: converting the raw structs into a [`ModelDescription`], checking
//! every value and naming the element (and its line) in each error. The root attributes,
//! UnitDefinitions, TypeDefinitions, LogCategories and DefaultExperiment are converted
//! here; interfaces, variables and ModelStructure have their own modules.

use super::interface::{convert_co_simulation, convert_model_exchange};
use super::raw::*;
use super::structure::convert_model_structure;
use super::type_element::{integer_attributes, real_attributes, single_type_element};
use super::values::{at, keyword, opt_f64, opt_i32, opt_u32, parse_int, required, R};
use super::variables::convert_variable;
use crate::types::*;

pub(super) fn convert(raw: RawModelDescription, lines: &SourceLines) -> R<ModelDescription> {
    let root = "<fmiModelDescription>";
    let in_root = at(lines.root);
    let fmi_version = required(raw.fmi_version, "fmiVersion", root).map_err(&in_root)?;
    if fmi_version != "2.0" {
        return Err(in_root(format!(
            "fmiVersion=\"{fmi_version}\" is not supported (FMI 2.0 and 3.0 descriptions are read)"
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
        .map(convert_model_exchange)
        .transpose()
        .map_err(at(lines.model_exchange))?;

    let co_simulation = raw
        .co_simulation
        .map(convert_co_simulation)
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
        .map(convert_default_experiment)
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
    let model_structure = convert_model_structure(raw_structure, lines)?;

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

fn convert_default_experiment(d: RawDefaultExperiment) -> R<DefaultExperiment> {
    let el = "<DefaultExperiment>";
    Ok(DefaultExperiment {
        start_time: opt_f64(&d.start_time, "startTime", el)?,
        stop_time: opt_f64(&d.stop_time, "stopTime", el)?,
        tolerance: opt_f64(&d.tolerance, "tolerance", el)?,
        step_size: opt_f64(&d.step_size, "stepSize", el)?,
    })
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
