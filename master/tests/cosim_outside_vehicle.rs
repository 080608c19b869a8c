//! A vehicle FMU from outside, coupled by `tbi cosim` to the bridge FMU.
//!
//! The vehicle is tests/c-fmu/sprung_mass.c: one axle, a mass on a spring and a damper over a
//! massless wheel on the rail, FMI 2.0 Co-Simulation with state get/set, written in C and
//! sharing no code with the project's crates, built here with `cc`. Its inputs are the rail
//! motion under the wheelset and its outputs the wheelset's position, speed and contact
//! forces, with the bridge FMU's names and units, so an SSD wires it to the bridge FMU
//! exported from the Yang–Yau scenario exactly as `tbi export` wires the train FMU.
//!
//! * Implicit (Aitken, and Newton with finite-difference Jacobians, the C FMU declaring no
//!   dependencies): the result equals the monolithic Yang–Yau solution to 1e-8 in mid-span
//!   deflection and vehicle acceleration (of each column's largest magnitude).
//! * Explicit Jacobi: equals a plain Jacobi loop over FMPy's `FMU2Slave` on the same FMUs
//!   (tests/python/jacobi_loop.py, same initialisation and recording order) to 1e-12, and
//!   converges to the monolithic solution at first order in the step.

mod fmu_support;

use fmu_support::{build_fmu, Variant};
use std::path::{Path, PathBuf};
use tbi_tests::fmpy::{python, venv};
use tbi_tests::{repo_path, run, run_ok, scratch, tbi_command, text, Table};

const RAIL: [&str; 9] = [
    "y", "theta", "z", "y_d", "theta_d", "z_d", "y_dd", "theta_dd", "z_dd",
];
const WHEEL: [&str; 5] = ["x", "vx", "F_y", "M_x", "F_z"];
/// The scenario's step and duration (bridge 25 m at 100 km/h plus 1 s free vibration).
const H: f64 = 0.0005;
const STOP: f64 = 1.9;

fn yang_yau() -> PathBuf {
    repo_path("master/tests/data/yang-yau.toml")
}

/// A folder with bridge.fmu (exported from Yang–Yau), vehicle.fmu (the C sprung mass) and a
/// SystemStructure.ssd wiring them with the coupling options `coupling`; returns the .ssd.
fn system(dir: &Path, coupling: &str) -> PathBuf {
    let sys = dir.join("system");
    if !sys.join("bridge.fmu").is_file() {
        run_ok(
            tbi_command()
                .arg("export")
                .arg(yang_yau())
                .arg("--out")
                .arg(dir.join("fmus")),
        );
        std::fs::create_dir_all(&sys).unwrap();
        std::fs::copy(dir.join("fmus/bridge.fmu"), sys.join("bridge.fmu")).unwrap();
        let vehicle = build_fmu(&Variant::model("sprung_mass", "sprung_mass"));
        std::fs::copy(vehicle, sys.join("vehicle.fmu")).unwrap();
    }
    let connector = |name: &str, kind: &str| {
        format!("<ssd:Connector name=\"ws[1].{name}\" kind=\"{kind}\"><ssc:Real/></ssd:Connector>")
    };
    let connectors = |inputs: &[&str], outputs: &[&str]| -> String {
        let ins = inputs.iter().map(|n| connector(n, "input"));
        let outs = outputs.iter().map(|n| connector(n, "output"));
        ins.chain(outs).collect::<Vec<_>>().join("\n          ")
    };
    let connection = |from: &str, to: &str, name: &str| {
        format!(
            "<ssd:Connection startElement=\"{from}\" startConnector=\"ws[1].{name}\" \
             endElement=\"{to}\" endConnector=\"ws[1].{name}\"/>"
        )
    };
    let connections: Vec<String> = WHEEL
        .iter()
        .map(|n| connection("vehicle", "bridge", n))
        .chain(RAIL.iter().map(|n| connection("bridge", "vehicle", n)))
        .collect();
    let ssd = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" xmlns:tbi="urn:tbi:coupling" version="1.0" name="outside-vehicle">
  <ssd:System name="outside-vehicle">
    <ssd:Elements>
      <ssd:Component name="bridge" type="application/x-fmu-sharedlibrary" source="bridge.fmu">
        <ssd:Connectors>
          {bridge}
        </ssd:Connectors>
      </ssd:Component>
      <ssd:Component name="vehicle" type="application/x-fmu-sharedlibrary" source="vehicle.fmu">
        <ssd:Connectors>
          {vehicle}
        </ssd:Connectors>
      </ssd:Component>
    </ssd:Elements>
    <ssd:Connections>
      {connections}
    </ssd:Connections>
    <ssd:Annotations>
      <ssc:Annotation type="org.tbi.coupling">
        <tbi:Coupling step_size="{H}" {coupling}/>
      </ssc:Annotation>
    </ssd:Annotations>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="{STOP}"/>
</ssd:SystemStructureDescription>
"#,
        bridge = connectors(&WHEEL, &RAIL),
        vehicle = connectors(&RAIL, &WHEEL),
        connections = connections.join("\n      "),
    );
    let path = sys.join("SystemStructure.ssd");
    std::fs::write(&path, ssd).unwrap();
    path
}

fn cosim(ssd: &Path, out: &Path, extra: &[&str]) -> Table {
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(ssd)
            .args(["--quiet", "--output"])
            .arg(out)
            .args(extra),
    );
    Table::read(out)
}

fn column<'a>(t: &'a Table, name: &str) -> impl Iterator<Item = f64> + 'a {
    let j = t
        .columns
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", t.columns));
    t.rows.iter().map(move |r| r[j])
}

/// Largest |a − b| relative to the largest |b| (absolute for a column of zeros).
fn worst(a: impl Iterator<Item = f64>, b: impl Iterator<Item = f64>) -> f64 {
    let (mut diff, mut scale) = (0.0_f64, 0.0_f64);
    for (x, y) in a.zip(b) {
        diff = diff.max((x - y).abs());
        scale = scale.max(y.abs());
    }
    if scale > 0.0 {
        diff / scale
    } else {
        diff
    }
}

fn monolithic(dir: &Path) -> Table {
    run_ok(
        tbi_command()
            .arg("run")
            .arg(yang_yau())
            .args(["--solver", "monolithic", "--quiet", "--out"])
            .arg(dir.join("mono")),
    );
    Table::read(&dir.join("mono/history.csv"))
}

#[test]
fn implicit_with_the_outside_vehicle_equals_the_monolithic_solution() {
    let dir = scratch("outside-vehicle-implicit");
    let mono = monolithic(&dir);
    // Aitken, and Newton with finite-difference Jacobians through rollback (the C FMU
    // declares no dependencies and no directional derivatives)
    for acceleration in ["aitken", "newton"] {
        let ssd = system(
            &dir,
            &format!("scheme=\"implicit\" acceleration=\"{acceleration}\" rtol=\"1e-12\""),
        );
        let co = cosim(
            &ssd,
            &dir.join(format!("implicit-{acceleration}.csv")),
            &[
                "--record",
                "bridge.probe[1].z",
                "--record",
                "vehicle.veh[1].a_z",
            ],
        );
        assert_eq!(
            co.rows.len(),
            mono.rows.len(),
            "a row per step of the scenario"
        );
        assert!(worst(column(&co, "time"), column(&mono, "time_s")) < 1e-12);
        let deflection = worst(
            column(&co, "bridge.probe[1].z"),
            column(&mono, "mid.vertical_displacement_m"),
        );
        let acceleration_error = worst(
            column(&co, "vehicle.veh[1].a_z"),
            column(&mono, "veh1.vertical_acceleration_m_s2"),
        );
        let force = worst(
            column(&co, "vehicle.ws[1].F_z"),
            column(&mono, "ws1.vertical_force_n"),
        );
        println!("implicit ({acceleration}) vs monolithic: deflection {deflection:.2e}, vehicle acceleration {acceleration_error:.2e}, wheel force {force:.2e}");
        assert!(
            deflection <= 1e-8,
            "{acceleration}: deflection {deflection:e}"
        );
        assert!(
            acceleration_error <= 1e-8,
            "{acceleration}: vehicle acceleration {acceleration_error:e}"
        );
        assert!(force <= 1e-8, "{acceleration}: wheel force {force:e}");
        // the response is the real one: the mass crossing the span deflects it by millimetres
        let peak = column(&co, "bridge.probe[1].z").fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(peak > 1e-3, "mid-span deflection {peak} m");
    }
}

#[test]
fn jacobi_with_the_outside_vehicle_equals_a_plain_fmpy_loop_and_is_first_order() {
    let dir = scratch("outside-vehicle-jacobi");
    let ssd = system(&dir, "scheme=\"jacobi\"");
    let ours = cosim(&ssd, &dir.join("jacobi.csv"), &[]);

    if let Some(venv) = venv() {
        let reference = dir.join("fmpy-jacobi.csv");
        let out = run(python(venv)
            .arg(repo_path("tests/python/jacobi_loop.py"))
            .arg(&ssd)
            .args([
                "--step-size",
                &H.to_string(),
                "--stop-time",
                &STOP.to_string(),
            ])
            .arg("--output")
            .arg(&reference));
        assert!(
            out.status.success(),
            "jacobi_loop.py failed:\n{}\n{}",
            text(&out.stdout),
            text(&out.stderr)
        );
        let theirs = Table::read(&reference);
        assert_eq!(ours.columns, theirs.columns);
        assert_eq!(ours.rows.len(), theirs.rows.len());
        let mut largest = (0.0_f64, String::new());
        for name in &ours.columns {
            let w = worst(column(&ours, name), column(&theirs, name));
            if w > largest.0 {
                largest = (w, name.clone());
            }
        }
        println!(
            "tbi jacobi vs FMPy loop: {:.2e} in {}",
            largest.0, largest.1
        );
        assert!(
            largest.0 <= 1e-12,
            "{} differs by {:e}",
            largest.1,
            largest.0
        );
    }

    // first order: the coupling error (against the implicit solution of the same system at
    // the same step, which equals the monolithic one) halves with the step
    let mut errors = Vec::new();
    for h in [1e-3, 5e-4, 2.5e-4] {
        let step = ["--step-size".to_owned(), h.to_string()];
        let step: Vec<&str> = step.iter().map(String::as_str).collect();
        let exact = cosim(
            &system(
                &dir,
                "scheme=\"implicit\" acceleration=\"aitken\" rtol=\"1e-12\"",
            ),
            &dir.join(format!("implicit-{h}.csv")),
            &step,
        );
        let jacobi = cosim(
            &system(&dir, "scheme=\"jacobi\""),
            &dir.join(format!("jacobi-{h}.csv")),
            &step,
        );
        errors.push(worst(
            column(&jacobi, "vehicle.ws[1].F_z"),
            column(&exact, "vehicle.ws[1].F_z"),
        ));
    }
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        println!(
            "jacobi coupling errors {:?}, observed order {order:.2}",
            errors
                .iter()
                .map(|e| format!("{e:.3e}"))
                .collect::<Vec<_>>()
        );
        assert!((0.8..=1.3).contains(&order), "observed order {order}");
    }
    assert!(errors[2] > 1e-6, "the splitting error must be visible");
}

/// `tests/c-fmu/build-fmu.sh`, the documented way to build the outside vehicle FMU, gives an
/// FMU that `tbi simulate` runs exactly as the tests' own build of the same C source.
#[test]
fn the_build_script_makes_the_outside_vehicle_fmu() {
    let dir = scratch("build-fmu-script");
    std::fs::create_dir_all(&dir).unwrap();
    let fmu = dir.join("vehicle.fmu");
    run_ok(
        std::process::Command::new("bash")
            .arg(repo_path("tests/c-fmu/build-fmu.sh"))
            .arg("sprung_mass")
            .arg(&fmu),
    );
    let ours = build_fmu(&Variant::model("sprung_mass", "sprung_mass"));
    let simulate = |f: &Path, out: &Path| {
        run_ok(
            tbi_command()
                .arg("simulate")
                .arg(f)
                .args(["--stop-time", "0.5", "--output"])
                .arg(out),
        );
        std::fs::read_to_string(out).unwrap()
    };
    let a = simulate(&fmu, &dir.join("script.csv"));
    let b = simulate(&ours, &dir.join("tests.csv"));
    assert!(a.lines().count() > 10);
    assert_eq!(a, b);
}
