//! Rules on `<ModelVariables>`: unique and legal names, causality / variability /
//! initial combinations, start values, declared types, units, ranges, derivatives and
//! shared value references (alias sets).

use super::definitions::check_range;
use super::names::NameParser;
use crate::types::*;
use std::collections::{BTreeMap, HashMap};

/// The causality / variability / initial combinations FMI 2.0 allows (FMPy's table).
fn legal_combination(c: Causality, v: Variability, i: Option<Initial>) -> bool {
    use Causality as C;
    use Initial as I;
    use Variability as V;
    matches!(
        (c, v, i),
        (C::Parameter, V::Fixed | V::Tunable, Some(I::Exact))
            | (
                C::CalculatedParameter,
                V::Fixed | V::Tunable,
                Some(I::Calculated | I::Approx)
            )
            | (C::Input, V::Discrete | V::Continuous, Some(I::Exact))
            | (C::Output, V::Constant, Some(I::Exact))
            | (C::Output, V::Discrete | V::Continuous, Some(_))
            | (C::Local, V::Constant, Some(I::Exact))
            | (
                C::Local,
                V::Fixed | V::Tunable,
                Some(I::Calculated | I::Approx)
            )
            | (C::Local, V::Discrete | V::Continuous, Some(_))
            | (C::Independent, V::Continuous, None)
    )
}

/// The value-reference space a variable lives in (Enumerations share Integer's).
fn reference_space(kind: &VariableKind) -> &'static str {
    match kind {
        VariableKind::Real(_) => "Real",
        VariableKind::Integer(_) | VariableKind::Enumeration(_) => "Integer",
        VariableKind::Boolean(_) => "Boolean",
        VariableKind::String(_) => "String",
    }
}

impl ModelDescription {
    /// `"name"`, with the variable's line when known, for lists of variables in messages.
    fn named(&self, i: usize) -> String {
        let v = &self.model_variables[i];
        match self.source_lines.variables.get(i) {
            Some(l) => format!("\"{}\" (line {l})", v.name),
            None => format!("\"{}\"", v.name),
        }
    }

    pub(super) fn validate_variables(&self, problems: &mut Vec<String>) {
        let mut names: HashMap<&str, usize> = HashMap::new();
        let mut independent = Vec::new();
        // (space, vr) -> indices of the variables sharing it
        let mut references: BTreeMap<(&str, u32), Vec<usize>> = BTreeMap::new();
        // an FMI 3.0 <Alias> takes its start value from its variable (read as a variable of
        // its own without one): the alias sets with a start value
        let fmi3 = self.fmi_version.starts_with('3');
        let started: std::collections::HashSet<(&str, u32)> = (self.model_variables.iter())
            .filter(|v| fmi3 && v.has_start())
            .map(|v| (reference_space(&v.kind), v.value_reference))
            .collect();

        for (i, v) in self.model_variables.iter().enumerate() {
            let what = format!(
                "Variable \"{}\" (index {}{})",
                v.name,
                i + 1,
                SourceLines::suffix(self.source_lines.variables.get(i).copied())
            );

            self.check_variable_name(problems, &what, i, v, &mut names);
            references
                .entry((reference_space(&v.kind), v.value_reference))
                .or_default()
                .push(i);

            if v.causality == Causality::Independent {
                independent.push(i);
            }
            let aliased = started.contains(&(reference_space(&v.kind), v.value_reference));
            check_kind_and_start(problems, &what, v, aliased);
            let declared_def = self.check_declared_type(problems, &what, v);
            self.check_variable_values(problems, &what, v, declared_def);
        }

        if independent.len() > 1 {
            let names: Vec<String> = independent.iter().map(|&i| self.named(i)).collect();
            problems.push(format!(
                "At most one variable may have causality=\"independent\", found {}.",
                names.join(", ")
            ));
        }

        self.check_alias_sets(problems, &references);
    }

    /// The name of variable `i` is unique (`names` maps the names seen so far to their
    /// index) and legal for the naming convention.
    fn check_variable_name<'a>(
        &self,
        problems: &mut Vec<String>,
        what: &str,
        i: usize,
        v: &'a ScalarVariable,
        names: &mut HashMap<&'a str, usize>,
    ) {
        if let Some(first) = names.insert(v.name.as_str(), i) {
            problems.push(format!(
                "{what}: the name is not unique (also used by index {}).",
                first + 1
            ));
        }
        match self.variable_naming_convention {
            VariableNamingConvention::Flat => {
                if v.name.is_empty() {
                    problems.push(format!("{what}: the name is empty."));
                }
                for (c, label) in [
                    ('\r', "carriage return"),
                    ('\n', "line feed"),
                    ('\t', "tab"),
                ] {
                    if v.name.contains(c) {
                        problems.push(format!("{what}: the name contains a {label} character."));
                    }
                }
            }
            VariableNamingConvention::Structured => {
                if let Err(e) = NameParser::check(&v.name) {
                    problems.push(format!(
                        "{what}: not a legal name for the naming convention \"structured\" ({e})."
                    ));
                }
            }
        }
    }

    /// The variable's declared type exists and has the variable's base type; returns its
    /// definition.
    fn check_declared_type(
        &self,
        problems: &mut Vec<String>,
        what: &str,
        v: &ScalarVariable,
    ) -> Option<&SimpleType> {
        let declared = v.declared_type().map(|t| (t, self.type_definition(t)));
        if let Some((name, def)) = declared {
            match def {
                None => problems.push(format!(
                    "{what}: declaredType=\"{name}\" is not defined in <TypeDefinitions>."
                )),
                Some(def) if def.kind.type_name() != v.type_name() => problems.push(format!(
                    "{what}: is of type {} but its declaredType \"{name}\" is of type {}.",
                    v.type_name(),
                    def.kind.type_name()
                )),
                Some(_) => {}
            }
        }
        declared.and_then(|(_, d)| d)
    }

    /// Units, min ≤ start ≤ max (with the declared type's attributes as defaults), Real
    /// derivative references and Enumeration start values.
    fn check_variable_values(
        &self,
        problems: &mut Vec<String>,
        what: &str,
        v: &ScalarVariable,
        declared_def: Option<&SimpleType>,
    ) {
        let n = self.model_variables.len();
        match &v.kind {
            VariableKind::Real(r) => {
                let type_attrs = match declared_def.map(|d| &d.kind) {
                    Some(SimpleTypeKind::Real(a)) => Some(a),
                    _ => None,
                };
                let unit = r
                    .attributes
                    .unit
                    .as_deref()
                    .or(type_attrs.and_then(|a| a.unit.as_deref()));
                let display = r
                    .attributes
                    .display_unit
                    .as_deref()
                    .or(type_attrs.and_then(|a| a.display_unit.as_deref()));
                self.check_unit(problems, what, unit, display);
                let min = r.attributes.min.or(type_attrs.and_then(|a| a.min));
                let max = r.attributes.max.or(type_attrs.and_then(|a| a.max));
                check_range(problems, what, min, max, r.start);
                if let Some(d) = r.derivative {
                    match self.variable_at_index(d) {
                        None => problems.push(format!(
                            "{what}: derivative=\"{d}\" is not the index of a variable (1 to {n})."
                        )),
                        Some(state) if !matches!(state.kind, VariableKind::Real(_)) => {
                            problems.push(format!(
                                "{what}: derivative=\"{d}\" refers to \"{}\", which is not a Real variable.",
                                state.name
                            ))
                        }
                        Some(_) => {}
                    }
                }
            }
            VariableKind::Integer(iv) => {
                let type_attrs = match declared_def.map(|d| &d.kind) {
                    Some(SimpleTypeKind::Integer(a)) => Some(a),
                    _ => None,
                };
                let min = iv.attributes.min.or(type_attrs.and_then(|a| a.min));
                let max = iv.attributes.max.or(type_attrs.and_then(|a| a.max));
                check_range(
                    problems,
                    what,
                    min.map(f64::from),
                    max.map(f64::from),
                    iv.start.map(f64::from),
                );
            }
            VariableKind::Enumeration(e) => {
                check_range(
                    problems,
                    what,
                    e.attributes.min.map(f64::from),
                    e.attributes.max.map(f64::from),
                    e.start.map(f64::from),
                );
                if let (Some(start), Some(SimpleTypeKind::Enumeration { items, .. })) =
                    (e.start, declared_def.map(|d| &d.kind))
                {
                    if !items.iter().any(|it| it.value == start) {
                        problems.push(format!(
                            "{what}: start={start} is not a value of the enumeration \"{}\".",
                            e.declared_type
                        ));
                    }
                }
            }
            VariableKind::Boolean(_) | VariableKind::String(_) => {}
        }
    }

    /// Variables sharing a value reference follow the alias rules of FMI 2.0, 2.2.7.
    fn check_alias_sets(
        &self,
        problems: &mut Vec<String>,
        references: &BTreeMap<(&str, u32), Vec<usize>>,
    ) {
        for ((space, vr), members) in references {
            if members.len() < 2 {
                continue;
            }
            let list = |filter: &dyn Fn(&ScalarVariable) -> bool| -> Vec<String> {
                members
                    .iter()
                    .filter(|&&i| filter(&self.model_variables[i]))
                    .map(|&i| self.named(i))
                    .collect()
            };
            let with_start = list(&|v| v.variability != Variability::Constant && v.has_start());
            if with_start.len() > 1 {
                problems.push(format!(
                    "The {space} value reference {vr} is shared by {} which all have a start value (at most one variable of an alias set may have one).",
                    with_start.join(", ")
                ));
            }
            let settable =
                list(&|v| matches!(v.causality, Causality::Input | Causality::Parameter));
            if settable.len() > 1 {
                problems.push(format!(
                    "The {space} value reference {vr} is shared by the inputs/parameters {} (at most one variable of an alias set may be an input or a parameter).",
                    settable.join(", ")
                ));
            }
        }
    }
}

/// Base-type and variability, start values and the causality / variability / initial
/// combination of one variable.
/// The type's variability, and a start value where one is needed (`aliased`: its alias set
/// has one).
fn check_kind_and_start(problems: &mut Vec<String>, what: &str, v: &ScalarVariable, aliased: bool) {
    if !matches!(v.kind, VariableKind::Real(_)) && v.variability == Variability::Continuous {
        problems.push(format!(
            "{what}: is of type {} and must have variability other than \"continuous\".",
            v.type_name()
        ));
    }
    let initial = v.initial_or_default();
    if (matches!(initial, Some(Initial::Exact | Initial::Approx))
        || v.causality == Causality::Input)
        && !v.has_start()
        && !aliased
    {
        problems.push(format!("{what}: has no start value."));
    }
    if !legal_combination(v.causality, v.variability, initial) {
        let initial_text = match (v.initial, initial) {
            (Some(i), _) => format!(" and initial=\"{i}\""),
            (None, Some(i)) => format!(" and (default) initial=\"{i}\""),
            (None, None) => String::new(),
        };
        problems.push(format!(
            "{what}: the combination causality=\"{}\", variability=\"{}\"{initial_text} is not allowed.",
            v.causality, v.variability
        ));
    }
    if initial == Some(Initial::Calculated) && v.has_start() {
        problems.push(format!(
            "{what}: has initial=\"calculated\" but provides a start value."
        ));
    }
    if v.causality == Causality::Independent && v.has_start() {
        problems.push(format!(
            "{what}: has causality=\"independent\" but provides a start value."
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn combination_table_matches_fmpy() {
        use Causality as C;
        use Initial as I;
        use Variability as V;
        // count legal combinations over the full product: FMPy's table has 27 FMI 2.0
        // entries (its two structuralParameter rows are FMI 3.0 only).
        let mut count = 0;
        for &c in C::ALL {
            for &v in V::ALL {
                for i in [None, Some(I::Exact), Some(I::Approx), Some(I::Calculated)] {
                    if legal_combination(c, v, i) {
                        count += 1;
                    }
                }
            }
        }
        assert_eq!(count, 27);
        assert!(legal_combination(C::Input, V::Continuous, Some(I::Exact)));
        assert!(!legal_combination(C::Input, V::Continuous, Some(I::Approx)));
        assert!(!legal_combination(
            C::Parameter,
            V::Continuous,
            Some(I::Exact)
        ));
        assert!(!legal_combination(C::Output, V::Fixed, Some(I::Calculated)));
    }
}
