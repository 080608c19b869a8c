//! `tbi cosim` with each FMU in a worker process (the default): two C oscillators
//! (tests/c-fmu/oscillator.c) forcing each other, `A.x → B.F` and `B.x → A.F`.
//!
//! * Isolated and in process give the same CSV, byte for byte, with the implicit scheme
//!   (the rollback states stay in the workers) and with Jacobi.
//! * An FMU that segfaults, aborts or calls `exit(0)` in `fmi2DoStep` fails the run with
//!   exit code 1 and a message naming the component, the call and the time; the rows so far
//!   stay in `<output>.partial`, no result is written, and the worker's unpacked folders are
//!   removed.
//! * A call that hangs is ended by `--fmu-timeout`, and by SIGTERM without one, within 2 s.

mod fmu_support;

use fmu_support::{build_fmu, Variant};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use tbi_tests::{run, run_ok, scratch, tbi_command, text};

/// The system of oscillators A and B in `dir`, B built with `defines`.
fn system(dir: &Path, defines: &[&str]) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::copy(build_fmu(&Variant::new("OscA")), dir.join("a.fmu")).unwrap();
    let b = defines
        .iter()
        .fold(Variant::new("OscB"), |v, d| v.define(d));
    std::fs::copy(build_fmu(&b), dir.join("b.fmu")).unwrap();
    let component = |name: &str, source: &str| {
        format!(
            r#"<ssd:Component name="{name}" type="application/x-fmu-sharedlibrary" source="{source}"/>"#
        )
    };
    let ssd = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="pair">
  <ssd:System name="pair">
    <ssd:Elements>
      {a}
      {b}
    </ssd:Elements>
    <ssd:Connections>
      <ssd:Connection startElement="A" startConnector="x" endElement="B" endConnector="F"/>
      <ssd:Connection startElement="B" startConnector="x" endElement="A" endConnector="F"/>
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="1"/>
</ssd:SystemStructureDescription>
"#,
        a = component("A", "a.fmu"),
        b = component("B", "b.fmu"),
    );
    let path = dir.join("SystemStructure.ssd");
    std::fs::write(&path, ssd).unwrap();
    path
}

/// `tbi cosim SSD --step-size 0.01 --quiet ARGS --output OUT`, with a temporary folder of
/// its own (`dir/tmp`).
fn cosim(ssd: &Path, out: &Path, args: &[&str]) -> std::process::Command {
    let tmp = ssd.parent().unwrap().join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let mut c = tbi_command();
    c.arg("cosim")
        .arg(ssd)
        .args(["--step-size", "0.01", "--quiet", "--record", "A.v"])
        .args(args)
        .arg("--output")
        .arg(out)
        .env("TMPDIR", &tmp);
    c
}

/// The unpacked FMU folders left in the run's temporary folder.
fn left_over(ssd: &Path) -> Vec<String> {
    let tmp = ssd.parent().unwrap().join("tmp");
    std::fs::read_dir(tmp)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("tbi-fmu"))
        .collect()
}

fn partial(out: &Path) -> PathBuf {
    let mut p = out.as_os_str().to_owned();
    p.push(".partial");
    PathBuf::from(p)
}

#[test]
fn isolated_fmus_give_the_in_process_result_bit_for_bit() {
    let dir = scratch("isolated-same");
    let ssd = system(&dir, &[]);
    for scheme in ["implicit", "jacobi"] {
        let iso = dir.join(format!("{scheme}-isolated.csv"));
        let inp = dir.join(format!("{scheme}-in-process.csv"));
        run_ok(&mut cosim(&ssd, &iso, &["--scheme", scheme]));
        run_ok(&mut cosim(
            &ssd,
            &inp,
            &["--scheme", scheme, "--in-process"],
        ));
        let (a, b) = (std::fs::read(&iso).unwrap(), std::fs::read(&inp).unwrap());
        assert!(a.len() > 1000, "{scheme}: {} bytes", a.len());
        assert!(
            a == b,
            "{scheme}: the isolated run differs from the in-process run"
        );
        assert!(left_over(&ssd).is_empty(), "{:?}", left_over(&ssd));
    }
}

#[test]
fn a_crashing_fmu_fails_the_run_and_keeps_the_rows() {
    for (how, said) in [
        ("1", "was killed by signal 11 (SIGSEGV)"),
        ("2", "was killed by signal 6 (SIGABRT)"),
        ("3", "exited with status 0"),
    ] {
        let dir = scratch(&format!("isolated-crash-{how}"));
        let ssd = system(&dir, &["-DCRASH_AT=0.505", &format!("-DCRASH_HOW={how}")]);
        let out = dir.join("out.csv");
        let r = run(&mut cosim(&ssd, &out, &["--scheme", "jacobi"]));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{how}: {err}");
        let expected = format!(
            "component \"B\": the FMU's worker process {said}, during fmi2DoStep at t = 0.5"
        );
        assert!(
            err.contains(&expected),
            "{how}: expected {expected:?} in {err}"
        );
        assert!(!out.exists(), "{how}: a result was written");
        let rows = std::fs::read_to_string(partial(&out)).unwrap();
        assert!(
            rows.lines().count() >= 50,
            "{how}: {} lines",
            rows.lines().count()
        );
        assert!(left_over(&ssd).is_empty(), "{how}: {:?}", left_over(&ssd));
    }
}

#[test]
fn a_hanging_call_is_ended_by_the_timeout_and_by_a_signal() {
    let dir = scratch("isolated-hang");
    let ssd = system(&dir, &["-DCRASH_AT=0.505", "-DCRASH_HOW=4"]);
    let out = dir.join("timeout.csv");
    let started = Instant::now();
    let r = run(&mut cosim(
        &ssd,
        &out,
        &["--scheme", "jacobi", "--fmu-timeout", "1"],
    ));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("component \"B\": the call did not return within 1 s (--fmu-timeout); the FMU's worker was ended, during fmi2DoStep at t = 0.5"),
        "{err}"
    );
    assert!(started.elapsed() < Duration::from_secs(20));
    assert!(left_over(&ssd).is_empty(), "{:?}", left_over(&ssd));
    // no limit: SIGTERM ends the run while the call hangs
    let out = dir.join("signal.csv");
    let mut child = cosim(&ssd, &out, &["--scheme", "jacobi"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // the steps to t = 0.5 take far less than this; then B's call hangs
    std::thread::sleep(Duration::from_secs(3));
    let signalled = Instant::now();
    run_ok(std::process::Command::new("kill").args(["-TERM", &child.id().to_string()]));
    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("tbi cosim did not end after SIGTERM");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let took = signalled.elapsed();
    assert!(took < Duration::from_secs(2), "{took:?}");
    assert_eq!(status.code(), Some(130));
    let rows = std::fs::read_to_string(partial(&out)).unwrap();
    assert!(rows.lines().count() >= 50, "{} lines", rows.lines().count());
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert!(err.contains("interrupted by a signal"), "{err}");
    assert!(!out.exists());
    assert!(left_over(&ssd).is_empty(), "{:?}", left_over(&ssd));
}

#[test]
fn the_timeout_needs_workers() {
    let dir = scratch("isolated-options");
    let ssd = system(&dir, &[]);
    let out = dir.join("o.csv");
    for (args, needle) in [
        (
            &["--in-process", "--fmu-timeout", "1"][..],
            "--fmu-timeout needs the FMUs in worker processes",
        ),
        (
            &["--fmu-timeout", "0"][..],
            "--fmu-timeout 0: expected a positive number of seconds",
        ),
    ] {
        let r = run(&mut cosim(&ssd, &out, args));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{err}");
        assert!(err.contains(needle), "{err}");
    }
}
