//! FMI 3.0 FMUs from outside the project: three of the Modelica Association's Reference
//! FMUs (tests/reference-fmus, built here with the C compiler):
//!
//! * BouncingBall (state events inside `fmi3DoStep`), VanDerPol and Feedthrough (Float64,
//!   Int32 and Boolean, driven by an input file) under `tbi simulate`, in a worker and in
//!   process, equal `fmpy simulate` of the same FMU to 1e-9 of each column's largest value
//!   (integers and booleans exactly);
//! * an FMU of another exporter, pythonfmu3 from PyPI (tests/python/lag_fmu3.py, built by
//!   the test; its library takes the Python C API from the process, which loads Python
//!   for it), under `tbi simulate` gives `fmpy simulate`'s CSV to 1e-9;
//! * the FMI 3.0 VanDerPol driving the FMI 2.0 C oscillator (tests/c-fmu) in an SSD under
//!   `tbi cosim` with the implicit scheme (which saves and restores both FMUs' states)
//!   gives the bytes of the same system with VanDerPol built as FMI 2.0 from the same C code.

mod fmu_support;

use fmu_support::{build_fmu, Variant};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;
use tbi_tests::fmpy::{self, fmpy};
use tbi_tests::{repo_path, run_ok, scratch, tbi_command};

/// Build `model` of tests/reference-fmus as an FMI `version` FMU with the description
/// `xml` (a file of the model's folder); the .fmu.
fn build(model: &str, version: u8, xml: &str) -> PathBuf {
    let root = repo_path("tests/reference-fmus");
    let dir = scratch(&format!("reference-{model}-{version}"));
    let so = dir.join(format!("{model}.so"));
    let compiler = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let out = Command::new(&compiler)
        .args([
            "-shared",
            "-fPIC",
            "-O2",
            &format!("-DFMI_VERSION={version}"),
            "-DDISABLE_PREFIX",
        ])
        .arg("-I")
        .arg(root.join("include"))
        .arg("-I")
        .arg(root.join(model))
        .arg(root.join(format!("src/fmi{version}Functions.c")))
        .arg(root.join("src/cosimulation.c"))
        .arg(root.join(format!("{model}/model.c")))
        .arg("-o")
        .arg(&so)
        .arg("-lm")
        .output()
        .unwrap_or_else(|e| panic!("cannot run the C compiler {compiler}: {e}"));
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let platform = if version == 3 {
        "x86_64-linux"
    } else {
        "linux64"
    };
    let fmu = dir.join(format!("{model}.fmu"));
    let mut zip = zip::ZipWriter::new(std::fs::File::create(&fmu).unwrap());
    let options = zip::write::SimpleFileOptions::default();
    zip.start_file("modelDescription.xml", options).unwrap();
    zip.write_all(&std::fs::read(root.join(model).join(xml)).unwrap())
        .unwrap();
    zip.start_file(format!("binaries/{platform}/{model}.so"), options)
        .unwrap();
    zip.write_all(&std::fs::read(&so).unwrap()).unwrap();
    zip.finish().unwrap();
    fmu
}

/// The cells of a result CSV: its header and rows of texts.
fn cells(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let split = |l: &str| {
        l.split(',')
            .map(|c| c.trim().trim_matches('"').to_owned())
            .collect::<Vec<_>>()
    };
    let header = split(lines.next().expect("a header"));
    (header, lines.map(split).collect())
}

/// Asserts two result CSVs have the same columns and rows: numbers to 1e-9 of their
/// column's largest value, other cells (True/False) exactly.
fn assert_same_results(a: &Path, b: &Path, what: &str) {
    let ((ha, ra), (hb, rb)) = (cells(a), cells(b));
    assert_eq!(ha, hb, "{what}: columns");
    assert_eq!(ra.len(), rb.len(), "{what}: rows");
    assert!(ra.len() > 10, "{what}: {} rows", ra.len());
    for (c, name) in ha.iter().enumerate() {
        let number = |s: &str| s.parse::<f64>().ok();
        let largest = ra
            .iter()
            .filter_map(|r| number(&r[c]))
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        for (x, y) in ra.iter().zip(&rb) {
            match (number(&x[c]), number(&y[c])) {
                (Some(p), Some(q)) => assert!(
                    (p - q).abs() <= 1e-9 * largest,
                    "{what}: {name} at t = {}: {p} against {q}",
                    x[0]
                ),
                _ => assert_eq!(x[c], y[c], "{what}: {name} at t = {}", x[0]),
            }
        }
    }
}

#[test]
fn reference_fmus_under_tbi_simulate_equal_fmpy() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    let input = scratch("reference-feedthrough-input").join("input.csv");
    std::fs::write(
        &input,
        "\"time\",\"Float64_continuous_input\",\"Float64_discrete_input\",\"Int32_input\",\"Boolean_input\"\n\
         0,0,0,0,0\n0.5,1.5,2,3,1\n0.5,-1,2,-4,0\n1,2,5,7,1\n2,0.25,-3,9,0\n",
    )
    .unwrap();
    for (model, xml, extra) in [
        ("BouncingBall", "FMI3.xml", None),
        ("VanDerPol", "FMI3.xml", None),
        (
            "Feedthrough",
            "FMI3-Float64-Int32-Boolean.xml",
            Some(&input),
        ),
    ] {
        let fmu = build(model, 3, xml);
        let dir = fmu.parent().unwrap();
        let with_input = |c: &mut Command, flag: &str| {
            if let Some(i) = extra {
                c.arg(flag).arg(i);
            }
        };
        // the same communication step for both (FMPy 0.3.32 picks its own for FMI 3.0
        // rather than the DefaultExperiment's)
        let mut theirs = fmpy(venv);
        theirs
            .arg("simulate")
            .arg(&fmu)
            .args(["--output-interval", "0.01", "--output-file"])
            .arg(dir.join("fmpy.csv"));
        with_input(&mut theirs, "--input-file");
        run_ok(&mut theirs);
        for (label, isolation) in [("worker", None), ("in process", Some("--in-process"))] {
            let out = dir.join(format!("tbi-{}.csv", label.replace(' ', "-")));
            let mut ours = tbi_command();
            ours.arg("simulate")
                .arg(&fmu)
                .args(["--quiet", "--step-size", "0.01", "--output"])
                .arg(&out);
            ours.args(isolation);
            with_input(&mut ours, "--input");
            run_ok(&mut ours);
            assert_same_results(&dir.join("fmpy.csv"), &out, &format!("{model} ({label})"));
        }
    }
}

/// An SSD of `vdp` (VanDerPol) driving the C oscillator: `V.x0 → O.F`.
fn system(dir: &Path, vdp: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::copy(vdp, dir.join("vdp.fmu")).unwrap();
    std::fs::copy(build_fmu(&Variant::new("Osc")), dir.join("osc.fmu")).unwrap();
    let ssd = r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="vdp-osc">
  <ssd:System name="vdp-osc">
    <ssd:Elements>
      <ssd:Component name="V" type="application/x-fmu-sharedlibrary" source="vdp.fmu"/>
      <ssd:Component name="O" type="application/x-fmu-sharedlibrary" source="osc.fmu"/>
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="V" startConnector="x0" endElement="O" endConnector="F"/>
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="5"/>
</ssd:SystemStructureDescription>
"#;
    let path = dir.join("SystemStructure.ssd");
    std::fs::write(&path, ssd).unwrap();
    path
}

#[test]
fn an_fmi3_fmu_beside_an_fmi2_one_under_tbi_cosim() {
    let dir = scratch("reference-cosim");
    let three = system(&dir.join("three"), &build("VanDerPol", 3, "FMI3.xml"));
    let two = system(&dir.join("two"), &build("VanDerPol", 2, "FMI2.xml"));
    let cosim = |ssd: &Path, out: &str, extra: &[&str]| {
        let out = dir.join(out);
        run_ok(
            tbi_command()
                .arg("cosim")
                .arg(ssd)
                .args(["--quiet", "--step-size", "0.01", "--scheme", "implicit"])
                .args(["--record", "V.x0", "--record", "O.x", "--output"])
                .arg(&out)
                .args(extra),
        );
        std::fs::read(&out).unwrap()
    };
    let reference = cosim(&two, "two.csv", &[]);
    assert!(reference.len() > 10_000, "{} bytes", reference.len());
    assert!(
        cosim(&three, "three.csv", &[]) == reference,
        "FMI 3.0 VanDerPol differs"
    );
    assert!(
        cosim(&three, "three-in-process.csv", &["--in-process"]) == reference,
        "FMI 3.0 VanDerPol in process differs"
    );
}

#[test]
fn a_pythonfmu3_fmu_under_tbi_simulate_equals_fmpy() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    let dir = scratch("pythonfmu3");
    run_ok(
        Command::new(venv.join("bin/pythonfmu3"))
            .arg("build")
            .arg("-f")
            .arg(repo_path("tests/python/lag_fmu3.py"))
            .arg("--dest")
            .arg(&dir),
    );
    let fmu = dir.join("Lag.fmu");
    run_ok(
        fmpy(venv)
            .arg("simulate")
            .arg(&fmu)
            .args([
                "--stop-time",
                "2",
                "--output-interval",
                "0.01",
                "--output-file",
            ])
            .arg(dir.join("fmpy.csv")),
    );
    for (label, isolation) in [("worker", None), ("in process", Some("--in-process"))] {
        let out = dir.join(format!("tbi-{}.csv", label.replace(' ', "-")));
        run_ok(
            tbi_command()
                .arg("simulate")
                .arg(&fmu)
                .args([
                    "--quiet",
                    "--stop-time",
                    "2",
                    "--step-size",
                    "0.01",
                    "--output",
                ])
                .arg(&out)
                .args(isolation)
                .env("TBI_PYTHON", venv.join("bin/python")),
        );
        assert_same_results(
            &dir.join("fmpy.csv"),
            &out,
            &format!("pythonfmu3 ({label})"),
        );
    }
}
