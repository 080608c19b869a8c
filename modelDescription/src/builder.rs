//! Creating descriptions in code (used by the FMU exporter).
//!
//! ```
//! use model_description::{Causality, ModelDescriptionBuilder, RealBuilder, Variability};
//!
//! let md = ModelDescriptionBuilder::new("Bridge", "{0b6c1f5e-0000-4000-8000-000000000001}", "bridge")
//!     .description("Simply supported Euler-Bernoulli beam")
//!     .capabilities(|cs| {
//!         cs.can_handle_variable_communication_step_size = true;
//!         cs.can_get_and_set_fmu_state = true;
//!     })
//!     .real(RealBuilder::parameter("EI", 0, 1.0e10).unit("N.m2").description("bending stiffness"))
//!     .real(RealBuilder::input("F", 1, 0.0).unit("N"))
//!     .real(RealBuilder::output("w", 2).unit("m"))
//!     .real(RealBuilder::new("a", 3).causality(Causality::Local).variability(Variability::Continuous))
//!     .build()
//!     .unwrap();
//! assert_eq!(md.model_structure.outputs.len(), 1);
//! assert_eq!(md.model_structure.initial_unknowns[0].index, 3);
//! assert!(md.validate().is_empty());
//! ```
//!
//! `build` fills in what follows from the variables — ModelStructure (Outputs and
//! InitialUnknowns, see [`ModelDescription::generate_model_structure`]) and a
//! `<Unit>` for every unit used but not declared — and then runs
//! [`ModelDescription::validate`], so a description that builds is one FMPy accepts.

use crate::types::*;
use std::fmt;

/// The description could not be built: the problems [`ModelDescription::validate`] found.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BuildError {
    pub model_name: String,
    pub problems: Vec<String>,
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the model description of {} is not valid FMI 2.0 ({} problem{}):",
            self.model_name,
            self.problems.len(),
            if self.problems.len() == 1 { "" } else { "s" }
        )?;
        for p in &self.problems {
            write!(f, "\n  - {p}")?;
        }
        Ok(())
    }
}

impl std::error::Error for BuildError {}

/// A scalar Real variable under construction.
#[derive(Debug, Clone, PartialEq)]
pub struct RealBuilder {
    variable: ScalarVariable,
}

impl RealBuilder {
    /// A local continuous variable (no start value, `initial` left to its default).
    pub fn new(name: impl Into<String>, value_reference: u32) -> Self {
        Self {
            variable: ScalarVariable {
                name: name.into(),
                value_reference,
                description: None,
                causality: Causality::Local,
                variability: Variability::Continuous,
                initial: None,
                can_handle_multiple_set_per_time_instant: None,
                kind: VariableKind::Real(RealVariable::default()),
            },
        }
    }

    /// A fixed parameter with its start value.
    pub fn parameter(name: impl Into<String>, value_reference: u32, start: f64) -> Self {
        Self::new(name, value_reference)
            .causality(Causality::Parameter)
            .variability(Variability::Fixed)
            .start(start)
    }

    /// A continuous input with its start value.
    pub fn input(name: impl Into<String>, value_reference: u32, start: f64) -> Self {
        Self::new(name, value_reference)
            .causality(Causality::Input)
            .start(start)
    }

    /// A continuous output computed by the model (`initial="calculated"` by default).
    pub fn output(name: impl Into<String>, value_reference: u32) -> Self {
        Self::new(name, value_reference).causality(Causality::Output)
    }

    pub fn causality(mut self, causality: Causality) -> Self {
        self.variable.causality = causality;
        self
    }

    pub fn variability(mut self, variability: Variability) -> Self {
        self.variable.variability = variability;
        self
    }

    /// Set `initial` explicitly (otherwise the FMI default for the combination applies).
    pub fn initial(mut self, initial: Initial) -> Self {
        self.variable.initial = Some(initial);
        self
    }

    pub fn start(mut self, start: f64) -> Self {
        self.real_mut().start = Some(start);
        self
    }

    /// The unit's name; a `<Unit>` definition is added by `build` if none is declared.
    pub fn unit(mut self, unit: impl Into<String>) -> Self {
        self.real_mut().attributes.unit = Some(unit.into());
        self
    }

    pub fn description(mut self, description: impl Into<String>) -> Self {
        self.variable.description = Some(description.into());
        self
    }

    pub fn min(mut self, min: f64) -> Self {
        self.real_mut().attributes.min = Some(min);
        self
    }

    pub fn max(mut self, max: f64) -> Self {
        self.real_mut().attributes.max = Some(max);
        self
    }

    pub fn nominal(mut self, nominal: f64) -> Self {
        self.real_mut().attributes.nominal = Some(nominal);
        self
    }

    pub fn quantity(mut self, quantity: impl Into<String>) -> Self {
        self.real_mut().attributes.quantity = Some(quantity.into());
        self
    }

    /// The finished variable (not validated; `build` validates the whole description).
    pub fn into_variable(self) -> ScalarVariable {
        self.variable
    }

    fn real_mut(&mut self) -> &mut RealVariable {
        match &mut self.variable.kind {
            VariableKind::Real(r) => r,
            _ => unreachable!("RealBuilder only ever holds a Real variable"),
        }
    }
}

/// Builds a Co-Simulation description; see the module documentation.
#[derive(Debug, Clone)]
pub struct ModelDescriptionBuilder {
    md: ModelDescription,
}

impl ModelDescriptionBuilder {
    /// A Co-Simulation description with no variables yet; every capability flag is `false`
    /// until set with [`ModelDescriptionBuilder::capabilities`].
    pub fn new(
        model_name: impl Into<String>,
        guid: impl Into<String>,
        model_identifier: impl Into<String>,
    ) -> Self {
        Self {
            md: ModelDescription {
                variable_naming_convention: VariableNamingConvention::Structured,
                number_of_event_indicators: Some(0),
                co_simulation: Some(CoSimulation::new(model_identifier)),
                ..ModelDescription::empty("2.0", &model_name.into(), &guid.into())
            },
        }
    }

    pub fn description(mut self, description: impl Into<String>) -> Self {
        self.md.description = Some(description.into());
        self
    }

    pub fn author(mut self, author: impl Into<String>) -> Self {
        self.md.author = Some(author.into());
        self
    }

    pub fn version(mut self, version: impl Into<String>) -> Self {
        self.md.version = Some(version.into());
        self
    }

    pub fn copyright(mut self, copyright: impl Into<String>) -> Self {
        self.md.copyright = Some(copyright.into());
        self
    }

    pub fn license(mut self, license: impl Into<String>) -> Self {
        self.md.license = Some(license.into());
        self
    }

    pub fn generation_tool(mut self, tool: impl Into<String>) -> Self {
        self.md.generation_tool = Some(tool.into());
        self
    }

    pub fn generation_date_and_time(mut self, date_and_time: impl Into<String>) -> Self {
        self.md.generation_date_and_time = Some(date_and_time.into());
        self
    }

    pub fn variable_naming_convention(mut self, convention: VariableNamingConvention) -> Self {
        self.md.variable_naming_convention = convention;
        self
    }

    /// Set the Co-Simulation capability flags.
    pub fn capabilities(mut self, set: impl FnOnce(&mut CoSimulation)) -> Self {
        if let Some(cs) = self.md.co_simulation.as_mut() {
            set(cs);
        }
        self
    }

    pub fn default_experiment(mut self, experiment: DefaultExperiment) -> Self {
        self.md.default_experiment = Some(experiment);
        self
    }

    /// Declare a unit (with base unit and display units); units only named by variables
    /// get a bare declaration automatically.
    pub fn unit(mut self, unit: Unit) -> Self {
        self.md.unit_definitions.push(unit);
        self
    }

    pub fn log_category(mut self, name: impl Into<String>, description: impl Into<String>) -> Self {
        self.md.log_categories.push(LogCategory {
            name: name.into(),
            description: Some(description.into()),
        });
        self
    }

    /// Append a Real variable (its ModelStructure index is its position, from 1).
    pub fn real(mut self, variable: RealBuilder) -> Self {
        self.md.model_variables.push(variable.into_variable());
        self
    }

    /// Append any variable.
    pub fn variable(mut self, variable: ScalarVariable) -> Self {
        self.md.model_variables.push(variable);
        self
    }

    /// Fill in ModelStructure and undeclared units, then validate.
    pub fn build(mut self) -> Result<ModelDescription, BuildError> {
        let mut used_units: Vec<String> = Vec::new();
        for v in &self.md.model_variables {
            if let VariableKind::Real(r) = &v.kind {
                if let Some(u) = &r.attributes.unit {
                    if !used_units.contains(u) {
                        used_units.push(u.clone());
                    }
                }
            }
        }
        for u in used_units {
            if self.md.unit_definition(&u).is_none() {
                self.md.unit_definitions.push(Unit::new(u));
            }
        }
        self.md.generate_model_structure();
        let problems = self.md.validate();
        if problems.is_empty() {
            Ok(self.md)
        } else {
            Err(BuildError {
                model_name: self.md.model_name,
                problems,
            })
        }
    }
}

impl ModelDescription {
    /// Replace ModelStructure with the one the variables imply:
    ///
    /// - Outputs: every variable with `causality="output"`, ascending index;
    /// - Derivatives: every Real variable with a `derivative` attribute;
    /// - InitialUnknowns: outputs whose `initial` is `approx` or `calculated`, calculated
    ///   parameters, and the derivatives and states listed above whose `initial` is
    ///   `approx` or `calculated`.
    ///
    /// No `dependencies` are written, which FMI 2.0 defines as "depends on all knowns":
    /// always correct, if less informative than an exact list.
    pub fn generate_model_structure(&mut self) {
        let index = |i: usize| u32::try_from(i + 1).expect("more than u32::MAX variables");
        let approx_or_calculated = |v: &ScalarVariable| {
            matches!(
                v.initial_or_default(),
                Some(Initial::Approx | Initial::Calculated)
            )
        };
        let vars = &self.model_variables;
        let outputs: Vec<Unknown> = vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == Causality::Output)
            .map(|(i, _)| Unknown::new(index(i)))
            .collect();
        let derivative_of = |v: &ScalarVariable| match &v.kind {
            VariableKind::Real(r) => r.derivative,
            _ => None,
        };
        let derivatives: Vec<Unknown> = vars
            .iter()
            .enumerate()
            .filter(|(_, v)| derivative_of(v).is_some())
            .map(|(i, _)| Unknown::new(index(i)))
            .collect();
        let mut initial: Vec<usize> = vars
            .iter()
            .enumerate()
            .filter(|(_, v)| {
                (v.causality == Causality::Output && approx_or_calculated(v))
                    || v.causality == Causality::CalculatedParameter
            })
            .map(|(i, _)| i)
            .collect();
        for (i, v) in vars.iter().enumerate() {
            if let Some(state) = derivative_of(v) {
                if approx_or_calculated(v) {
                    initial.push(i);
                }
                if let Some(s) = self.variable_at_index(state) {
                    if approx_or_calculated(s) {
                        initial.push(state as usize - 1);
                    }
                }
            }
        }
        initial.sort_unstable();
        initial.dedup();
        self.model_structure = ModelStructure {
            outputs,
            derivatives,
            initial_unknowns: initial
                .into_iter()
                .map(|i| Unknown::new(index(i)))
                .collect(),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn build_reports_invalid_variables() {
        let err = ModelDescriptionBuilder::new("M", "{guid}", "m")
            .real(RealBuilder::new("x", 0).causality(Causality::Input))
            .real(RealBuilder::output("x", 1))
            .build()
            .unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains("\"x\" (index 1): has no start value"),
            "{text}"
        );
        assert!(text.contains("the name is not unique"), "{text}");
    }

    #[test]
    fn undeclared_units_are_declared_once() {
        let md = ModelDescriptionBuilder::new("M", "{guid}", "m")
            .unit(Unit {
                name: "m".into(),
                base_unit: Some(BaseUnit {
                    m: 1,
                    ..BaseUnit::default()
                }),
                display_units: vec![],
            })
            .real(RealBuilder::output("x", 0).unit("m"))
            .real(RealBuilder::output("v", 1).unit("m/s"))
            .real(RealBuilder::output("v2", 2).unit("m/s"))
            .build()
            .unwrap();
        let names: Vec<&str> = md
            .unit_definitions
            .iter()
            .map(|u| u.name.as_str())
            .collect();
        assert_eq!(names, ["m", "m/s"]);
        assert!(md.unit_definitions[0].base_unit.is_some());
    }

    #[test]
    fn model_structure_follows_initial() {
        let md = ModelDescriptionBuilder::new("M", "{guid}", "m")
            .real(RealBuilder::parameter("k", 0, 1.0))
            .real(
                RealBuilder::output("y_exact", 1)
                    .initial(Initial::Exact)
                    .start(0.0),
            )
            .real(RealBuilder::output("y", 2))
            .real(
                RealBuilder::new("kc", 3)
                    .causality(Causality::CalculatedParameter)
                    .variability(Variability::Fixed),
            )
            .build()
            .unwrap();
        let outputs: Vec<u32> = md.model_structure.outputs.iter().map(|u| u.index).collect();
        let initial: Vec<u32> = md
            .model_structure
            .initial_unknowns
            .iter()
            .map(|u| u.index)
            .collect();
        assert_eq!(outputs, [2, 3]);
        assert_eq!(initial, [3, 4]);
    }
}
