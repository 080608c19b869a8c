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

mod definitions;
mod header;
mod names;
mod structure;
mod variables;

use crate::types::ModelDescription;

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
}
