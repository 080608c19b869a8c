//! docs/scenario.md is the one scenario reference, and it holds to the code: every key the
//! scenario reader accepts is a row of it, and every row of a table the reader types names a
//! key the reader accepts.
//!
//! The accepted keys come from the reader itself: a scenario with an unknown key in a table
//! is refused with serde's "unknown field `…`, expected one of `a`, `b`, …", which lists the
//! table's keys. (The tables read by hand, `train.axles`, `train.vehicle` and `train.coach`,
//! are checked one way: each documented key is accepted.)

use std::collections::BTreeSet;
use std::path::Path;
use tbi::scenario::Scenario;

const BASE: &str = r#"name = "s"
[run]
speed_kmh = 100.0
[bridge]
kind = "simply_supported"
span_m = 20.0
youngs_modulus_pa = 3.5e10
inertia_vertical_m4 = 0.9
mass_per_length_kg_m = 12000.0
[train]
kind = "hslm_a"
name = "A1"
[track]
irregularity = "none"
[[probe]]
name = "mid"
x_m = 10.0
"#;

/// The documented keys: the first cell of every table row, `| \`key\` | …`.
fn documented() -> BTreeSet<String> {
    let path = tbi_tests::repo_path("docs/scenario.md");
    let text = std::fs::read_to_string(&path).unwrap();
    text.lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .map(String::from)
        .collect()
}

/// The keys the reader lists for an unknown key in `text`.
fn accepted(text: &str) -> BTreeSet<String> {
    let e = Scenario::from_toml(text, "probe.toml", Path::new("."))
        .expect_err("an unknown key is refused")
        .to_string();
    let list = e
        .split_once("unknown field `zz_unknown`, expected")
        .unwrap_or_else(|| panic!("no key list in: {e}"))
        .1;
    list.split('`')
        .skip(1)
        .step_by(2)
        .map(String::from)
        .collect()
}

/// `text` with `zz_unknown = 1` added as the first key under the line `header`.
fn with_unknown(text: &str, header: &str) -> String {
    if header.is_empty() {
        return format!("zz_unknown = 1\n{text}");
    }
    text.replacen(header, &format!("{header}\nzz_unknown = 1"), 1)
}

#[test]
fn the_reference_names_every_key_and_no_other() {
    let docs = documented();
    let beam = BASE.replace(
        "kind = \"simply_supported\"\nspan_m = 20.0",
        "kind = \"beam\"\nspans_m = [20.0]\nsections = [{ inertia_vertical_m4 = 0.9, zz_unknown = 1 }]",
    );
    let damping = BASE.replace(
        "mass_per_length_kg_m = 12000.0",
        "mass_per_length_kg_m = 12000.0\ndamping = { rule = \"en1991-2\", structure = \"prestressed_concrete\", zz_unknown = 1 }",
    );
    let wind = format!("{BASE}[wind]\nmean_speed_m_s = 10.0\n");
    let irregular = BASE.replace(
        "irregularity = \"none\"",
        "irregularity = { spectrum = \"german-low\", seed = 1, zz_unknown = 1 }",
    );
    let hunting = BASE.replace(
        "name = \"A1\"",
        "name = \"A1\"\nhunting = { amplitude_m = 0.003, zz_unknown = 1 }",
    );
    let cases: Vec<(&str, String)> = vec![
        ("", with_unknown(BASE, "")),
        ("run", with_unknown(BASE, "[run]")),
        ("bridge", with_unknown(BASE, "[bridge]")),
        ("train", with_unknown(BASE, "[train]")),
        ("track", with_unknown(BASE, "[track]")),
        ("probe", with_unknown(BASE, "[[probe]]")),
        ("coupling", format!("{BASE}[coupling]\nzz_unknown = 1\n")),
        ("wind", with_unknown(&wind, "[wind]")),
        ("wind.deck", format!("{wind}[wind.deck]\nzz_unknown = 1\n")),
        (
            "wind.turbulence",
            format!("{wind}[wind.turbulence]\nzz_unknown = 1\n"),
        ),
        (
            "wind.vehicle",
            format!("{wind}[wind.vehicle]\nzz_unknown = 1\n"),
        ),
        ("bridge.sections", beam),
        ("bridge.damping", damping),
        ("track.irregularity", irregular),
        ("train.hunting", hunting),
    ];
    let mut missing = Vec::new();
    let mut unknown = Vec::new();
    for (table, text) in &cases {
        let keys = accepted(text);
        let full = |k: &str| {
            if table.is_empty() {
                k.to_string()
            } else {
                format!("{table}.{k}")
            }
        };
        for k in &keys {
            if !docs.contains(&full(k)) {
                missing.push(full(k));
            }
        }
        // the documented keys of this table, one level down
        let prefix = if table.is_empty() {
            String::new()
        } else {
            format!("{table}.")
        };
        for d in docs.iter().filter(|d| d.starts_with(&prefix)) {
            let rest = &d[prefix.len()..];
            if rest.contains('.') || (table.is_empty() && d.contains('.')) {
                continue;
            }
            if !keys.contains(rest) {
                unknown.push(d.clone());
            }
        }
    }
    assert!(
        missing.is_empty(),
        "keys the reader accepts, missing from docs/scenario.md: {missing:?}"
    );
    assert!(
        unknown.is_empty(),
        "rows of docs/scenario.md the reader does not accept: {unknown:?}"
    );
}
