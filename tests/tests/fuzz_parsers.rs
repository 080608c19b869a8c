//! Every parser of user input, fed mutated inputs: zero panics. 30 000 cases per parser
//! (210 000 in all) from a fixed seed, so a failure reproduces; inputs that once failed
//! are kept in each test's corpus and checked on every run.
//!
//! Parsers: the scenario TOML (parse and every check, `Scenario::from_toml`), the track
//! record CSV (`Record::parse`), the modes file as CSV (`ModeSet::parse_csv`) and JSON
//! (serde + `ModeSet::validate`), `modelDescription.xml` (`ModelDescription::parse`) and the
//! SSP's `SystemStructure.ssd` (`ssp::parse_ssd`; seeds with inline parameter bindings of
//! every type, a bound `.ssv` file and the coupling and process annotations) and its `.ssv`
//! parameter files (`ssp::parse_ssv`).

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
    // a process annotation in a component outside <Elements> once panicked
    let outside = br#"<ssd:SystemStructureDescription xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0"><ssd:System><ssd:Component name="a"><ssd:Annotations><ssc:Annotation type="org.tbi.process"><tbi:Process in_process="true"/></ssc:Annotation></ssd:Annotations></ssd:Component><ssd:Elements/></ssd:System></ssd:SystemStructureDescription>"#;
    fuzz::corpus(
        "ssd",
        &[b"<a/>", b"<ssd:Component name=\"x\"/>", outside],
        parse,
    );
    assert!(
        parse(BOUND_SSD.as_bytes()),
        "the seed with bindings is valid"
    );
    let seeds: [&[u8]; 2] = [seed.as_bytes(), BOUND_SSD.as_bytes()];
    let accepted = fuzz::run("ssd", 0x55d0, &seeds, CASES, parse);
    assert!(accepted > 100, "only {accepted} mutated SSDs were valid");
}

/// An SSD whose components bind parameters inline (Real, Integer, Boolean, String) and
/// from an `.ssv` file, with the coupling annotation and a component's process annotation.
const BOUND_SSD: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" xmlns:tbi="urn:tbi:coupling" version="1.0" name="s">
  <ssd:System name="s">
    <ssd:Elements>
      <ssd:Component name="a" source="resources/a.fmu" type="application/x-fmu-sharedlibrary">
        <ssd:ParameterBindings>
          <ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet version="1.0" name="p"><ssv:Parameters>
            <ssv:Parameter name="k"><ssv:Real value="2.5"/></ssv:Parameter>
            <ssv:Parameter name="n"><ssv:Integer value="3"/></ssv:Parameter>
            <ssv:Parameter name="on"><ssv:Boolean value="true"/></ssv:Parameter>
            <ssv:Parameter name="label"><ssv:String value="left"/></ssv:Parameter>
          </ssv:Parameters></ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding>
          <ssd:ParameterBinding source="resources/a.ssv"/>
        </ssd:ParameterBindings>
        <ssd:Annotations><ssc:Annotation type="org.tbi.process"><tbi:Process in_process="true"/></ssc:Annotation></ssd:Annotations>
      </ssd:Component>
      <ssd:Component name="b" source="resources/b.fmu"/>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="a" startConnector="y" endElement="b" endConnector="u"/>
      <ssd:Connection startElement="b" startConnector="y" endElement="a" endConnector="u"/>
    </ssd:Connections>
    <ssd:Annotations><ssc:Annotation type="org.tbi.coupling"><tbi:Coupling step_size="0.01" scheme="implicit" rtol="1e-9"><tbi:Output name="a.y" element="a" connector="y"/></tbi:Coupling></ssc:Annotation></ssd:Annotations>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="1"/>
</ssd:SystemStructureDescription>
"#;

#[test]
fn parameter_values_ssv() {
    let seed = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="p">
  <ssv:Parameters>
    <ssv:Parameter name="k"><ssv:Real value="3"/></ssv:Parameter>
    <ssv:Parameter name="n"><ssv:Integer value="-2"/></ssv:Parameter>
    <ssv:Parameter name="on"><ssv:Boolean value="false"/></ssv:Parameter>
    <ssv:Parameter name="label"><ssv:String value="x"/></ssv:Parameter>
  </ssv:Parameters>
</ssv:ParameterSet>
"#;
    let parse = |b: &[u8]| tbi_ssp::parse_ssv(&text(b), "fuzz.ssv").is_ok();
    assert!(parse(seed.as_bytes()), "the seed is valid");
    fuzz::corpus("ssv", &[b"<a/>", b"hostname\n"], parse);
    let accepted = fuzz::run("ssv", 0x55d1, &[seed.as_bytes()], CASES, parse);
    assert!(accepted > 100, "only {accepted} mutated SSVs were valid");
}
