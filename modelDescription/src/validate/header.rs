//! Rules on the root attributes, the interface elements (`modelIdentifier`) and
//! `<DefaultExperiment>`.

use super::names::is_c_identifier;
use crate::types::*;

impl ModelDescription {
    pub(super) fn validate_header(&self, problems: &mut Vec<String>) {
        let lines = &self.source_lines;
        let root = SourceLines::prefix(lines.root);
        // an FMI 3.0 description is read into these types (its own reader checks the version)
        if self.fmi_version != "2.0" && !self.fmi_version.starts_with("3.") {
            problems.push(format!(
                "{root}fmiVersion is \"{}\" but must be \"2.0\".",
                self.fmi_version
            ));
        }
        if self.model_name.trim().is_empty() {
            problems.push(format!("{root}modelName is empty."));
        }
        if self.guid.trim().is_empty() {
            let token = if self.fmi_version.starts_with('3') {
                "instantiationToken"
            } else {
                "guid"
            };
            problems.push(format!("{root}{token} is empty."));
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
}
