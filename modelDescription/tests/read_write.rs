//! Reading real-world descriptions, round trips, and read errors.

use model_description::*;
use std::path::PathBuf;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn read(name: &str) -> ModelDescription {
    ModelDescription::from_path(data(name)).unwrap_or_else(|e| panic!("{e}"))
}

const SAMPLES: [&str; 3] = [
    "reference_fmus_bouncing_ball.xml",
    "dymola_coupled_clutches.xml",
    "openmodelica_tank.xml",
];

#[test]
fn reference_fmus_bouncing_ball() {
    let md = read("reference_fmus_bouncing_ball.xml");
    assert_eq!(md.model_name, "BouncingBall");
    assert_eq!(md.guid, "{1AE5E10D-9521-4DE3-80B9-D0EAAA7D5AF1}");
    assert_eq!(md.number_of_event_indicators, Some(1));
    let cs = md.co_simulation.as_ref().unwrap();
    assert_eq!(cs.model_identifier, "BouncingBall");
    assert!(cs.can_handle_variable_communication_step_size);
    assert!(cs.can_get_and_set_fmu_state && cs.can_serialize_fmu_state);
    assert!(!cs.can_interpolate_inputs);
    assert_eq!(cs.source_files, ["all.c"]);
    assert!(md.model_exchange.is_some());
    assert_eq!(md.unit_definitions.len(), 3);
    assert_eq!(md.unit_definitions[2].base_unit.as_ref().unwrap().s, -2);
    assert_eq!(md.type_definitions.len(), 3);
    assert_eq!(md.log_categories[1].name, "logStatusError");
    let de = md.default_experiment.as_ref().unwrap();
    assert_eq!(
        (de.start_time, de.stop_time, de.step_size, de.tolerance),
        (Some(0.0), Some(3.0), Some(0.01), None)
    );
    assert_eq!(md.model_variables.len(), 8);
    let time = &md.model_variables[0];
    assert_eq!(time.causality, Causality::Independent);
    assert_eq!(time.initial_or_default(), None);
    let h = md.variable("h").unwrap();
    assert_eq!(h.value_reference, 1);
    assert_eq!(h.real_start(), Some(1.0));
    assert_eq!(h.declared_type(), Some("Position"));
    let der_h = md.variable("der(h)").unwrap();
    match &der_h.kind {
        VariableKind::Real(r) => assert_eq!(r.derivative, Some(2)),
        other => panic!("{other:?}"),
    }
    let e = md.variable("e").unwrap();
    match &e.kind {
        VariableKind::Real(r) => {
            assert_eq!((r.attributes.min, r.attributes.max), (Some(0.5), Some(1.0)));
        }
        other => panic!("{other:?}"),
    }
    // causality absent → local; initial absent → default exact for a constant
    let v_min = md.variable("v_min").unwrap();
    assert_eq!(v_min.causality, Causality::Local);
    assert_eq!(v_min.initial, None);
    assert_eq!(v_min.initial_or_default(), Some(Initial::Exact));
    let outputs: Vec<u32> = md.model_structure.outputs.iter().map(|u| u.index).collect();
    assert_eq!(outputs, [2, 4]);
    assert_eq!(md.index_of("der(v)"), Some(5));
    assert_eq!(md.variable_at_index(5).unwrap().name, "der(v)");
    assert_eq!(md.variable_at_index(0), None);
    assert_eq!(md.validate(), Vec::<String>::new());
}

#[test]
fn dymola_description_with_vendor_annotations_aliases_and_unknown_attributes() {
    let md = read("dymola_coupled_clutches.xml");
    assert_eq!(
        md.variable_naming_convention,
        VariableNamingConvention::Structured
    );
    assert!(md.generation_tool.as_deref().unwrap().starts_with("Dymola"));
    let cs = md.co_simulation.as_ref().unwrap();
    assert_eq!(cs.max_output_derivative_order, 1);
    assert!(cs.provides_directional_derivative);
    let vendor = md.vendor_annotations.as_deref().unwrap();
    assert!(vendor.starts_with("<VendorAnnotations>"), "{vendor}");
    assert!(vendor.ends_with("</VendorAnnotations>"), "{vendor}");
    assert!(vendor.contains("<Flag name=\"Advanced.Translation.SparseActivate\" value=\"true\"/>"));
    assert!(vendor.contains("<Tool name=\"Dymola.Experiment\">"));

    let rad = md.unit_definition("rad").unwrap();
    assert_eq!(rad.display_units[0].name, "deg");
    assert_eq!(rad.display_units[0].factor, 57.29577951308232);
    assert_eq!(
        md.unit_definition("degC")
            .unwrap()
            .base_unit
            .as_ref()
            .unwrap()
            .offset,
        273.15
    );
    match &md
        .type_definition("Modelica.Blocks.Types.Init")
        .unwrap()
        .kind
    {
        SimpleTypeKind::Enumeration { items, .. } => {
            assert_eq!(items.len(), 4);
            assert_eq!(items[2].name, "InitialState");
            assert_eq!(items[2].value, 3);
        }
        other => panic!("{other:?}"),
    }
    // variable with <Annotations> inside
    assert_eq!(md.variable("T2").unwrap().real_start(), Some(0.4));
    // alias set sharing a Real value reference
    assert_eq!(
        md.variable("J1.phi").unwrap().value_reference,
        md.variable("J1.flange_a.phi").unwrap().value_reference
    );
    match &md.variable("sin1.nperiod").unwrap().kind {
        VariableKind::Integer(i) => assert_eq!((i.start, i.attributes.min), (Some(-1), Some(-1))),
        other => panic!("{other:?}"),
    }
    match &md.variable("clutch1.locked").unwrap().kind {
        VariableKind::Boolean(b) => assert_eq!(b.start, None),
        other => panic!("{other:?}"),
    }
    match &md.variable("J1.initType").unwrap().kind {
        VariableKind::Enumeration(e) => {
            assert_eq!(e.declared_type, "Modelica.Blocks.Types.Init");
            assert_eq!(e.start, Some(3));
        }
        other => panic!("{other:?}"),
    }
    match &md.variable("author").unwrap().kind {
        VariableKind::String(s) => {
            assert_eq!(
                s.start.as_deref(),
                Some("Modelica & friends <modelica.org>")
            )
        }
        other => panic!("{other:?}"),
    }
    let outputs = &md.model_structure.outputs;
    assert_eq!(outputs[0].dependencies, Some(vec![]));
    assert_eq!(outputs[0].dependencies_kind, Some(vec![]));
    let iu = &md.model_structure.initial_unknowns[2];
    assert_eq!(iu.dependencies, Some(vec![1, 2]));
    assert_eq!(
        iu.dependencies_kind,
        Some(vec![DependencyKind::Dependent, DependencyKind::Tunable])
    );
    assert_eq!(md.validate(), Vec::<String>::new());
}

#[test]
fn openmodelica_description_reads_and_its_missing_units_are_reported() {
    let md = read("openmodelica_tank.xml");
    assert_eq!(md.log_categories.len(), 4);
    assert_eq!(
        md.default_experiment.as_ref().unwrap().tolerance,
        Some(1e-6)
    );
    let vendor = md.vendor_annotations.as_deref().unwrap();
    assert!(vendor.contains("<Nested deeper=\"yes\">text &amp; more</Nested>"));
    assert_eq!(md.variable("qIn").unwrap().causality, Causality::Input);
    assert_eq!(
        md.variable("qIn").unwrap().initial_or_default(),
        Some(Initial::Exact)
    );
    let problems = md.validate();
    assert_eq!(
        problems,
        [
            "Variable \"h\" (index 1, line 42): the unit \"m\" is not defined.",
            "Variable \"A\" (index 5, line 79): the unit \"m2\" is not defined.",
        ]
    );
}

#[test]
fn round_trip_is_lossless() {
    for name in SAMPLES {
        let md = read(name);
        let xml = md.to_xml_string();
        let again = ModelDescription::parse(&xml, "written")
            .unwrap_or_else(|e| panic!("{name}: {e}\n{xml}"));
        assert_eq!(again, md, "{name}");
        assert_eq!(
            again.to_xml_string(),
            xml,
            "{name}: writing is not idempotent"
        );
    }
}

#[test]
fn written_document_is_plain_fmi_xml() {
    let md = read("dymola_coupled_clutches.xml");
    let xml = md.to_xml_string();
    assert!(xml.starts_with(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription fmiVersion=\"2.0\""
    ));
    assert!(xml.contains("start=\"Modelica &amp; friends &lt;modelica.org&gt;\""));
    // schema order: CoSimulation, UnitDefinitions, TypeDefinitions, DefaultExperiment,
    // VendorAnnotations, ModelVariables, ModelStructure
    let order = [
        "<CoSimulation",
        "<UnitDefinitions>",
        "<TypeDefinitions>",
        "<DefaultExperiment",
        "<VendorAnnotations>",
        "<ModelVariables>",
        "<ModelStructure>",
    ];
    let positions: Vec<usize> = order.iter().map(|t| xml.find(t).unwrap()).collect();
    assert!(positions.windows(2).all(|w| w[0] < w[1]), "{positions:?}");
    // unknown attributes are not invented back
    assert!(!xml.contains("dymolaExtensionFlag"));
}

#[test]
fn round_trip_of_special_values() {
    let mut md = read("reference_fmus_bouncing_ball.xml");
    if let VariableKind::Real(r) = &mut md.model_variables[6].kind {
        r.attributes.max = Some(f64::INFINITY);
        r.attributes.min = Some(f64::NEG_INFINITY);
        r.start = Some(1.0 / 3.0);
    }
    md.description = Some("quotes \" and 'apostrophes' and \u{e9}\u{2013}\u{1F682}".into());
    let again: ModelDescription = md.to_xml_string().parse().unwrap();
    assert_eq!(again, md);
}

#[test]
fn from_str_trait_and_byte_order_mark() {
    let text = std::fs::read_to_string(data("openmodelica_tank.xml")).unwrap();
    let with_bom = format!("\u{feff}{text}");
    let md: ModelDescription = with_bom.parse().unwrap();
    assert_eq!(md.model_name, "Tank");
}

fn error_of(xml: &str) -> String {
    ModelDescription::parse(xml, "Sample.fmu/modelDescription.xml")
        .unwrap_err()
        .to_string()
}

const MINIMAL_HEAD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="{g}">
  <CoSimulation modelIdentifier="m"/>
  <ModelVariables>
"#;
const MINIMAL_TAIL: &str = r#"  </ModelVariables>
  <ModelStructure/>
</fmiModelDescription>
"#;

fn with_variables(variables: &str) -> String {
    format!("{MINIMAL_HEAD}{variables}{MINIMAL_TAIL}")
}

#[test]
fn minimal_description_reads() {
    let md = ModelDescription::parse(&with_variables(""), "m").unwrap();
    assert!(md.model_variables.is_empty());
    assert_eq!(md.validate(), Vec::<String>::new());
}

#[test]
fn malformed_xml_is_reported_with_origin_and_line() {
    let xml = with_variables("    <ScalarVariable name=\"x\" valueReference=\"0\">\n      <Real>\n    </ScalarVariable>\n");
    let e = error_of(&xml);
    assert!(
        e.starts_with("Sample.fmu/modelDescription.xml: malformed XML at line 7"),
        "{e}"
    );
}

#[test]
fn truncated_document_is_reported() {
    let xml = with_variables("");
    let e = error_of(&xml[..xml.len() / 2]);
    assert!(e.starts_with("Sample.fmu/modelDescription.xml: "), "{e}");
    assert!(
        e.contains("ends inside an element") || e.contains("malformed XML"),
        "{e}"
    );
}

#[test]
fn wrong_root_and_version_are_reported() {
    let e = error_of("<fmiModelDescriptio/>");
    assert!(
        e.contains("the root element is <fmiModelDescriptio>"),
        "{e}"
    );
    let e = error_of(&with_variables("").replace("fmiVersion=\"2.0\"", "fmiVersion=\"4.0\""));
    assert!(e.contains("fmiVersion=\"4.0\" is not supported"), "{e}");
    // an FMI 3.0 document is read by the FMI 3.0 reader, which wants its own attributes
    let e = error_of(&with_variables("").replace("fmiVersion=\"2.0\"", "fmiVersion=\"3.0\""));
    assert!(e.contains("has no instantiationToken"), "{e}");
    let e = error_of("");
    assert!(e.contains("empty document"), "{e}");
}

#[test]
fn bad_values_name_the_variable_and_attribute() {
    let cases = [
        (
            r#"<ScalarVariable name="x" valueReference="a"><Real/></ScalarVariable>"#,
            r#"<ScalarVariable> 1 "x": valueReference="a" is not an unsigned 32-bit integer"#,
        ),
        (
            r#"<ScalarVariable name="x" valueReference="0" causality="inputs"><Real/></ScalarVariable>"#,
            r#"<ScalarVariable> 1 "x": causality "inputs" is not one of parameter, calculatedParameter, input, output, local, independent"#,
        ),
        (
            r#"<ScalarVariable name="x" valueReference="0"><Real start="1,5"/></ScalarVariable>"#,
            r#"<ScalarVariable> 1 "x"/Real: start="1,5" is not a number"#,
        ),
        (
            r#"<ScalarVariable name="x" valueReference="0"><Boolean start="yes"/></ScalarVariable>"#,
            r#"<ScalarVariable> 1 "x"/Boolean: start="yes" is not a boolean"#,
        ),
        (
            r#"<ScalarVariable name="x" valueReference="0"></ScalarVariable>"#,
            r#"<ScalarVariable> 1 "x": has no type element"#,
        ),
        (
            r#"<ScalarVariable name="x" valueReference="0"><Real/><Integer/></ScalarVariable>"#,
            r#"<ScalarVariable> 1 "x": has more than one type element (<Real>, <Integer>)"#,
        ),
        (
            r#"<ScalarVariable valueReference="0"><Real/></ScalarVariable>"#,
            r#"<ScalarVariable> 1: the required attribute name is missing"#,
        ),
        (
            r#"<ScalarVariable name="e" valueReference="0"><Enumeration/></ScalarVariable>"#,
            r#"<ScalarVariable> 1 "e"/Enumeration: the required attribute declaredType is missing"#,
        ),
    ];
    for (variable, expected) in cases {
        let e = error_of(&with_variables(variable));
        assert!(
            e.starts_with("Sample.fmu/modelDescription.xml: ") && e.contains(expected),
            "{e}\nexpected: {expected}"
        );
    }
}

#[test]
fn missing_required_elements_are_reported() {
    let e = error_of(
        r#"<fmiModelDescription fmiVersion="2.0" modelName="M" guid="g"><ModelStructure/></fmiModelDescription>"#,
    );
    assert!(e.contains("<ModelVariables> is missing"), "{e}");
    let e = error_of(
        r#"<fmiModelDescription fmiVersion="2.0" guid="g"><ModelVariables/><ModelStructure/></fmiModelDescription>"#,
    );
    assert!(
        e.contains("the required attribute modelName is missing"),
        "{e}"
    );
    let e = error_of(
        &with_variables("")
            .replace("<ModelStructure/>\n", "")
            .replace("<ModelStructure>", ""),
    );
    assert!(e.contains("<ModelStructure> is missing"), "{e}");
}

#[test]
fn from_path_names_the_missing_file() {
    let e = ModelDescription::from_path("/nonexistent/dir/modelDescription.xml").unwrap_err();
    assert_eq!(e.origin(), "/nonexistent/dir/modelDescription.xml");
    assert!(e.to_string().contains("cannot read the file"), "{e}");
}

#[test]
fn messages_name_the_line_of_the_element() {
    let xml = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="m" guid="{1}">
  <CoSimulation modelIdentifier="m"/>
  <ModelVariables>
    <ScalarVariable name="a" valueReference="0" causality="output"><Real/></ScalarVariable>
    <ScalarVariable name="b" valueReference="1" causality="input" variability="sometimes">
      <Real start="0"/>
    </ScalarVariable>
  </ModelVariables>
  <ModelStructure/>
</fmiModelDescription>"#;
    // a value the conversion refuses: the line of its <ScalarVariable>
    let err = xml.parse::<ModelDescription>().unwrap_err().to_string();
    assert!(err.contains("line 6: <ScalarVariable> 2 \"b\""), "{err}");

    // rules the validation checks: the lines of the variable, the unknown and the
    // ModelStructure element
    let xml = xml.replace(" variability=\"sometimes\"", "").replace(
        "<ModelStructure/>",
        "<ModelStructure>\n    <Outputs><Unknown index=\"7\"/></Outputs>\n  </ModelStructure>",
    );
    let xml = xml
        .replace(
            "guid=\"{1}\"",
            "guid=\"{1}\" variableNamingConvention=\"structured\"",
        )
        .replace("name=\"a\"", "name=\"a b\"");
    let md: ModelDescription = xml.parse().expect("parses");
    let problems = md.validate().join("\n");
    assert!(
        problems.contains("Variable \"a b\" (index 1, line 5)"),
        "{problems}"
    );
    assert!(
        problems.contains("ModelStructure/Outputs/Unknown 1 (index=7, line 11)"),
        "{problems}"
    );
    // built in code, a description has no lines and its messages none either
    let mut built = md.clone();
    built.source_lines = SourceLines::default();
    assert_eq!(built, md);
    assert!(!built.validate().join("\n").contains("line "));
}
