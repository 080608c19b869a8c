//! Every parser of user input, fed mutated inputs: zero panics. 30 000 cases per parser
//! (180 000 in all) from a fixed seed, so a failure reproduces; inputs that once failed
//! are kept in each test's corpus and checked on every run.
//!
//! Parsers: the scenario TOML (parse and every check, `Scenario::from_toml`), the track
//! record CSV (`Record::parse`), the modes file as CSV (`ModeSet::parse_csv`) and JSON
//! (serde + `ModeSet::validate`), `modelDescription.xml` (`ModelDescription::parse`) and the
//! SSP's `SystemStructure.ssd` (`ssp::parse_ssd`).

use std::path::Path;
use tbi::scenario::Scenario;
use tbi_modes::ModeSet;
use tbi_tests::fuzz;

const CASES: usize = 30_000;

fn text(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(bytes)
}

#[test]
fn scenario_toml() {
    let data = tbi_tests::repo_path("master/tests/data");
    let seeds: Vec<String> = ["yang-yau.toml", "coaches-60m.toml", "stiff-20m.toml"]
        .iter()
        .map(|f| std::fs::read_to_string(data.join(f)).unwrap())
        .chain([tbi::scenario::DEFAULT_SCENARIO.to_owned()])
        .collect();
    let seeds: Vec<&[u8]> = seeds.iter().map(|s| s.as_bytes()).collect();
    let parse = |b: &[u8]| Scenario::from_toml(&text(b), "fuzz.toml", Path::new(".")).is_ok();
    fuzz::corpus(
        "scenario",
        &[
            b"name = \"x\"\n[run]\nspeed_kmh = 1e-300\n",
            b"[run]\nspeed_kmh = 70\n[bridge]\nkind = \"simply_supported\"\nmodes = 18446744073709551615\n",
        ],
        parse,
    );
    let accepted = fuzz::run("scenario", 0x5ce7, &seeds, CASES, parse);
    assert!(
        accepted > 100,
        "only {accepted} mutated scenarios were valid"
    );
}

#[test]
fn track_record_csv() {
    let mut seed = String::from("x_m,lateral_m,vertical_m,cross_level_rad\n");
    for i in 0..40 {
        let x = i as f64 * 0.5;
        seed += &format!("{x},{},{},{}\n", 1e-3 * x.sin(), 2e-3 * x.cos(), 1e-4 * x);
    }
    let periodic = seed.replacen('\n', "\n# periodic\n", 1);
    let parse = |b: &[u8]| tbi_track::Record::parse(&text(b), "fuzz.csv").is_ok();
    fuzz::corpus(
        "record",
        &[b"x_m,lateral_m\n1e308,nan\n", b"\xef\xbb\xbf"],
        parse,
    );
    let accepted = fuzz::run(
        "record",
        0x7ac4,
        &[seed.as_bytes(), periodic.as_bytes()],
        CASES,
        parse,
    );
    assert!(accepted > 100, "only {accepted} mutated records were valid");
}

fn modes_csv_seed() -> String {
    let mut s =
        String::from("mode,label,frequency_hz,damping_ratio,x_m,lateral,vertical,torsion\n");
    for m in 1..=3 {
        for j in 0..9 {
            let x = j as f64 * 5.0;
            let v = (m as f64 * std::f64::consts::PI * x / 40.0).sin() * 0.02;
            s += &format!("{m},V-{m},{},,{x},0,{v},0\n", 2.0 * m as f64);
        }
    }
    s
}

#[test]
fn modes_csv() {
    let seed = modes_csv_seed();
    let parse = |b: &[u8]| ModeSet::parse_csv(&text(b), Path::new("fuzz.csv")).is_ok();
    fuzz::corpus("modes-csv", &[b"mode,label\n0,x\n", b"\n\n\n"], parse);
    let accepted = fuzz::run("modes-csv", 0x30de, &[seed.as_bytes()], CASES, parse);
    assert!(
        accepted > 100,
        "only {accepted} mutated modes files were valid"
    );
}

#[test]
fn modes_json() {
    let set = ModeSet::parse_csv(&modes_csv_seed(), Path::new("seed.csv")).unwrap();
    let seed = serde_json::to_string_pretty(&set).unwrap();
    let parse = |b: &[u8]| {
        serde_json::from_slice::<ModeSet>(b)
            .ok()
            .is_some_and(|s| s.validate(Path::new("fuzz.json")).is_ok())
    };
    fuzz::corpus(
        "modes-json",
        &[b"{\"format\":\"tbi-modes-1\",\"x_m\":[],\"modes\":[]}"],
        parse,
    );
    let accepted = fuzz::run("modes-json", 0x150e, &[seed.as_bytes()], CASES, parse);
    assert!(
        accepted > 100,
        "only {accepted} mutated modes files were valid"
    );
}

#[test]
fn model_description_xml() {
    let seeds: Vec<String> = ["yang-yau-bridge.xml", "yang-yau-train.xml"]
        .iter()
        .map(|f| std::fs::read_to_string(tbi_tests::repo_path("tests/golden").join(f)).unwrap())
        .collect();
    let seeds: Vec<&[u8]> = seeds.iter().map(|s| s.as_bytes()).collect();
    let parse = |b: &[u8]| model_description::ModelDescription::parse(&text(b), "fuzz.xml").is_ok();
    fuzz::corpus(
        "modelDescription",
        &[b"<fmiModelDescription/>", b"<?xml"],
        parse,
    );
    let accepted = fuzz::run("modelDescription", 0x3d11, &seeds, CASES, parse);
    assert!(
        accepted > 100,
        "only {accepted} mutated descriptions were valid"
    );
}

#[test]
fn system_structure_ssd() {
    let seed =
        std::fs::read_to_string(tbi_tests::repo_path("tests/golden/yang-yau-system.ssd")).unwrap();
    let parse = |b: &[u8]| tbi_ssp::parse_ssd(&text(b), "fuzz.ssd").is_ok();
    fuzz::corpus("ssd", &[b"<a/>", b"<ssd:Component name=\"x\"/>"], parse);
    let accepted = fuzz::run("ssd", 0x55d0, &[seed.as_bytes()], CASES, parse);
    assert!(accepted > 100, "only {accepted} mutated SSDs were valid");
}
