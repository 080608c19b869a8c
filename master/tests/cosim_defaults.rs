//! `tbi cosim` with sane defaults on the exported default (Tsing Ma) system:
//!
//! * by default the system's own outputs (the probes by their scenario names and the car
//!   bodies) at the annotation's output interval: at most 10 MB for the whole 130 s run;
//! * `--record-all` every connected output;
//! * an explicit scheme's side-car has no acceleration and its defect relative, with the
//!   measure named, and the defect is printed;
//! * contradictory options exit 2 naming both; a wrong variable gets the close name; a
//!   result past 2 GiB is refused before any step.

use std::path::Path;
use tbi_tests::{read_json, require_fmu_libraries, run, run_ok, scratch, tbi_command, text};

fn header(csv: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(csv).unwrap();
    text.lines()
        .next()
        .unwrap()
        .split(',')
        .map(String::from)
        .collect()
}

#[test]
fn cosim_defaults_on_the_exported_default_system() {
    require_fmu_libraries();
    let dir = scratch("cosim-defaults");
    run_ok(
        tbi_command()
            .args(["export", "--out"])
            .arg(dir.join("fmus")),
    );
    let ssp = dir.join("fmus/system.ssp");
    // the whole run, default recording
    let out = dir.join("default.csv");
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&ssp)
            .args(["--quiet", "--output"])
            .arg(&out),
    );
    let bytes = std::fs::metadata(&out).unwrap().len();
    println!("default recording: {bytes} bytes");
    assert!(bytes <= 10_000_000, "{bytes} bytes");
    let names = header(&out);
    for want in [
        "time", "A.z", "A.z_dd", "mid.y", "D.theta", "veh1.a_z", "veh8.a_y",
    ] {
        assert!(names.iter().any(|n| n == want), "{want} in {names:?}");
    }
    assert!(
        !names.iter().any(|n| n.starts_with("train.ws[")),
        "{names:?}"
    );
    let rows = std::fs::read_to_string(&out).unwrap().lines().count() - 1;
    // 65 059 steps of 2 ms, a row every 25 steps (50 ms), the first and the last
    assert_eq!(rows, 65_059 / 25 + 2, "rows");
    let side = read_json(&dir.join("default.csv.json"));
    assert_eq!(side["recorded"], "the system's outputs");
    assert_eq!(side["acceleration"], "iqn-ils");
    // every connected output with --record-all (a short run)
    let all = dir.join("all.csv");
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&ssp)
            .args(["--quiet", "--record-all", "--stop-time", "0.1", "--output"])
            .arg(&all),
    );
    let names = header(&all);
    assert!(names.iter().any(|n| n == "train.ws[1].F_z"), "{names:?}");
    assert!(names.iter().any(|n| n == "bridge.ws[32].z"), "{names:?}");
    assert!(!names.iter().any(|n| n == "A.z"), "{names:?}");
    // Jacobi: no acceleration, the defect relative and printed
    let jacobi = dir.join("jacobi.csv");
    let r = run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&ssp)
            .args([
                "--quiet",
                "--scheme",
                "jacobi",
                "--stop-time",
                "5",
                "--output",
            ])
            .arg(&jacobi),
    );
    let side = read_json(&dir.join("jacobi.csv.json"));
    assert!(side["acceleration"].is_null(), "{side}");
    let relative = side["max_residual_relative"].as_f64().unwrap();
    let tolerances = side["max_residual_in_tolerances"].as_f64().unwrap();
    assert!((relative - tolerances * 1e-10).abs() <= 1e-12 * relative.abs().max(1.0));
    assert!(side["residual_measure"].as_str().unwrap().contains("rtol"));
    let said = text(&r.stderr);
    assert!(
        said.contains("jacobi scheme: interface defect up to"),
        "{said}"
    );
    assert!(said.contains("use --scheme implicit"), "{said}");
    // contradictory options: exit 2 naming both
    let r = run(tbi_command()
        .arg("cosim")
        .arg(&ssp)
        .args(["--scheme", "jacobi", "--acceleration", "newton", "--output"])
        .arg(dir.join("x.csv")));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--acceleration newton") && err.contains("--scheme jacobi"),
        "{err}"
    );
    assert!(!dir.join("x.csv").exists());
    // a misspelled variable: the close name
    let r = run(tbi_command()
        .arg("cosim")
        .arg(&ssp)
        .args(["--record", "bridge.probe[1].zz", "--output"])
        .arg(dir.join("y.csv")));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(err.contains("did you mean \"probe[1].z\"?"), "{err}");
    // past 2 GiB: refused before any step, naming the estimate
    let r = run(tbi_command()
        .arg("cosim")
        .arg(&ssp)
        .args([
            "--record-all",
            "--stop-time",
            "500",
            "--output-interval",
            "0.002",
            "--output",
        ])
        .arg(dir.join("big.csv")));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("MiB") && err.contains("--allow-large"),
        "{err}"
    );
    assert!(!dir.join("big.csv").exists());
}

/// Every option of `tbi cosim` has help text, and those with defaults name them.
#[test]
fn every_cosim_option_has_help() {
    let r = run_ok(tbi_command().args(["cosim", "--help"]));
    let help = text(&r.stdout);
    for option in [
        "--rtol",
        "--atol",
        "--max-iterations",
        "--scheme",
        "--acceleration",
        "--output-interval",
        "--record-all",
        "--allow-large",
    ] {
        let line = help
            .lines()
            .skip_while(|l| !l.trim_start().starts_with(option))
            .take(4)
            .collect::<Vec<_>>()
            .join(" ");
        assert!(line.split_whitespace().count() > 3, "{option}: {line}");
    }
    for default in ["1e-10", "1e-12", "50"] {
        assert!(help.contains(default), "{default}");
    }
}

/// `python3 -m zipfile -e ARCHIVE DIR`: an archive unpacked (the machine's Python).
fn unpack(archive: &Path, into: &Path) {
    run_ok(
        std::process::Command::new("python3")
            .args(["-m", "zipfile", "-e"])
            .arg(archive)
            .arg(into),
    );
}

/// Outputs never destroy inputs or fake results: an `--output` (or its side-car) that is
/// the system, a component's FMU or a parameter file is refused before any work; a run that
/// fails after a good one leaves the good CSV and side-car as they were, its rows in
/// `<output>.partial` and its failure in `<output>.partial.json`; `tbi simulate` refuses to
/// write over its FMU or its `--input`.
#[test]
fn outputs_never_replace_inputs_or_earlier_results() {
    require_fmu_libraries();
    let dir = scratch("cosim-outputs");
    run_ok(
        tbi_command()
            .args(["export", "--out"])
            .arg(dir.join("fmus")),
    );
    let ssp = dir.join("fmus/system.ssp");
    // an unpacked system with a parameter file bound to the train
    let open = dir.join("open");
    unpack(&ssp, &open);
    std::fs::write(
        open.join("speed.ssv"),
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="speed">
  <ssv:Parameters><ssv:Parameter name="speed"><ssv:Real value="19.444444444444443"/></ssv:Parameter></ssv:Parameters>
</ssv:ParameterSet>
"#,
    )
    .unwrap();
    let ssd = open.join("SystemStructure.ssd");
    let written = std::fs::read_to_string(&ssd).unwrap();
    let component = r#"<ssd:Component name="train" type="application/x-fmu-sharedlibrary" source="resources/train.fmu">"#;
    assert!(written.contains(component));
    std::fs::write(
        &ssd,
        written.replace(
            component,
            &format!(r#"{component}<ssd:ParameterBindings><ssd:ParameterBinding source="speed.ssv"/></ssd:ParameterBindings>"#),
        ),
    )
    .unwrap();
    let before = |p: &Path| std::fs::read(p).unwrap();
    for (system, output, what) in [
        (&ssp, ssp.clone(), "the system"),
        (&ssd, ssd.clone(), "the system"),
        (
            &ssd,
            open.join("resources/bridge.fmu"),
            "the FMU of component \"bridge\"",
        ),
        (
            &ssd,
            open.join("speed.ssv"),
            "a parameter file of component \"train\"",
        ),
        // the side-car of "speed" would be speed.json: write the CSV as the .ssv's stem
        (
            &ssd,
            open.join("resources/train.fmu"),
            "the FMU of component \"train\"",
        ),
    ] {
        let kept = before(&output);
        let r = run(tbi_command()
            .arg("cosim")
            .arg(system)
            .args(["--quiet", "--stop-time", "0.1", "--output"])
            .arg(&output));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{}: {err}", output.display());
        assert!(
            err.contains(what) && err.contains("choose another --output"),
            "{err}"
        );
        assert_eq!(before(&output), kept, "{} is untouched", output.display());
    }
    // the unpacked system with its parameter file runs
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&ssd)
            .args(["--quiet", "--stop-time", "0.1", "--output"])
            .arg(dir.join("open.csv")),
    );
    // a good run, then a failing one into the same output
    let out = dir.join("out.csv");
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&ssp)
            .args(["--quiet", "--stop-time", "1", "--output"])
            .arg(&out),
    );
    let side = dir.join("out.csv.json");
    let (good, good_side) = (before(&out), before(&side));
    let r = run(tbi_command()
        .arg("cosim")
        .arg(&ssp)
        .args([
            "--quiet",
            "--stop-time",
            "5",
            "--acceleration",
            "constant",
            "--max-iterations",
            "2",
            "--output",
        ])
        .arg(&out));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("out.csv.partial") && err.contains("left as it was"),
        "{err}"
    );
    assert_eq!(before(&out), good, "the earlier CSV");
    assert_eq!(before(&side), good_side, "the earlier side-car");
    let partial = std::fs::read_to_string(dir.join("out.csv.partial")).unwrap();
    assert!(partial.starts_with("time,"), "{partial}");
    let failure = read_json(&dir.join("out.csv.partial.json"));
    assert_eq!(failure["status"], "failed");
    assert!(failure["error"]
        .as_str()
        .unwrap()
        .contains("did not converge"));
    // tbi simulate: not over its FMU or its --input
    let fmu = dir.join("fmus/bridge.fmu");
    let kept = before(&fmu);
    let r = run(tbi_command()
        .arg("simulate")
        .arg(&fmu)
        .arg("--output")
        .arg(&fmu));
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    assert!(text(&r.stderr).contains("would replace the FMU"));
    assert_eq!(before(&fmu), kept);
    let input = dir.join("input.csv");
    std::fs::write(&input, "time,ws[1].F_z\n0,0\n1,0\n").unwrap();
    let r = run(tbi_command()
        .arg("simulate")
        .arg(&fmu)
        .args(["--stop-time", "0.01", "--input"])
        .arg(&input)
        .arg("--output")
        .arg(&input));
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    assert!(text(&r.stderr).contains("would replace the --input file"));
}
