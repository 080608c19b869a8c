//! The FMUs exported as FMI 3.0 Co-Simulation (`tbi export --fmi-version 3`), in FMPy
//! 0.3.32, the reference importer of FMI 3.0:
//!
//! * `fmpy validate` finds no problems, and the description is valid against the FMI 3.0
//!   schema FMPy ships (`fmi3ModelDescription.xsd`, checked with lxml);
//! * each FMU simulated alone by `fmpy simulate`, its inputs driven by the same input file,
//!   gives the same table as the FMI 2.0 export of the same scenario, to 1e-12 of each
//!   column's largest value (the same binary serves both standards);
//! * the FMU state survives `fmi3SerializeFMUState` → `fmi3DeserializeFMUState` →
//!   `fmi3SetFMUState` and the run continues bit for bit as the uninterrupted one.

mod common;

use common::scenarios;
use std::path::Path;
use std::sync::OnceLock;
use tbi_tests::fmpy::{self, fmpy, python};
use tbi_tests::fmu::{export, export_as, unpack, Export};
use tbi_tests::{repo_path, run, run_ok, text, Table};

/// The coach scenario and the turbulent crosswind (three FMUs), as FMI 2.0 and FMI 3.0.
fn exports() -> &'static [(Export, Export, &'static str)] {
    static E: OnceLock<Vec<(Export, Export, &'static str)>> = OnceLock::new();
    E.get_or_init(|| {
        [
            (scenarios::coach2(), "coach2"),
            (scenarios::coach2_windy(), "windy"),
        ]
        .into_iter()
        .map(|(toml, label)| {
            let two = export(&format!("fmi3-{label}-2"), &toml);
            let three = export_as(&format!("fmi3-{label}-3"), &toml, &["--fmi-version", "3"]);
            (two, three, label)
        })
        .collect()
    })
}

/// The FMUs of an export.
fn fmus(e: &Export) -> Vec<&Path> {
    let mut v = vec![e.bridge.as_path(), e.train.as_path()];
    v.extend(e.wind.as_deref());
    v
}

/// The XSD check of a description with lxml and FMPy's FMI 3.0 schema.
const SCHEMA_CHECK: &str = r#"
import os, sys, zipfile, fmpy
from lxml import etree
schema = etree.XMLSchema(file=os.path.join(os.path.dirname(fmpy.__file__), 'schema', 'fmi3', 'fmi3ModelDescription.xsd'))
root = etree.fromstring(zipfile.ZipFile(sys.argv[1]).read('modelDescription.xml'))
if not schema.validate(root):
    print('\n'.join(str(e) for e in schema.error_log))
    sys.exit(1)
print('valid', root.get('fmiVersion'))
"#;

#[test]
fn fmi3_exports_pass_fmpy_validate_and_the_schema() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    for (_, e, label) in exports() {
        assert_eq!(e.wind.is_some(), *label == "windy");
        for fmu in fmus(e) {
            let out = run(fmpy(venv).arg("validate").arg(fmu));
            let stdout = text(&out.stdout);
            assert!(
                out.status.success() && stdout.contains("No problems found"),
                "fmpy validate {}:\n{stdout}\n{}",
                fmu.display(),
                text(&out.stderr)
            );
            let out = run_ok(python(venv).args(["-c", SCHEMA_CHECK]).arg(fmu));
            assert_eq!(text(&out.stdout).trim(), "valid 3.0", "{}", fmu.display());
        }
    }
}

/// An input file for every Real input of `fmu` (FMI 2.0), rows every 10 ms to 0.2 s: a
/// wheelset moving from x = 5 m at 10 m/s, forces and moments around 10 kN, every other
/// input a millimetre-sized sine, each with its own phase.
fn input_file(fmu: &Path, csv: &Path) {
    let md = unpack(fmu, &fmu.with_extension("inputs")).md;
    let names: Vec<String> = md
        .model_variables
        .iter()
        .filter(|v| v.causality == model_description::Causality::Input)
        .map(|v| v.name.clone())
        .collect();
    let value = |name: &str, i: usize, t: f64| {
        let field = name.rsplit('.').next().unwrap_or(name);
        let wave = (20.0 * t + i as f64).sin();
        match field {
            "x" => 5.0 + 10.0 * t,
            "vx" => 10.0,
            f if f.starts_with("F_") || f.starts_with("M_") => 1e4 * (1.0 + 0.5 * wave),
            _ => 1e-3 * wave,
        }
    };
    let mut text = std::iter::once("\"time\"".to_string())
        .chain(names.iter().map(|n| format!("\"{n}\"")))
        .collect::<Vec<_>>()
        .join(",");
    text.push('\n');
    for k in 0..=20 {
        let t = k as f64 * 0.01;
        let row: Vec<String> = std::iter::once(format!("{t:?}"))
            .chain(
                names
                    .iter()
                    .enumerate()
                    .map(|(i, n)| format!("{:?}", value(n, i, t))),
            )
            .collect();
        text.push_str(&row.join(","));
        text.push('\n');
    }
    std::fs::write(csv, text).expect("write the input file");
}

#[test]
fn fmi3_exports_simulate_alone_as_the_fmi2_ones() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    for (two, three, label) in exports() {
        for (fmu2, fmu3) in fmus(two).into_iter().zip(fmus(three)) {
            let stem = fmu2.file_stem().unwrap().to_string_lossy().into_owned();
            let input = three.dir.join(format!("{stem}-input.csv"));
            input_file(fmu2, &input);
            let simulate = |fmu: &Path, csv: &Path| {
                run_ok(
                    fmpy(venv)
                        .arg("simulate")
                        .arg(fmu)
                        .args(["--stop-time", "0.2", "--output-interval", "0.002"])
                        .arg("--input-file")
                        .arg(&input)
                        .arg("--output-file")
                        .arg(csv),
                );
                Table::read(csv)
            };
            let a = simulate(fmu2, &two.dir.join(format!("{stem}-2.csv")));
            let b = simulate(fmu3, &three.dir.join(format!("{stem}-3.csv")));
            assert_eq!(a.columns, b.columns, "{label} {stem}");
            assert_eq!(a.rows.len(), 101, "{label} {stem}");
            assert_eq!(a.rows.len(), b.rows.len(), "{label} {stem}");
            let mut moving = 0;
            for (c, name) in a.columns.iter().enumerate() {
                let largest = (a.rows.iter()).map(|r| r[c].abs()).fold(0.0_f64, f64::max);
                let first = a.rows[0][c];
                moving += usize::from(a.rows.iter().any(|r| r[c] != first));
                for (ra, rb) in a.rows.iter().zip(&b.rows) {
                    assert!(
                        (ra[c] - rb[c]).abs() <= 1e-12 * largest,
                        "{label} {stem} {name} at t = {}: FMI 2.0 {} against FMI 3.0 {}",
                        ra[0],
                        ra[c],
                        rb[c]
                    );
                }
            }
            // the inputs move the outputs, so the comparison is not of constants
            assert!(
                moving > a.columns.len() / 2,
                "{label} {stem}: {moving} columns move"
            );
        }
    }
}

#[test]
fn fmi3_state_serializes_and_resumes_bit_for_bit() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    let (_, e, _) = &exports()[0];
    let script = repo_path("tests/python/fmi3_state.py");
    for fmu in fmus(e) {
        let out = run_ok(
            python(venv)
                .arg(&script)
                .arg(fmu)
                .args(["0.002", "50", "30"]),
        );
        let got: serde_json::Value =
            serde_json::from_str(text(&out.stdout).trim()).expect("one JSON line");
        let rows = |k: &str| got[k].as_array().expect("rows").clone();
        assert!(got["bytes"].as_u64().unwrap() > 0, "{got}");
        assert_eq!(rows("uninterrupted").len(), 30);
        assert_eq!(
            rows("resumed"),
            rows("uninterrupted"),
            "{}: the resumed run differs",
            fmu.display()
        );
        assert_ne!(
            rows("continued"),
            rows("uninterrupted"),
            "{}: the outputs do not move",
            fmu.display()
        );
    }
}
