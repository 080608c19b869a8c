//! Rules on `<ModelStructure>`: valid and ascending Unknown indices and dependencies,
//! and the expected sets of Outputs, Derivatives and InitialUnknowns.

use crate::types::*;
use std::collections::HashSet;

impl ModelDescription {
    pub(super) fn validate_model_structure(&self, problems: &mut Vec<String>) {
        if !self.check_unknown_lists(problems) {
            return;
        }
        self.check_outputs(problems);
        let derivatives_ok = self.check_derivatives(problems);
        self.check_initial_unknowns(problems, derivatives_ok);
    }

    /// Indices and dependencies of the three `<Unknown>` lists refer to variables, indices
    /// ascend, dependenciesKind matches dependencies. Returns whether every index refers to
    /// a variable (the further rules need that).
    fn check_unknown_lists(&self, problems: &mut Vec<String>) -> bool {
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
        indices_ok
    }

    /// The sorted, deduplicated names of the variables at the 0-based `indices`.
    fn sorted_names(&self, indices: &mut dyn Iterator<Item = usize>) -> Vec<String> {
        let mut names: Vec<String> = indices
            .map(|i| self.model_variables[i].name.clone())
            .collect();
        names.sort();
        names.dedup();
        names
    }

    /// Outputs: exactly the variables with causality="output".
    fn check_outputs(&self, problems: &mut Vec<String>) {
        let ms = &self.model_structure;
        let lines = &self.source_lines;
        let expected: HashSet<usize> = self
            .model_variables
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == Causality::Output)
            .map(|(i, _)| i)
            .collect();
        let actual: HashSet<usize> = ms.outputs.iter().map(|u| u.index as usize - 1).collect();
        if expected != actual {
            let missing = self.sorted_names(&mut expected.difference(&actual).copied());
            let extra = self.sorted_names(&mut actual.difference(&expected).copied());
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
    }

    /// Derivatives: each refers to a variable with a derivative attribute. Returns whether
    /// all do.
    fn check_derivatives(&self, problems: &mut Vec<String>) -> bool {
        let ms = &self.model_structure;
        let lines = &self.source_lines;
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
        derivatives_ok
    }

    /// InitialUnknowns: outputs with initial approx/calculated, calculated parameters, and
    /// states/derivatives with initial approx/calculated (the latter only when
    /// `derivatives_ok`).
    fn check_initial_unknowns(&self, problems: &mut Vec<String>, derivatives_ok: bool) {
        let ms = &self.model_structure;
        let lines = &self.source_lines;
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
                self.sorted_names(&mut expected.iter().copied()).join(", "),
                self.sorted_names(&mut actual.iter().copied()).join(", ")
            ));
        }
    }
}
