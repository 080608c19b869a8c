//! Writing `modelDescription.xml`.
//!
//! The writer emits elements in the order the FMI 2.0 schema prescribes, attribute values
//! escaped with quick-xml's escaper, numbers in the shortest form that reads back to the
//! same `f64` (`INF`, `-INF` and `NaN` as `xs:double` spells them) and `causality` /
//! `variability` always explicit. `<VendorAnnotations>` is written back verbatim.

use crate::types::*;
use quick_xml::escape::escape;
use std::fmt::Write as _;

/// An `xs:double` literal that parses back to exactly `v`.
pub(crate) fn format_f64(v: f64) -> String {
    if v.is_nan() {
        "NaN".to_owned()
    } else if v == f64::INFINITY {
        "INF".to_owned()
    } else if v == f64::NEG_INFINITY {
        "-INF".to_owned()
    } else {
        format!("{v:?}")
    }
}

fn format_bool(b: bool) -> &'static str {
    if b {
        "true"
    } else {
        "false"
    }
}

/// Accumulates one element's attributes.
pub(crate) struct Attrs(pub(crate) String);

impl Attrs {
    pub(crate) fn new() -> Self {
        Attrs(String::new())
    }
    pub(crate) fn s(&mut self, name: &str, value: &str) -> &mut Self {
        let _ = write!(self.0, " {name}=\"{}\"", escape(value));
        self
    }
    pub(crate) fn os(&mut self, name: &str, value: &Option<String>) -> &mut Self {
        if let Some(v) = value {
            self.s(name, v);
        }
        self
    }
    pub(crate) fn f(&mut self, name: &str, value: Option<f64>) -> &mut Self {
        if let Some(v) = value {
            self.s(name, &format_f64(v));
        }
        self
    }
    pub(crate) fn i<T: ToString>(&mut self, name: &str, value: Option<T>) -> &mut Self {
        if let Some(v) = value {
            self.s(name, &v.to_string());
        }
        self
    }
    pub(crate) fn b(&mut self, name: &str, value: Option<bool>) -> &mut Self {
        if let Some(v) = value {
            self.s(name, format_bool(v));
        }
        self
    }
    /// A capability flag: written only when `true` (its default is `false`).
    pub(crate) fn flag(&mut self, name: &str, value: bool) -> &mut Self {
        if value {
            self.s(name, "true");
        }
        self
    }
}

/// Writes indented elements.
pub(crate) struct Out {
    pub(crate) text: String,
}

impl Out {
    pub(crate) fn line(&mut self, depth: usize, content: &str) {
        for _ in 0..depth {
            self.text.push_str("  ");
        }
        self.text.push_str(content);
        self.text.push('\n');
    }
    pub(crate) fn empty(&mut self, depth: usize, name: &str, attrs: &Attrs) {
        self.line(depth, &format!("<{name}{}/>", attrs.0));
    }
    pub(crate) fn open(&mut self, depth: usize, name: &str, attrs: &Attrs) {
        self.line(depth, &format!("<{name}{}>", attrs.0));
    }
    pub(crate) fn close(&mut self, depth: usize, name: &str) {
        self.line(depth, &format!("</{name}>"));
    }
}

pub(crate) fn real_attrs(a: &mut Attrs, r: &RealAttributes) {
    a.os("quantity", &r.quantity)
        .os("unit", &r.unit)
        .os("displayUnit", &r.display_unit)
        .b("relativeQuantity", r.relative_quantity)
        .f("min", r.min)
        .f("max", r.max)
        .f("nominal", r.nominal)
        .b("unbounded", r.unbounded);
}

fn integer_attrs(a: &mut Attrs, i: &IntegerAttributes) {
    a.os("quantity", &i.quantity)
        .i("min", i.min)
        .i("max", i.max);
}

fn source_files(out: &mut Out, depth: usize, files: &[String]) {
    if files.is_empty() {
        return;
    }
    out.open(depth, "SourceFiles", &Attrs::new());
    for f in files {
        let mut a = Attrs::new();
        a.s("name", f);
        out.empty(depth + 1, "File", &a);
    }
    out.close(depth, "SourceFiles");
}

fn unknowns(out: &mut Out, name: &str, list: &[Unknown]) {
    if list.is_empty() {
        return;
    }
    out.open(2, name, &Attrs::new());
    for u in list {
        let mut a = Attrs::new();
        a.s("index", &u.index.to_string());
        if let Some(d) = &u.dependencies {
            let d: Vec<String> = d.iter().map(u32::to_string).collect();
            a.s("dependencies", &d.join(" "));
        }
        if let Some(k) = &u.dependencies_kind {
            let k: Vec<&str> = k.iter().map(|k| k.as_str()).collect();
            a.s("dependenciesKind", &k.join(" "));
        }
        out.empty(3, "Unknown", &a);
    }
    out.close(2, name);
}

impl ModelDescription {
    /// The root element's attributes both versions share: `fmiVersion`, `modelName`, the
    /// GUID under `token` (`guid`, FMI 3.0's `instantiationToken`), the texts and
    /// `variableNamingConvention`.
    pub(crate) fn root_attrs(&self, fmi_version: &str, token: &str) -> Attrs {
        let mut root = Attrs::new();
        root.s("fmiVersion", fmi_version)
            .s("modelName", &self.model_name)
            .s(token, &self.guid)
            .os("description", &self.description)
            .os("author", &self.author)
            .os("version", &self.version)
            .os("copyright", &self.copyright)
            .os("license", &self.license)
            .os("generationTool", &self.generation_tool)
            .os("generationDateAndTime", &self.generation_date_and_time)
            .s(
                "variableNamingConvention",
                self.variable_naming_convention.as_str(),
            );
        root
    }

    /// The description as a complete `modelDescription.xml` document (UTF-8, indented).
    pub fn to_xml_string(&self) -> String {
        let mut out = Out {
            text: String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"),
        };
        let mut root = self.root_attrs(&self.fmi_version, "guid");
        root.i("numberOfEventIndicators", self.number_of_event_indicators);
        out.open(0, "fmiModelDescription", &root);

        if let Some(me) = &self.model_exchange {
            write_model_exchange(&mut out, me);
        }
        if let Some(cs) = &self.co_simulation {
            write_co_simulation(&mut out, cs);
        }
        if !self.unit_definitions.is_empty() {
            write_unit_definitions(&mut out, &self.unit_definitions);
        }
        if !self.type_definitions.is_empty() {
            write_type_definitions(&mut out, &self.type_definitions);
        }

        write_log_categories(&mut out, &self.log_categories, |d| d.to_owned());
        if let Some(d) = &self.default_experiment {
            write_default_experiment(&mut out, d);
        }

        if let Some(v) = &self.vendor_annotations {
            out.line(1, v.trim());
        }

        write_model_variables(&mut out, &self.model_variables);
        write_model_structure(&mut out, &self.model_structure);
        out.close(0, "fmiModelDescription");
        out.text
    }
}

/// `<LogCategories>` (nothing when there are none), each description through `describe`.
pub(crate) fn write_log_categories(
    out: &mut Out,
    categories: &[LogCategory],
    describe: impl Fn(&str) -> String,
) {
    if categories.is_empty() {
        return;
    }
    out.open(1, "LogCategories", &Attrs::new());
    for c in categories {
        let mut a = Attrs::new();
        let description = c.description.as_deref().map(&describe);
        a.s("name", &c.name).os("description", &description);
        out.empty(2, "Category", &a);
    }
    out.close(1, "LogCategories");
}

/// `<DefaultExperiment>`.
pub(crate) fn write_default_experiment(out: &mut Out, d: &DefaultExperiment) {
    let mut a = Attrs::new();
    a.f("startTime", d.start_time)
        .f("stopTime", d.stop_time)
        .f("tolerance", d.tolerance)
        .f("stepSize", d.step_size);
    out.empty(1, "DefaultExperiment", &a);
}

/// `<ModelExchange>`, with its source files.
fn write_model_exchange(out: &mut Out, me: &ModelExchange) {
    let mut a = Attrs::new();
    a.s("modelIdentifier", &me.model_identifier)
        .flag("needsExecutionTool", me.needs_execution_tool)
        .flag(
            "completedIntegratorStepNotNeeded",
            me.completed_integrator_step_not_needed,
        )
        .flag(
            "canBeInstantiatedOnlyOncePerProcess",
            me.can_be_instantiated_only_once_per_process,
        )
        .flag(
            "canNotUseMemoryManagementFunctions",
            me.can_not_use_memory_management_functions,
        )
        .flag("canGetAndSetFMUstate", me.can_get_and_set_fmu_state)
        .flag("canSerializeFMUstate", me.can_serialize_fmu_state)
        .flag(
            "providesDirectionalDerivative",
            me.provides_directional_derivative,
        );
    if me.source_files.is_empty() {
        out.empty(1, "ModelExchange", &a);
    } else {
        out.open(1, "ModelExchange", &a);
        source_files(out, 2, &me.source_files);
        out.close(1, "ModelExchange");
    }
}

/// `<CoSimulation>`, with its source files.
fn write_co_simulation(out: &mut Out, cs: &CoSimulation) {
    let mut a = Attrs::new();
    a.s("modelIdentifier", &cs.model_identifier)
        .flag("needsExecutionTool", cs.needs_execution_tool)
        .flag(
            "canHandleVariableCommunicationStepSize",
            cs.can_handle_variable_communication_step_size,
        )
        .flag("canInterpolateInputs", cs.can_interpolate_inputs);
    if cs.max_output_derivative_order != 0 {
        a.i(
            "maxOutputDerivativeOrder",
            Some(cs.max_output_derivative_order),
        );
    }
    a.flag("canRunAsynchronuously", cs.can_run_asynchronuously)
        .flag(
            "canBeInstantiatedOnlyOncePerProcess",
            cs.can_be_instantiated_only_once_per_process,
        )
        .flag(
            "canNotUseMemoryManagementFunctions",
            cs.can_not_use_memory_management_functions,
        )
        .flag("canGetAndSetFMUstate", cs.can_get_and_set_fmu_state)
        .flag("canSerializeFMUstate", cs.can_serialize_fmu_state)
        .flag(
            "providesDirectionalDerivative",
            cs.provides_directional_derivative,
        );
    if cs.source_files.is_empty() {
        out.empty(1, "CoSimulation", &a);
    } else {
        out.open(1, "CoSimulation", &a);
        source_files(out, 2, &cs.source_files);
        out.close(1, "CoSimulation");
    }
}

/// `<UnitDefinitions>` (non-empty).
pub(crate) fn write_unit_definitions(out: &mut Out, units: &[Unit]) {
    out.open(1, "UnitDefinitions", &Attrs::new());
    for u in units {
        let mut attrs = Attrs::new();
        attrs.s("name", &u.name);
        if u.base_unit.is_none() && u.display_units.is_empty() {
            out.empty(2, "Unit", &attrs);
            continue;
        }
        out.open(2, "Unit", &attrs);
        if let Some(b) = &u.base_unit {
            let mut a = Attrs::new();
            for (name, e) in [
                ("kg", b.kg),
                ("m", b.m),
                ("s", b.s),
                ("A", b.a),
                ("K", b.k),
                ("mol", b.mol),
                ("cd", b.cd),
                ("rad", b.rad),
            ] {
                if e != 0 {
                    a.i(name, Some(e));
                }
            }
            if b.factor != 1.0 {
                a.f("factor", Some(b.factor));
            }
            if b.offset != 0.0 {
                a.f("offset", Some(b.offset));
            }
            out.empty(3, "BaseUnit", &a);
        }
        for d in &u.display_units {
            let mut a = Attrs::new();
            a.s("name", &d.name);
            if d.factor != 1.0 {
                a.f("factor", Some(d.factor));
            }
            if d.offset != 0.0 {
                a.f("offset", Some(d.offset));
            }
            out.empty(3, "DisplayUnit", &a);
        }
        out.close(2, "Unit");
    }
    out.close(1, "UnitDefinitions");
}

/// `<TypeDefinitions>` (non-empty).
fn write_type_definitions(out: &mut Out, types: &[SimpleType]) {
    out.open(1, "TypeDefinitions", &Attrs::new());
    for t in types {
        let mut a = Attrs::new();
        a.s("name", &t.name).os("description", &t.description);
        out.open(2, "SimpleType", &a);
        let mut ta = Attrs::new();
        match &t.kind {
            SimpleTypeKind::Real(r) => {
                real_attrs(&mut ta, r);
                out.empty(3, "Real", &ta);
            }
            SimpleTypeKind::Integer(i) => {
                integer_attrs(&mut ta, i);
                out.empty(3, "Integer", &ta);
            }
            SimpleTypeKind::Boolean => out.empty(3, "Boolean", &ta),
            SimpleTypeKind::String => out.empty(3, "String", &ta),
            SimpleTypeKind::Enumeration { attributes, items } => {
                integer_attrs(&mut ta, attributes);
                out.open(3, "Enumeration", &ta);
                for item in items {
                    let mut ia = Attrs::new();
                    ia.s("name", &item.name)
                        .i("value", Some(item.value))
                        .os("description", &item.description);
                    out.empty(4, "Item", &ia);
                }
                out.close(3, "Enumeration");
            }
        }
        out.close(2, "SimpleType");
    }
    out.close(1, "TypeDefinitions");
}

/// `<ModelVariables>`, each variable preceded by a comment with its index.
fn write_model_variables(out: &mut Out, variables: &[ScalarVariable]) {
    out.open(1, "ModelVariables", &Attrs::new());
    for (i, v) in variables.iter().enumerate() {
        out.line(2, &format!("<!-- Index {} -->", i + 1));
        let mut a = Attrs::new();
        a.s("name", &v.name)
            .s("valueReference", &v.value_reference.to_string())
            .os("description", &v.description)
            .s("causality", v.causality.as_str())
            .s("variability", v.variability.as_str());
        if let Some(initial) = v.initial {
            a.s("initial", initial.as_str());
        }
        a.b(
            "canHandleMultipleSetPerTimeInstant",
            v.can_handle_multiple_set_per_time_instant,
        );
        out.open(2, "ScalarVariable", &a);
        let mut ta = Attrs::new();
        match &v.kind {
            VariableKind::Real(r) => {
                ta.os("declaredType", &r.declared_type);
                real_attrs(&mut ta, &r.attributes);
                ta.f("start", r.start)
                    .i("derivative", r.derivative)
                    .b("reinit", r.reinit);
            }
            VariableKind::Integer(i) => {
                ta.os("declaredType", &i.declared_type);
                integer_attrs(&mut ta, &i.attributes);
                ta.i("start", i.start);
            }
            VariableKind::Boolean(b) => {
                ta.os("declaredType", &b.declared_type).b("start", b.start);
            }
            VariableKind::String(s) => {
                ta.os("declaredType", &s.declared_type)
                    .os("start", &s.start);
            }
            VariableKind::Enumeration(e) => {
                ta.s("declaredType", &e.declared_type);
                integer_attrs(&mut ta, &e.attributes);
                ta.i("start", e.start);
            }
        }
        out.empty(3, v.kind.type_name(), &ta);
        out.close(2, "ScalarVariable");
    }
    out.close(1, "ModelVariables");
}

/// `<ModelStructure>`, empty when it has no Unknowns.
fn write_model_structure(out: &mut Out, ms: &ModelStructure) {
    if ms.outputs.is_empty() && ms.derivatives.is_empty() && ms.initial_unknowns.is_empty() {
        out.empty(1, "ModelStructure", &Attrs::new());
    } else {
        out.open(1, "ModelStructure", &Attrs::new());
        unknowns(out, "Outputs", &ms.outputs);
        unknowns(out, "Derivatives", &ms.derivatives);
        unknowns(out, "InitialUnknowns", &ms.initial_unknowns);
        out.close(1, "ModelStructure");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn doubles_round_trip_through_their_literal() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1e-300,
            1.7976931348623157e308,
            -2.5e-7,
            1e22,
        ] {
            let s = format_f64(v);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{s}");
        }
        assert_eq!(format_f64(f64::INFINITY), "INF");
        assert_eq!(format_f64(f64::NEG_INFINITY), "-INF");
        assert_eq!(format_f64(f64::NAN), "NaN");
    }
}
