//! Rules on `<UnitDefinitions>` and `<TypeDefinitions>`, and the unit and range checks
//! that variables share with type definitions.

use crate::types::*;
use std::collections::HashSet;

impl ModelDescription {
    pub(super) fn validate_units_and_types(&self, problems: &mut Vec<String>) {
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
    pub(super) fn check_unit(
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
}

pub(super) fn check_range(
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
