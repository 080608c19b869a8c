//! The FMI 2.0 rules a model description must follow beyond the XML schema.
//!
//! The checks are those of FMPy's `validate_fmu` (start values, legal combinations of
//! causality / variability / initial, unique names, units, ModelStructure outputs,
//! derivatives and initial unknowns, structured variable names), plus a few further rules
//! of the standard that FMPy leaves to the schema or skips: references between elements
//! (declared types, derivative indices, Unknown indices and dependencies), ascending
//! Unknown order, min ≤ start ≤ max, interface and experiment attributes.
//!
//! Value references: FMI 2.0 lets several variables of the same base type share a value
//! reference (an *alias set*, as Modelica tools emit for `a = b`). A shared reference is
//! therefore reported only when it breaks the alias rules of section 2.2.7: at most one
//! variable of a set that is not a constant may carry a `start` value, and at most one
//! may be an input or a parameter. Integer and Enumeration variables share one reference
//! space (both are accessed with `fmi2Get/SetInteger`).

use crate::types::*;
use std::collections::{BTreeMap, HashMap, HashSet};

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

/// Whether `s` is a C identifier (as a modelIdentifier must be: it prefixes symbols and
/// names the shared library).
fn is_c_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c == '_' || c.is_ascii_alphabetic())
        && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
}

/// A recursive-descent check of the `structured` naming convention (FMI 2.0, 2.2.9).
struct NameParser<'a> {
    s: &'a [u8],
    pos: usize,
}

impl NameParser<'_> {
    fn check(name: &str) -> Result<(), String> {
        let mut p = NameParser {
            s: name.as_bytes(),
            pos: 0,
        };
        p.name()?;
        if p.pos != p.s.len() {
            return Err(format!("unexpected character at position {}", p.pos + 1));
        }
        Ok(())
    }
    fn peek(&self) -> Option<u8> {
        self.s.get(self.pos).copied()
    }
    fn eat(&mut self, c: u8) -> bool {
        if self.peek() == Some(c) {
            self.pos += 1;
            true
        } else {
            false
        }
    }
    fn expect(&mut self, c: u8) -> Result<(), String> {
        if self.eat(c) {
            Ok(())
        } else {
            Err(format!(
                "expected '{}' at position {}",
                c as char,
                self.pos + 1
            ))
        }
    }
    fn name(&mut self) -> Result<(), String> {
        if self.s.starts_with(b"der(") {
            self.pos = 4;
            self.identifier()?;
            if self.eat(b',') {
                self.unsigned()?;
            }
            return self.expect(b')');
        }
        self.identifier()
    }
    fn identifier(&mut self) -> Result<(), String> {
        loop {
            self.bname()?;
            if self.peek() == Some(b'[') {
                self.array_indices()?;
            }
            if !self.eat(b'.') {
                return Ok(());
            }
        }
    }
    fn bname(&mut self) -> Result<(), String> {
        match self.peek() {
            Some(c) if c == b'_' || c.is_ascii_alphabetic() => {
                while matches!(self.peek(), Some(c) if c == b'_' || c.is_ascii_alphanumeric()) {
                    self.pos += 1;
                }
                Ok(())
            }
            Some(b'\'') => {
                self.pos += 1;
                let start = self.pos;
                loop {
                    match self.peek() {
                        None => return Err("unterminated quoted name".into()),
                        Some(b'\'') => break,
                        Some(b'\\') => {
                            self.pos += 1;
                            match self.peek() {
                                Some(
                                    b'\'' | b'"' | b'?' | b'\\' | b'a' | b'b' | b'f' | b'n' | b'r'
                                    | b't' | b'v',
                                ) => self.pos += 1,
                                _ => {
                                    return Err(format!(
                                        "illegal escape sequence at position {}",
                                        self.pos
                                    ))
                                }
                            }
                        }
                        Some(c)
                            if c.is_ascii_alphanumeric()
                                || b"_!#$%&()*+,-./:;<>=?@[]^{}|~ ".contains(&c) =>
                        {
                            self.pos += 1
                        }
                        Some(_) => {
                            return Err(format!(
                                "illegal character in quoted name at position {}",
                                self.pos + 1
                            ))
                        }
                    }
                }
                if self.pos == start {
                    return Err("empty quoted name".into());
                }
                self.pos += 1;
                Ok(())
            }
            _ => Err(format!(
                "expected a name (letter, '_' or quote) at position {}",
                self.pos + 1
            )),
        }
    }
    fn array_indices(&mut self) -> Result<(), String> {
        self.expect(b'[')?;
        self.unsigned()?;
        while self.eat(b',') {
            self.unsigned()?;
        }
        self.expect(b']')
    }
    fn unsigned(&mut self) -> Result<(), String> {
        let start = self.pos;
        while matches!(self.peek(), Some(c) if c.is_ascii_digit()) {
            self.pos += 1;
        }
        if self.pos == start {
            Err(format!(
                "expected an unsigned integer at position {}",
                self.pos + 1
            ))
        } else {
            Ok(())
        }
    }
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
    /// Check the FMI 2.0 rules (see the module documentation) and return one message per
    /// problem found; an empty list means the description is valid. Messages name the
    /// variable (and its 1-based index) or element concerned.
    pub fn validate(&self) -> Vec<String> {
        let mut problems = Vec::new();
        self.validate_header(&mut problems);
        self.validate_units_and_types(&mut problems);
        self.validate_variables(&mut problems);
        self.validate_model_structure(&mut problems);
        problems
    }

    /// `"name"`, with the variable's line when known, for lists of variables in messages.
    fn named(&self, i: usize) -> String {
        let v = &self.model_variables[i];
        match self.source_lines.variables.get(i) {
            Some(l) => format!("\"{}\" (line {l})", v.name),
            None => format!("\"{}\"", v.name),
        }
    }

    fn validate_header(&self, problems: &mut Vec<String>) {
        let lines = &self.source_lines;
        let root = SourceLines::prefix(lines.root);
        if self.fmi_version != "2.0" {
            problems.push(format!(
                "{root}fmiVersion is \"{}\" but must be \"2.0\".",
                self.fmi_version
            ));
        }
        if self.model_name.trim().is_empty() {
            problems.push(format!("{root}modelName is empty."));
        }
        if self.guid.trim().is_empty() {
            problems.push(format!("{root}guid is empty."));
        }
        if self.model_exchange.is_none() && self.co_simulation.is_none() {
            problems.push(format!(
                "{root}The description has neither a <ModelExchange> nor a <CoSimulation> element."
            ));
        }
        let identifiers = [
            self.model_exchange
                .as_ref()
                .map(|m| ("ModelExchange", &m.model_identifier, lines.model_exchange)),
            self.co_simulation
                .as_ref()
                .map(|c| ("CoSimulation", &c.model_identifier, lines.co_simulation)),
        ];
        for (element, id, line) in identifiers.into_iter().flatten() {
            if !is_c_identifier(id) {
                problems.push(format!(
                    "{}<{element}> modelIdentifier=\"{id}\" is not a valid C identifier.",
                    SourceLines::prefix(line)
                ));
            }
        }
        let experiment = SourceLines::prefix(lines.default_experiment);
        if let Some(d) = &self.default_experiment {
            let start = d.start_time.unwrap_or(0.0);
            for (name, value) in [
                ("startTime", d.start_time),
                ("stopTime", d.stop_time),
                ("tolerance", d.tolerance),
                ("stepSize", d.step_size),
            ] {
                if let Some(v) = value {
                    if !v.is_finite() {
                        problems.push(format!(
                            "{experiment}<DefaultExperiment> {name}={v} is not finite."
                        ));
                    }
                }
            }
            if let Some(stop) = d.stop_time {
                if stop <= start {
                    problems.push(format!(
                        "{experiment}<DefaultExperiment> stopTime={stop} is not greater than startTime={start}."
                    ));
                }
            }
            if let Some(t) = d.tolerance {
                if t <= 0.0 {
                    problems.push(format!(
                        "{experiment}<DefaultExperiment> tolerance={t} must be positive."
                    ));
                }
            }
            if let Some(h) = d.step_size {
                if h <= 0.0 {
                    problems.push(format!(
                        "{experiment}<DefaultExperiment> stepSize={h} must be positive."
                    ));
                }
            }
        }
    }

    fn validate_units_and_types(&self, problems: &mut Vec<String>) {
        let lines = &self.source_lines;
        let mut seen = HashSet::new();
        for (i, u) in self.unit_definitions.iter().enumerate() {
            let here = SourceLines::prefix(lines.units.get(i).copied());
            if !seen.insert(u.name.as_str()) {
                problems.push(format!(
                    "{here}The unit \"{}\" is defined more than once.",
                    u.name
                ));
            }
            let mut display = HashSet::new();
            for d in &u.display_units {
                if !display.insert(d.name.as_str()) {
                    problems.push(format!(
                        "{here}The display unit \"{}\" of unit \"{}\" is defined more than once.",
                        d.name, u.name
                    ));
                }
            }
        }
        let mut seen = HashSet::new();
        for (i, t) in self.type_definitions.iter().enumerate() {
            let line = lines.types.get(i).copied();
            let here = SourceLines::prefix(line);
            let what = format!(
                "Type \"{}\"{}",
                t.name,
                line.map(|l| format!(" (line {l})")).unwrap_or_default()
            );
            if !seen.insert(t.name.as_str()) {
                problems.push(format!(
                    "{here}The type \"{}\" is defined more than once.",
                    t.name
                ));
            }
            match &t.kind {
                SimpleTypeKind::Real(r) => {
                    self.check_unit(
                        problems,
                        &what,
                        r.unit.as_deref(),
                        r.display_unit.as_deref(),
                    );
                    check_range(problems, &what, r.min, r.max, None);
                }
                SimpleTypeKind::Integer(i) => {
                    check_range(
                        problems,
                        &what,
                        i.min.map(f64::from),
                        i.max.map(f64::from),
                        None,
                    );
                }
                SimpleTypeKind::Enumeration { items, .. } => {
                    if items.is_empty() {
                        problems.push(format!(
                            "{here}The enumeration type \"{}\" has no items.",
                            t.name
                        ));
                    }
                    let mut names = HashSet::new();
                    let mut values = HashSet::new();
                    for item in items {
                        if !names.insert(item.name.as_str()) || !values.insert(item.value) {
                            problems.push(format!(
                                "{here}The enumeration type \"{}\" has more than one item named \"{}\" or with value {}.",
                                t.name, item.name, item.value
                            ));
                        }
                    }
                }
                SimpleTypeKind::Boolean | SimpleTypeKind::String => {}
            }
        }
    }

    /// `unit` must be defined; `display_unit` must be one of its display units.
    fn check_unit(
        &self,
        problems: &mut Vec<String>,
        what: &str,
        unit: Option<&str>,
        display_unit: Option<&str>,
    ) {
        match unit {
            Some(unit) => match self.unit_definition(unit) {
                None => problems.push(format!("{what}: the unit \"{unit}\" is not defined.")),
                Some(def) => {
                    if let Some(d) = display_unit {
                        if !def.display_units.iter().any(|du| du.name == d) {
                            problems.push(format!(
                                "{what}: the display unit \"{d}\" is not defined for unit \"{unit}\"."
                            ));
                        }
                    }
                }
            },
            None => {
                if let Some(d) = display_unit {
                    problems.push(format!("{what}: has the display unit \"{d}\" but no unit."));
                }
            }
        }
    }

    fn validate_variables(&self, problems: &mut Vec<String>) {
        let n = self.model_variables.len();
        let mut names: HashMap<&str, usize> = HashMap::new();
        let mut independent = Vec::new();
        // (space, vr) -> indices of the variables sharing it
        let mut references: BTreeMap<(&str, u32), Vec<usize>> = BTreeMap::new();

        for (i, v) in self.model_variables.iter().enumerate() {
            let what = format!(
                "Variable \"{}\" (index {}{})",
                v.name,
                i + 1,
                SourceLines::suffix(self.source_lines.variables.get(i).copied())
            );

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
                            problems
                                .push(format!("{what}: the name contains a {label} character."));
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
            references
                .entry((reference_space(&v.kind), v.value_reference))
                .or_default()
                .push(i);

            if v.causality == Causality::Independent {
                independent.push(i);
            }
            if !matches!(v.kind, VariableKind::Real(_)) && v.variability == Variability::Continuous
            {
                problems.push(format!(
                    "{what}: is of type {} and must have variability other than \"continuous\".",
                    v.type_name()
                ));
            }
            let initial = v.initial_or_default();
            if (matches!(initial, Some(Initial::Exact | Initial::Approx))
                || v.causality == Causality::Input)
                && !v.has_start()
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

            // declared type, units, ranges
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
            let declared_def = declared.and_then(|(_, d)| d);
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
                    self.check_unit(problems, &what, unit, display);
                    let min = r.attributes.min.or(type_attrs.and_then(|a| a.min));
                    let max = r.attributes.max.or(type_attrs.and_then(|a| a.max));
                    check_range(problems, &what, min, max, r.start);
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
                        &what,
                        min.map(f64::from),
                        max.map(f64::from),
                        iv.start.map(f64::from),
                    );
                }
                VariableKind::Enumeration(e) => {
                    check_range(
                        problems,
                        &what,
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

        if independent.len() > 1 {
            let names: Vec<String> = independent.iter().map(|&i| self.named(i)).collect();
            problems.push(format!(
                "At most one variable may have causality=\"independent\", found {}.",
                names.join(", ")
            ));
        }

        for ((space, vr), members) in &references {
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

    fn validate_model_structure(&self, problems: &mut Vec<String>) {
        let n = self.model_variables.len();
        let ms = &self.model_structure;
        let mut indices_ok = true;

        let lines = &self.source_lines;
        for (list, unknowns, list_lines) in [
            ("Outputs", &ms.outputs, &lines.outputs),
            ("Derivatives", &ms.derivatives, &lines.derivatives),
            (
                "InitialUnknowns",
                &ms.initial_unknowns,
                &lines.initial_unknowns,
            ),
        ] {
            let mut previous = 0u32;
            for (k, u) in unknowns.iter().enumerate() {
                let what = format!(
                    "ModelStructure/{list}/Unknown {} (index={}{})",
                    k + 1,
                    u.index,
                    SourceLines::suffix(list_lines.get(k).copied())
                );
                if u.index == 0 || u.index as usize > n {
                    problems.push(format!(
                        "{what}: the index is not the 1-based position of a variable (1 to {n})."
                    ));
                    indices_ok = false;
                } else if u.index <= previous {
                    problems.push(format!(
                        "{what}: the unknowns must be listed once each in ascending order of index."
                    ));
                }
                previous = previous.max(u.index);
                if let Some(deps) = &u.dependencies {
                    for d in deps {
                        if *d == 0 || *d as usize > n {
                            problems.push(format!(
                                "{what}: dependency {d} is not the index of a variable (1 to {n})."
                            ));
                        }
                    }
                }
                match (&u.dependencies, &u.dependencies_kind) {
                    (None, Some(_)) => {
                        problems.push(format!("{what}: has dependenciesKind but no dependencies."))
                    }
                    (Some(d), Some(k)) if d.len() != k.len() => problems.push(format!(
                        "{what}: dependencies has {} entries but dependenciesKind has {}.",
                        d.len(),
                        k.len()
                    )),
                    _ => {}
                }
            }
        }
        if !indices_ok {
            return;
        }
        let name_set = |indices: &mut dyn Iterator<Item = usize>| -> Vec<String> {
            let mut names: Vec<String> = indices
                .map(|i| self.model_variables[i].name.clone())
                .collect();
            names.sort();
            names.dedup();
            names
        };

        // Outputs: exactly the variables with causality="output".
        let expected: HashSet<usize> = self
            .model_variables
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == Causality::Output)
            .map(|(i, _)| i)
            .collect();
        let actual: HashSet<usize> = ms.outputs.iter().map(|u| u.index as usize - 1).collect();
        if expected != actual {
            let missing = name_set(&mut expected.difference(&actual).copied());
            let extra = name_set(&mut actual.difference(&expected).copied());
            let mut message = format!(
                "{}ModelStructure/Outputs must have exactly one entry for each variable with causality=\"output\".",
                SourceLines::prefix(lines.model_structure)
            );
            if !missing.is_empty() {
                message.push_str(&format!(" Missing: {}.", missing.join(", ")));
            }
            if !extra.is_empty() {
                message.push_str(&format!(" Not outputs: {}.", extra.join(", ")));
            }
            problems.push(message);
        }

        // Derivatives: each refers to a variable with a derivative attribute.
        let mut derivatives_ok = true;
        for (k, u) in ms.derivatives.iter().enumerate() {
            let v = &self.model_variables[u.index as usize - 1];
            let has_derivative = matches!(&v.kind, VariableKind::Real(r) if r.derivative.is_some());
            if !has_derivative {
                derivatives_ok = false;
                problems.push(format!(
                    "{}ModelStructure/Derivatives/Unknown {} refers to variable \"{}\" (index {}), which has no derivative attribute.",
                    SourceLines::prefix(lines.derivatives.get(k).copied()),
                    k + 1,
                    v.name,
                    u.index
                ));
            }
        }

        // InitialUnknowns: outputs with initial approx/calculated, calculated parameters,
        // and states/derivatives with initial approx/calculated.
        let approx_or_calculated = |v: &ScalarVariable| {
            matches!(
                v.initial_or_default(),
                Some(Initial::Approx | Initial::Calculated)
            )
        };
        let mut expected: HashSet<usize> = self
            .model_variables
            .iter()
            .enumerate()
            .filter(|(_, v)| {
                (v.causality == Causality::Output && approx_or_calculated(v))
                    || v.causality == Causality::CalculatedParameter
            })
            .map(|(i, _)| i)
            .collect();
        if derivatives_ok {
            for u in &ms.derivatives {
                let der_index = u.index as usize - 1;
                let der = &self.model_variables[der_index];
                if approx_or_calculated(der) {
                    expected.insert(der_index);
                }
                if let VariableKind::Real(RealVariable {
                    derivative: Some(state),
                    ..
                }) = &der.kind
                {
                    if let Some(state_var) = self.variable_at_index(*state) {
                        if approx_or_calculated(state_var) {
                            expected.insert(*state as usize - 1);
                        }
                    }
                }
            }
        }
        let actual: HashSet<usize> = ms
            .initial_unknowns
            .iter()
            .map(|u| u.index as usize - 1)
            .collect();
        if expected != actual {
            problems.push(format!(
                "{}ModelStructure/InitialUnknowns does not contain the expected set of variables. Expected {{{}}} but was {{{}}}.",
                SourceLines::prefix(lines.model_structure),
                name_set(&mut expected.iter().copied()).join(", "),
                name_set(&mut actual.iter().copied()).join(", ")
            ));
        }
    }
}

fn check_range(
    problems: &mut Vec<String>,
    what: &str,
    min: Option<f64>,
    max: Option<f64>,
    start: Option<f64>,
) {
    if let (Some(lo), Some(hi)) = (min, max) {
        if lo > hi {
            problems.push(format!("{what}: min={lo} is greater than max={hi}."));
        }
    }
    if let Some(s) = start {
        if let Some(lo) = min {
            if s < lo {
                problems.push(format!("{what}: start={s} is less than min={lo}."));
            }
        }
        if let Some(hi) = max {
            if s > hi {
                problems.push(format!("{what}: start={s} is greater than max={hi}."));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structured_names() {
        for ok in [
            "a",
            "a.b[1].c",
            "der(x)",
            "der(body.v,2)",
            "'quoted name!'",
            "a[1,2]",
            "'it\\'s'",
            "_x1",
        ] {
            assert!(NameParser::check(ok).is_ok(), "{ok}");
        }
        for bad in [
            "", "1a", "a..b", "a[", "a[]", "der(x", "a b", "''", "a[1, 2]", "'a\\q'",
        ] {
            assert!(NameParser::check(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn c_identifiers() {
        assert!(is_c_identifier("bridge_fmu"));
        assert!(is_c_identifier("_B2"));
        assert!(!is_c_identifier("2b"));
        assert!(!is_c_identifier("a-b"));
        assert!(!is_c_identifier(""));
    }

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
