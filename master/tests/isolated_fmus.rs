//! `tbi cosim` and `tbi simulate` with each FMU in a worker process (the default): for
//! `cosim`, two C oscillators (tests/c-fmu/oscillator.c) forcing each other, `A.x → B.F`
//! and `B.x → A.F`; for `simulate`, oscillator B alone.
//!
//! * Isolated and in process give the same CSV, byte for byte: `cosim` with the implicit
//!   scheme (the rollback states stay in the workers) and with Jacobi, and `simulate`.
//! * An FMU that segfaults, aborts or calls `exit(0)` in `fmi2DoStep`, or segfaults in
//!   `fmi2Instantiate`, fails the run with exit code 1 and a message naming the component,
//!   the call and the time; the rows so far stay in `<output>.partial`, no result is
//!   written, and the worker's unpacked folders are removed.
//! * A call that hangs is ended by `--fmu-timeout`, and by SIGTERM without one, within 2 s.
//! * A component whose SSD annotation says `in_process="true"` runs in the master's
//!   process (its crash takes the master with it), the others still in workers.

mod fmu_support;

use fmu_support::{build_fmu, Variant};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use tbi_tests::{run, run_ok, scratch, tbi_command, text};

/// The system of oscillators A and B in `dir`, B built with `defines`.
fn system(dir: &Path, defines: &[&str]) -> PathBuf {
    system_with(dir, defines, "")
}

/// [`system`], with `b_annotation` inside B's `<ssd:Component>`.
fn system_with(dir: &Path, defines: &[&str], b_annotation: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::copy(build_fmu(&Variant::new("OscA")), dir.join("a.fmu")).unwrap();
    let b = defines
        .iter()
        .fold(Variant::new("OscB"), |v, d| v.define(d));
    std::fs::copy(build_fmu(&b), dir.join("b.fmu")).unwrap();
    let component = |name: &str, source: &str, inner: &str| {
        format!(
            r#"<ssd:Component name="{name}" type="application/x-fmu-sharedlibrary" source="{source}">{inner}</ssd:Component>"#
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
        a = component("A", "a.fmu", ""),
        b = component("B", "b.fmu", b_annotation),
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

/// `tbi simulate b.fmu --step-size 0.01 --quiet ARGS --output OUT` in the folder of
/// [`system`] (`b.fmu` beside the SSD), with the same temporary folder.
fn simulate(ssd: &Path, out: &Path, args: &[&str]) -> std::process::Command {
    let dir = ssd.parent().unwrap();
    let tmp = dir.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let mut c = tbi_command();
    c.arg("simulate")
        .arg(dir.join("b.fmu"))
        .args(["--step-size", "0.01", "--stop-time", "1", "--quiet"])
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
fn isolated_simulate_gives_the_in_process_result_bit_for_bit() {
    let dir = scratch("isolated-simulate-same");
    let ssd = system(&dir, &[]);
    let (iso, inp) = (dir.join("isolated.csv"), dir.join("in-process.csv"));
    run_ok(&mut simulate(&ssd, &iso, &[]));
    run_ok(&mut simulate(&ssd, &inp, &["--in-process"]));
    let (a, b) = (std::fs::read(&iso).unwrap(), std::fs::read(&inp).unwrap());
    assert!(a.len() > 1000, "{} bytes", a.len());
    assert!(a == b, "the isolated run differs from the in-process run");
    assert!(left_over(&ssd).is_empty(), "{:?}", left_over(&ssd));
}

/// (CRASH_HOW, what the message says of the worker's end).
const CRASHES: [(&str, &str); 3] = [
    ("1", "was killed by signal 11 (SIGSEGV)"),
    ("2", "was killed by signal 6 (SIGABRT)"),
    ("3", "exited with status 0"),
];

#[test]
fn a_crashing_fmu_fails_the_run_and_keeps_the_rows() {
    for ((how, said), command) in CRASHES.iter().flat_map(|c| [(c, "cosim"), (c, "simulate")]) {
        let dir = scratch(&format!("isolated-crash-{how}-{command}"));
        let ssd = system(&dir, &["-DCRASH_AT=0.505", &format!("-DCRASH_HOW={how}")]);
        let out = dir.join("out.csv");
        let r = run(&mut if command == "cosim" {
            cosim(&ssd, &out, &["--scheme", "jacobi"])
        } else {
            simulate(&ssd, &out, &[])
        });
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{how} {command}: {err}");
        // tbi simulate names the FMU file
        let who = if command == "cosim" {
            "component \"B\""
        } else {
            "b.fmu"
        };
        let expected =
            format!("{who}: the FMU's worker process {said}, during fmi2DoStep at t = 0.5");
        assert!(
            err.contains(&expected),
            "{how} {command}: expected {expected:?} in {err}"
        );
        assert!(!out.exists(), "{how} {command}: a result was written");
        let rows = std::fs::read_to_string(partial(&out)).unwrap();
        assert!(
            rows.lines().count() >= 50,
            "{how} {command}: {} lines",
            rows.lines().count()
        );
        assert!(
            left_over(&ssd).is_empty(),
            "{how} {command}: {:?}",
            left_over(&ssd)
        );
    }
}

#[test]
fn a_crash_in_instantiate_fails_the_run_cleanly() {
    for command in ["cosim", "simulate"] {
        let dir = scratch(&format!("isolated-instantiate-{command}"));
        let ssd = system(&dir, &["-DCRASH_IN_INSTANTIATE"]);
        let out = dir.join("out.csv");
        let r = run(&mut if command == "cosim" {
            cosim(&ssd, &out, &[])
        } else {
            simulate(&ssd, &out, &[])
        });
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{command}: {err}");
        assert!(
            err.contains("the FMU's worker process was killed by signal 11 (SIGSEGV), during loading and fmi2Instantiate"),
            "{command}: {err}"
        );
        assert!(!out.exists() && !partial(&out).exists(), "{command}");
        assert!(
            left_over(&ssd).is_empty(),
            "{command}: {:?}",
            left_over(&ssd)
        );
    }
}

#[test]
fn a_component_annotated_in_process_runs_in_the_master() {
    let annotation = |value: &str| {
        format!(
            r#"<ssd:Annotations><ssc:Annotation type="org.tbi.process"><tbi:Process xmlns:tbi="urn:tbi:coupling" in_process="{value}"/></ssc:Annotation></ssd:Annotations>"#
        )
    };
    let crash = ["-DCRASH_AT=0.505", "-DCRASH_HOW=2"];
    // isolated by the annotation's "false" as by default: a clean failure
    let dir = scratch("annotated-isolated");
    let ssd = system_with(&dir, &crash, &annotation("false"));
    let r = run(&mut cosim(
        &ssd,
        &dir.join("o.csv"),
        &["--scheme", "jacobi"],
    ));
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    // in the master's process: abort() in B ends tbi itself
    let dir = scratch("annotated-in-process");
    let ssd = system_with(&dir, &crash, &annotation("true"));
    let r = run(&mut cosim(
        &ssd,
        &dir.join("o.csv"),
        &["--scheme", "jacobi"],
    ));
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(r.status.signal(), Some(6), "{:?}", r.status);
    // and without the crash, the same result as all isolated
    let dir = scratch("annotated-same");
    let mixed = system_with(&dir.join("mixed"), &[], &annotation("true"));
    let plain = system(&dir.join("plain"), &[]);
    let (a, b) = (dir.join("mixed.csv"), dir.join("plain.csv"));
    run_ok(&mut cosim(&mixed, &a, &[]));
    run_ok(&mut cosim(&plain, &b, &[]));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    // a value other than true or false is refused, naming the component and the line
    let bad = system_with(&dir.join("bad"), &[], &annotation("yes"));
    let r = run(&mut cosim(&bad, &dir.join("bad.csv"), &[]));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("SystemStructure.ssd:6: component \"B\": <tbi:Process in_process=\"yes\">: expected \"true\" or \"false\""),
        "{err}"
    );
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
    let child = cosim(&ssd, &out, &["--scheme", "jacobi"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // the steps to t = 0.5 take far less than 3 s; then B's call hangs
    let (status, err) = terminate_after(child, Duration::from_secs(3));
    assert_eq!(status.code(), Some(130));
    let rows = std::fs::read_to_string(partial(&out)).unwrap();
    assert!(rows.lines().count() >= 50, "{} lines", rows.lines().count());
    assert!(err.contains("interrupted by a signal"), "{err}");
    assert!(!out.exists());
    assert!(left_over(&ssd).is_empty(), "{:?}", left_over(&ssd));
}

#[test]
fn a_hanging_simulate_is_ended_by_the_timeout_and_by_a_signal() {
    let dir = scratch("isolated-simulate-hang");
    let ssd = system(&dir, &["-DCRASH_AT=0.505", "-DCRASH_HOW=4"]);
    let out = dir.join("timeout.csv");
    let r = run(&mut simulate(&ssd, &out, &["--fmu-timeout", "2"]));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("b.fmu: the call did not return within 2 s (--fmu-timeout); the FMU's worker was ended, during fmi2DoStep at t = 0.5"),
        "{err}"
    );
    assert!(
        std::fs::read_to_string(partial(&out))
            .unwrap()
            .lines()
            .count()
            >= 50
    );
    assert!(!out.exists());
    assert!(left_over(&ssd).is_empty(), "{:?}", left_over(&ssd));
    let out = dir.join("signal.csv");
    let child = simulate(&ssd, &out, &[])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let (status, err) = terminate_after(child, Duration::from_secs(3));
    assert_eq!(status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted by a signal"), "{err}");
    assert!(
        std::fs::read_to_string(partial(&out))
            .unwrap()
            .lines()
            .count()
            >= 50
    );
    assert!(!out.exists());
    assert!(left_over(&ssd).is_empty(), "{:?}", left_over(&ssd));
}

/// Sends SIGTERM to `child` after `wait` and checks it ends within 2 s; its status and
/// standard error.
fn terminate_after(
    mut child: std::process::Child,
    wait: Duration,
) -> (std::process::ExitStatus, String) {
    std::thread::sleep(wait);
    let signalled = Instant::now();
    run_ok(std::process::Command::new("kill").args(["-TERM", &child.id().to_string()]));
    let deadline = Instant::now() + Duration::from_secs(10);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("tbi did not end after SIGTERM");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let took = signalled.elapsed();
    assert!(took < Duration::from_secs(2), "{took:?}");
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    (status, err)
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
