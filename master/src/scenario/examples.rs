//! The scenarios `tbi scenario show NAME` prints: the default and the repository's
//! `examples/`, embedded so that a user starts from them in any folder.

/// (name, what it is, TOML).
pub const EXAMPLES: [(&str, &str, &str); 3] = [
    (
        "tsing-ma",
        "the paper's Tsing Ma case: 8 coaches at 70 km/h over the suspension bridge (the default)",
        super::DEFAULT_SCENARIO,
    ),
    (
        "tsing-ma-meeting",
        "two such trains meeting at mid main span, one per track (tbi run --meeting)",
        super::MEETING_SCENARIO,
    ),
    (
        "psc-25m-hslm",
        "a 25 m prestressed-concrete span on a 300 km/h line for the EN 1991-2 HSLM-A check",
        include_str!("../../../examples/psc-25m-hslm.toml"),
    ),
];

/// The TOML of the example `name` (None: the default), or an error naming the
/// examples.
pub fn text(name: Option<&str>) -> Result<&'static str, Box<dyn std::error::Error>> {
    let name = name.unwrap_or("tsing-ma");
    EXAMPLES
        .iter()
        .find(|e| e.0 == name)
        .map(|e| e.2)
        .ok_or_else(|| {
            format!(
                "tbi scenario show {name}: no such example; the examples are {}",
                EXAMPLES.map(|e| e.0).join(", ")
            )
            .into()
        })
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_example_is_a_valid_scenario() {
        for (name, _, text) in super::EXAMPLES {
            crate::scenario::Scenario::from_toml(text, name, std::path::Path::new("."))
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
}
