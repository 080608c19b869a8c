//! Each validation rule on a description that breaks exactly that rule.

use model_description::*;

fn valid() -> ModelDescription {
    ModelDescriptionBuilder::new("Osc", "{7d3f0a4e-1c1b-4b7e-9a55-0d6c1f2e3a4b}", "osc")
        .default_experiment(DefaultExperiment {
            start_time: Some(0.0),
            stop_time: Some(10.0),
            tolerance: None,
            step_size: Some(0.01),
        })
        .real(RealBuilder::parameter("k", 0, 4.0).unit("N/m"))
        .real(RealBuilder::input("F", 1, 0.0).unit("N"))
        .real(RealBuilder::output("x", 2).unit("m"))
        .real(RealBuilder::output("v", 3).unit("m/s"))
        .real(RealBuilder::new("a", 4).unit("m/s2"))
        .build()
        .unwrap()
}

fn problems_of(md: &ModelDescription) -> Vec<String> {
    md.validate()
}

fn assert_single(md: &ModelDescription, expected: &str) {
    let p = problems_of(md);
    assert!(
        p.len() == 1 && p[0].contains(expected),
        "expected one problem containing {expected:?}, got {p:#?}"
    );
}

fn real_mut<'a>(md: &'a mut ModelDescription, name: &str) -> &'a mut RealVariable {
    let v = md
        .model_variables
        .iter_mut()
        .find(|v| v.name == name)
        .unwrap();
    match &mut v.kind {
        VariableKind::Real(r) => r,
        _ => panic!("{name} is not Real"),
    }
}

fn var_mut<'a>(md: &'a mut ModelDescription, name: &str) -> &'a mut ScalarVariable {
    md.model_variables
        .iter_mut()
        .find(|v| v.name == name)
        .unwrap()
}

#[test]
fn the_base_description_is_valid() {
    assert_eq!(problems_of(&valid()), Vec::<String>::new());
}

#[test]
fn input_without_start() {
    let mut md = valid();
    real_mut(&mut md, "F").start = None;
    assert_single(&md, "Variable \"F\" (index 2): has no start value.");
}

#[test]
fn parameter_without_start() {
    let mut md = valid();
    real_mut(&mut md, "k").start = None;
    assert_single(&md, "Variable \"k\" (index 1): has no start value.");
}

#[test]
fn illegal_causality_variability_combinations() {
    let mut md = valid();
    var_mut(&mut md, "k").variability = Variability::Continuous;
    assert_single(
        &md,
        "the combination causality=\"parameter\", variability=\"continuous\" is not allowed",
    );

    let mut md = valid();
    var_mut(&mut md, "F").initial = Some(Initial::Approx);
    assert_single(
        &md,
        "Variable \"F\" (index 2): the combination causality=\"input\", variability=\"continuous\" and initial=\"approx\" is not allowed",
    );

    let mut md = valid();
    var_mut(&mut md, "a").variability = Variability::Constant;
    var_mut(&mut md, "a").initial = Some(Initial::Calculated);
    assert_single(
        &md,
        "causality=\"local\", variability=\"constant\" and initial=\"calculated\"",
    );
}

#[test]
fn calculated_variable_with_start() {
    let mut md = valid();
    real_mut(&mut md, "x").start = Some(1.0);
    assert_single(
        &md,
        "Variable \"x\" (index 3): has initial=\"calculated\" but provides a start value.",
    );
}

#[test]
fn non_real_continuous_variable() {
    let mut md = valid();
    md.model_variables.push(ScalarVariable {
        name: "n".into(),
        value_reference: 0,
        description: None,
        causality: Causality::Local,
        variability: Variability::Continuous,
        initial: None,
        can_handle_multiple_set_per_time_instant: None,
        kind: VariableKind::Integer(IntegerVariable::default()),
    });
    assert_single(&md, "Variable \"n\" (index 6): is of type Integer and must have variability other than \"continuous\".");
}

#[test]
fn duplicate_names() {
    let mut md = valid();
    var_mut(&mut md, "a").name = "x".into();
    assert_single(
        &md,
        "Variable \"x\" (index 5): the name is not unique (also used by index 3).",
    );
}

#[test]
fn shared_value_references_follow_the_alias_rules() {
    // an alias without start value is fine
    let mut md = valid();
    md.model_variables[4].value_reference = 2;
    assert_eq!(problems_of(&md), Vec::<String>::new());
    // two parameters with start values on one reference are not
    let mut md = valid();
    md.model_variables[1] = RealBuilder::parameter("k2", 0, 1.0).into_variable();
    md.generate_model_structure();
    let p = problems_of(&md);
    assert_eq!(p.len(), 2, "{p:#?}");
    assert!(
        p[0].contains(
            "The Real value reference 0 is shared by \"k\", \"k2\" which all have a start value"
        ),
        "{p:#?}"
    );
    assert!(
        p[1].contains("at most one variable of an alias set may be an input or a parameter"),
        "{p:#?}"
    );
    // different base types never clash
    let mut md = valid();
    md.model_variables.push(ScalarVariable {
        name: "flag".into(),
        value_reference: 0,
        description: None,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: None,
        can_handle_multiple_set_per_time_instant: None,
        kind: VariableKind::Boolean(BooleanVariable {
            declared_type: None,
            start: Some(true),
        }),
    });
    assert_eq!(problems_of(&md), Vec::<String>::new());
}

#[test]
fn undefined_units_and_types() {
    let mut md = valid();
    md.unit_definitions.retain(|u| u.name != "m/s");
    assert_single(
        &md,
        "Variable \"v\" (index 4): the unit \"m/s\" is not defined.",
    );

    let mut md = valid();
    real_mut(&mut md, "x").attributes.display_unit = Some("mm".into());
    assert_single(&md, "the display unit \"mm\" is not defined for unit \"m\"");

    let mut md = valid();
    real_mut(&mut md, "x").declared_type = Some("Length".into());
    assert_single(
        &md,
        "declaredType=\"Length\" is not defined in <TypeDefinitions>.",
    );
}

#[test]
fn ranges() {
    let mut md = valid();
    real_mut(&mut md, "k").attributes.min = Some(5.0);
    assert_single(&md, "Variable \"k\" (index 1): start=4 is less than min=5.");
    let mut md = valid();
    real_mut(&mut md, "k").attributes.min = Some(1.0);
    real_mut(&mut md, "k").attributes.max = Some(0.0);
    let p = problems_of(&md);
    assert!(
        p.iter().any(|p| p.contains("min=1 is greater than max=0")),
        "{p:#?}"
    );
}

#[test]
fn outputs_must_list_exactly_the_outputs() {
    let mut md = valid();
    md.model_structure.outputs.remove(0);
    assert_single(
        &md,
        "ModelStructure/Outputs must have exactly one entry for each variable with causality=\"output\". Missing: x.",
    );

    let mut md = valid();
    md.model_structure.outputs.push(Unknown::new(5));
    assert_single(&md, "Not outputs: a.");
}

#[test]
fn outputs_are_one_based_and_ascending() {
    let mut md = valid();
    md.model_structure.outputs[0].index = 0;
    let p = problems_of(&md);
    assert!(p.iter().any(|p| p.contains("ModelStructure/Outputs/Unknown 1 (index=0): the index is not the 1-based position of a variable (1 to 5).")), "{p:#?}");

    let mut md = valid();
    md.model_structure.outputs.swap(0, 1);
    md.model_structure.initial_unknowns.swap(0, 1);
    let p = problems_of(&md);
    assert_eq!(p.len(), 2, "{p:#?}");
    assert!(
        p.iter().all(|p| p.contains("ascending order of index")),
        "{p:#?}"
    );
}

#[test]
fn dependencies_must_match_their_kinds_and_exist() {
    let mut md = valid();
    md.model_structure.outputs[0].dependencies = Some(vec![2, 9]);
    md.model_structure.outputs[0].dependencies_kind = Some(vec![DependencyKind::Dependent]);
    let p = problems_of(&md);
    assert_eq!(p.len(), 2, "{p:#?}");
    assert!(
        p[0].contains("dependency 9 is not the index of a variable"),
        "{p:#?}"
    );
    assert!(
        p[1].contains("dependencies has 2 entries but dependenciesKind has 1"),
        "{p:#?}"
    );
}

#[test]
fn initial_unknowns_rules() {
    let mut md = valid();
    md.model_structure.initial_unknowns.pop();
    assert_single(
        &md,
        "ModelStructure/InitialUnknowns does not contain the expected set of variables. Expected {v, x} but was {x}.",
    );
    // an output with initial="exact" is not an initial unknown
    let mut md = valid();
    var_mut(&mut md, "x").initial = Some(Initial::Exact);
    real_mut(&mut md, "x").start = Some(0.0);
    assert_single(&md, "Expected {v} but was {v, x}.");
    // states and derivatives with initial calculated/approx are initial unknowns
    let mut md = valid();
    real_mut(&mut md, "a").derivative = Some(4);
    md.generate_model_structure();
    assert_eq!(problems_of(&md), Vec::<String>::new());
    let iu: Vec<u32> = md
        .model_structure
        .initial_unknowns
        .iter()
        .map(|u| u.index)
        .collect();
    assert_eq!(iu, [3, 4, 5]);
    assert_eq!(md.model_structure.derivatives, [Unknown::new(5)]);
}

#[test]
fn derivative_attribute_must_refer_to_a_real_variable() {
    let mut md = valid();
    real_mut(&mut md, "a").derivative = Some(42);
    let p = problems_of(&md);
    assert!(
        p.iter()
            .any(|p| p.contains("derivative=\"42\" is not the index of a variable (1 to 5)")),
        "{p:#?}"
    );
}

#[test]
fn derivatives_entries_need_the_derivative_attribute() {
    let mut md = valid();
    md.model_structure.derivatives.push(Unknown::new(5));
    assert_single(&md, "ModelStructure/Derivatives/Unknown 1 refers to variable \"a\" (index 5), which has no derivative attribute.");
}

#[test]
fn structured_names_are_checked() {
    let mut md = valid();
    var_mut(&mut md, "a").name = "a b".into();
    assert_single(
        &md,
        "Variable \"a b\" (index 5): not a legal name for the naming convention \"structured\"",
    );
    md.variable_naming_convention = VariableNamingConvention::Flat;
    assert_eq!(problems_of(&md), Vec::<String>::new());
    var_mut(&mut md, "a b").name = "a\tb".into();
    assert_single(&md, "the name contains a tab character.");
}

#[test]
fn header_rules() {
    let mut md = valid();
    md.co_simulation.as_mut().unwrap().model_identifier = "my-fmu".into();
    assert_single(
        &md,
        "<CoSimulation> modelIdentifier=\"my-fmu\" is not a valid C identifier.",
    );
    let mut md = valid();
    md.co_simulation = None;
    assert_single(&md, "neither a <ModelExchange> nor a <CoSimulation>");
    let mut md = valid();
    md.default_experiment.as_mut().unwrap().stop_time = Some(-1.0);
    assert_single(&md, "stopTime=-1 is not greater than startTime=0");
    let mut md = valid();
    md.default_experiment.as_mut().unwrap().step_size = Some(0.0);
    assert_single(&md, "stepSize=0 must be positive");
}

#[test]
fn independent_variable_rules() {
    let mut md = valid();
    md.model_variables.push(
        RealBuilder::new("time", 9)
            .causality(Causality::Independent)
            .into_variable(),
    );
    assert_eq!(problems_of(&md), Vec::<String>::new());
    real_mut(&mut md, "time").start = Some(0.0);
    let p = problems_of(&md);
    assert!(
        p.iter()
            .any(|p| p.contains("has causality=\"independent\" but provides a start value")),
        "{p:#?}"
    );
    let mut md = valid();
    for name in ["t1", "t2"] {
        md.model_variables.push(
            RealBuilder::new(name, 9)
                .causality(Causality::Independent)
                .into_variable(),
        );
    }
    let p = problems_of(&md);
    assert!(
        p.iter().any(|p| p.contains(
            "At most one variable may have causality=\"independent\", found \"t1\", \"t2\""
        )),
        "{p:#?}"
    );
}

#[test]
fn builder_output_round_trips_and_validates() {
    let md = valid();
    let xml = md.to_xml_string();
    let again = ModelDescription::parse(&xml, "built").unwrap();
    assert_eq!(again, md);
    assert!(xml.contains("<Unknown index=\"3\"/>"), "{xml}");
    assert!(xml.contains("<Unit name=\"N/m\"/>"), "{xml}");
}
