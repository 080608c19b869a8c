//! The FMI 3.0 `modelDescription.xml` of a Co-Simulation FMU described for FMI 2.0: the same
//! variables under the same names and value references, so one binary serves both
//! standards and an SSP system wires either.
//!
//! What changes between the two documents:
//!
//! | FMI 2.0 | FMI 3.0 |
//! |---|---|
//! | `fmiVersion="2.0"`, `guid` | `fmiVersion="3.0"`, `instantiationToken` (the same text) |
//! | `<ScalarVariable …><Real …/></ScalarVariable>` | `<Float64 …/>` with the attributes of both |
//! | `<Integer>`, `<Boolean>`, `<String>` | `<Int32>`, `<Boolean>`, `<String>` (a `<String>` start is a `<Start value>` child) |
//! | `derivative`, `dependencies`, `index`: 1-based indices into ModelVariables | value references |
//! | `<Outputs>`, `<Derivatives>`, `<InitialUnknowns>` of `<Unknown>` | `<Output>`, `<ContinuousStateDerivative>`, `<InitialUnknown>` |
//! | `canGetAndSetFMUstate`, `canSerializeFMUstate`, `providesDirectionalDerivative` | `canGetAndSetFMUState`, `canSerializeFMUState`, `providesDirectionalDerivatives` |
//! | no independent variable required | exactly one: `time` (Float64, `causality="independent"`) at [`TIME_VALUE_REFERENCE`] |
//!
//! The Co-Simulation element also says `hasEventMode="false"` and
//! `canReturnEarlyAfterIntermediateUpdate="false"`: the FMU steps without event mode and
//! never returns early. Enumeration variables, type definitions of other base types than
//! Real and Model Exchange interfaces are refused by name.

use crate::types::*;
use crate::write::{
    real_attrs, write_default_experiment, write_log_categories, write_unit_definitions, Attrs, Out,
};

pub use ::fmi3::TIME_VALUE_REFERENCE;

impl ModelDescription {
    /// The FMI 3.0 Co-Simulation description of the same FMU (see the module docs); an
    /// error names what has no FMI 3.0 counterpart here.
    pub fn to_fmi3_xml_string(&self) -> Result<String, String> {
        let cs = self
            .co_simulation
            .as_ref()
            .ok_or("only Co-Simulation FMUs are described for FMI 3.0")?;
        if self.model_exchange.is_some() {
            return Err("a Model Exchange interface is not described for FMI 3.0".into());
        }
        if let Some(v) =
            (self.model_variables.iter()).find(|v| v.value_reference == TIME_VALUE_REFERENCE)
        {
            return Err(format!(
                "variable \"{}\" uses value reference {TIME_VALUE_REFERENCE}, which FMI 3.0 gives the independent variable time",
                v.name
            ));
        }
        let mut out = Out {
            text: String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"),
        };
        let root = self.root_attrs("3.0", "instantiationToken");
        out.open(0, "fmiModelDescription", &root);
        write_co_simulation(&mut out, cs);
        if !self.unit_definitions.is_empty() {
            write_unit_definitions(&mut out, &self.unit_definitions);
        }
        self.write_type_definitions(&mut out)?;
        // the plumbing's own categories describe their status by its FMI 2.0 name
        write_log_categories(&mut out, &self.log_categories, |d| {
            d.replace("fmi2", "fmi3")
        });
        if let Some(d) = &self.default_experiment {
            write_default_experiment(&mut out, d);
        }
        self.write_variables(&mut out)?;
        self.write_structure(&mut out)?;
        out.close(0, "fmiModelDescription");
        Ok(out.text)
    }

    /// The value reference of the variable at the 1-based `index`.
    fn vr_of(&self, index: u32, what: &str) -> Result<u32, String> {
        (index as usize)
            .checked_sub(1)
            .and_then(|i| self.model_variables.get(i))
            .map(|v| v.value_reference)
            .ok_or_else(|| format!("{what}: index {index} names no variable"))
    }

    fn write_type_definitions(&self, out: &mut Out) -> Result<(), String> {
        if self.type_definitions.is_empty() {
            return Ok(());
        }
        out.open(1, "TypeDefinitions", &Attrs::new());
        for t in &self.type_definitions {
            let SimpleTypeKind::Real(r) = &t.kind else {
                return Err(format!(
                    "type definition \"{}\": only Real types are described for FMI 3.0",
                    t.name
                ));
            };
            let mut a = Attrs::new();
            a.s("name", &t.name).os("description", &t.description);
            real_attrs(&mut a, r);
            out.empty(2, "Float64Type", &a);
        }
        out.close(1, "TypeDefinitions");
        Ok(())
    }

    fn write_variables(&self, out: &mut Out) -> Result<(), String> {
        out.open(1, "ModelVariables", &Attrs::new());
        let mut time = Attrs::new();
        time.s("name", "time")
            .s("valueReference", &TIME_VALUE_REFERENCE.to_string())
            .s("description", "Simulation time")
            .s("causality", "independent")
            .s("variability", "continuous");
        // a unit the description does not declare would fail validation
        if self.unit_definitions.iter().any(|u| u.name == "s") {
            time.s("unit", "s");
        }
        out.empty(2, "Float64", &time);
        for v in &self.model_variables {
            let mut a = Attrs::new();
            a.s("name", &v.name)
                .s("valueReference", &v.value_reference.to_string())
                .os("description", &v.description)
                .s("causality", v.causality.as_str())
                .s("variability", v.variability.as_str())
                .b(
                    "canHandleMultipleSetPerTimeInstant",
                    v.can_handle_multiple_set_per_time_instant,
                );
            if let Some(i) = v.initial {
                a.s("initial", i.as_str());
            }
            let element = match &v.kind {
                VariableKind::Real(r) => {
                    a.os("declaredType", &r.declared_type);
                    real_attrs(&mut a, &r.attributes);
                    a.f("start", r.start);
                    if let Some(d) = r.derivative {
                        let vr = self.vr_of(d, &format!("variable \"{}\" derivative", v.name))?;
                        a.s("derivative", &vr.to_string());
                    }
                    a.b("reinit", r.reinit);
                    "Float64"
                }
                VariableKind::Integer(i) => {
                    a.os("declaredType", &i.declared_type);
                    a.os("quantity", &i.attributes.quantity)
                        .i("min", i.attributes.min)
                        .i("max", i.attributes.max)
                        .i("start", i.start);
                    "Int32"
                }
                VariableKind::Boolean(b) => {
                    a.os("declaredType", &b.declared_type).b("start", b.start);
                    "Boolean"
                }
                VariableKind::String(s) => {
                    a.os("declaredType", &s.declared_type);
                    if let Some(start) = &s.start {
                        out.open(2, "String", &a);
                        let mut value = Attrs::new();
                        value.s("value", start);
                        out.empty(3, "Start", &value);
                        out.close(2, "String");
                        continue;
                    }
                    "String"
                }
                VariableKind::Enumeration(_) => {
                    return Err(format!(
                        "variable \"{}\": Enumeration variables are not described for FMI 3.0",
                        v.name
                    ))
                }
            };
            out.empty(2, element, &a);
        }
        out.close(1, "ModelVariables");
        Ok(())
    }

    fn write_structure(&self, out: &mut Out) -> Result<(), String> {
        let s = &self.model_structure;
        out.open(1, "ModelStructure", &Attrs::new());
        for (element, list) in [
            ("Output", &s.outputs),
            ("ContinuousStateDerivative", &s.derivatives),
            ("InitialUnknown", &s.initial_unknowns),
        ] {
            for u in list {
                let mut a = Attrs::new();
                a.s("valueReference", &self.vr_of(u.index, element)?.to_string());
                if let Some(d) = &u.dependencies {
                    let vrs = (d.iter())
                        .map(|&i| self.vr_of(i, element).map(|vr| vr.to_string()))
                        .collect::<Result<Vec<_>, _>>()?;
                    a.s("dependencies", &vrs.join(" "));
                }
                if let Some(k) = &u.dependencies_kind {
                    let k: Vec<&str> = k.iter().map(|k| k.as_str()).collect();
                    a.s("dependenciesKind", &k.join(" "));
                }
                out.empty(2, element, &a);
            }
        }
        out.close(1, "ModelStructure");
        Ok(())
    }
}

/// `<CoSimulation>` of FMI 3.0 (see the module docs for the flags).
fn write_co_simulation(out: &mut Out, cs: &CoSimulation) {
    let mut a = Attrs::new();
    a.s("modelIdentifier", &cs.model_identifier)
        .flag("needsExecutionTool", cs.needs_execution_tool)
        .flag(
            "canBeInstantiatedOnlyOncePerProcess",
            cs.can_be_instantiated_only_once_per_process,
        )
        .flag("canGetAndSetFMUState", cs.can_get_and_set_fmu_state)
        .flag("canSerializeFMUState", cs.can_serialize_fmu_state)
        .s(
            "providesDirectionalDerivatives",
            if cs.provides_directional_derivative {
                "true"
            } else {
                "false"
            },
        )
        .flag(
            "canHandleVariableCommunicationStepSize",
            cs.can_handle_variable_communication_step_size,
        );
    if cs.max_output_derivative_order != 0 {
        a.i(
            "maxOutputDerivativeOrder",
            Some(cs.max_output_derivative_order),
        );
    }
    a.s("hasEventMode", "false")
        .s("canReturnEarlyAfterIntermediateUpdate", "false");
    out.empty(1, "CoSimulation", &a);
}

#[cfg(test)]
mod tests {
    use super::*;

    const FMI2: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="m" guid="{g}">
  <CoSimulation modelIdentifier="m" canGetAndSetFMUstate="true"/>
  <UnitDefinitions><Unit name="m"/><Unit name="s"/></UnitDefinitions>
  <ModelVariables>
    <ScalarVariable name="u" valueReference="7" causality="input" variability="continuous"><Real start="0" unit="m"/></ScalarVariable>
    <ScalarVariable name="x" valueReference="3" causality="output" variability="continuous" initial="exact"><Real start="1"/></ScalarVariable>
    <ScalarVariable name="dx" valueReference="5" causality="local" variability="continuous"><Real derivative="2"/></ScalarVariable>
    <ScalarVariable name="n" valueReference="9" causality="parameter" variability="fixed"><Integer start="4"/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="2" dependencies="1" dependenciesKind="dependent"/></Outputs>
    <Derivatives><Unknown index="3" dependencies="1 2"/></Derivatives>
  </ModelStructure>
</fmiModelDescription>"#;

    #[test]
    fn indices_become_value_references_and_time_is_declared() {
        let md = ModelDescription::parse(FMI2, "m.xml").unwrap();
        let xml = md.to_fmi3_xml_string().unwrap();
        for want in [
            r#"fmiVersion="3.0" modelName="m" instantiationToken="{g}""#,
            r#"canGetAndSetFMUState="true""#,
            r#"hasEventMode="false" canReturnEarlyAfterIntermediateUpdate="false""#,
            r#"<Float64 name="time" valueReference="2147483647" description="Simulation time" causality="independent" variability="continuous" unit="s"/>"#,
            r#"<Float64 name="u" valueReference="7" causality="input" variability="continuous" unit="m" start="0.0"/>"#,
            r#"<Float64 name="dx" valueReference="5" causality="local" variability="continuous" derivative="3"/>"#,
            r#"<Int32 name="n" valueReference="9" causality="parameter" variability="fixed" start="4"/>"#,
            r#"<Output valueReference="3" dependencies="7" dependenciesKind="dependent"/>"#,
            r#"<ContinuousStateDerivative valueReference="5" dependencies="7 3"/>"#,
        ] {
            assert!(xml.contains(want), "{want}\nnot in\n{xml}");
        }
    }

    #[test]
    fn what_fmi3_cannot_say_is_refused_by_name() {
        let taken = FMI2.replace(r#"valueReference="9""#, r#"valueReference="2147483647""#);
        let md = ModelDescription::parse(&taken, "m.xml").unwrap();
        let e = md.to_fmi3_xml_string().unwrap_err();
        assert!(
            e.contains("variable \"n\" uses value reference 2147483647"),
            "{e}"
        );
        let mut md = ModelDescription::parse(FMI2, "m.xml").unwrap();
        md.co_simulation = None;
        assert!(md
            .to_fmi3_xml_string()
            .unwrap_err()
            .contains("only Co-Simulation"));
    }
}
