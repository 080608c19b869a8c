//! `tbi simulate` on an FMU built outside the project (the C oscillator in tests/c-fmu)
//! against `fmpy simulate` (FMPy 0.3.32) on the same FMU: same header, same rows, values
//! equal to 1e-9.
//!
//! The FMPy venv comes from tests/python/setup-venv.sh; if it cannot be created the tests
//! fail, unless TBI_SKIP_PYTHON=1 is set, in which case only the tbi side runs (and is
//! still checked for its own invariants, the free responses against their closed form).

mod fmu_support;

use fmu_support::*;
use std::path::Path;
use tbi_tests::fmpy::{self, fmpy};
use tbi_tests::{assert_text_csv_match, run, tbi_in, text, TextCsv};

/// Run both tools on `fmu` and compare. `tbi_args` / `fmpy_args` are the extra options
/// in each tool's spelling. Returns tbi's CSV.
fn compare(fmu: &Path, tbi_args: &[&str], fmpy_args: &[&str]) -> TextCsv {
    let dir = fmu.parent().unwrap();
    let tbi_out = dir.join("tbi_out.csv");
    let mut args = vec![
        "simulate",
        fmu.to_str().unwrap(),
        "--output",
        tbi_out.to_str().unwrap(),
    ];
    args.extend_from_slice(tbi_args);
    let out = tbi_in(dir, &args);
    assert!(
        out.status.success(),
        "tbi {args:?} failed:\n{}",
        text(&out.stderr)
    );
    let ours = TextCsv::read(&tbi_out);
    if let Some(venv) = fmpy::venv() {
        let fmpy_out = dir.join("fmpy_out.csv");
        let mut args = vec![
            fmu.to_str().unwrap(),
            "--output-file",
            fmpy_out.to_str().unwrap(),
        ];
        args.extend_from_slice(fmpy_args);
        let out = run(fmpy(venv).arg("simulate").args(&args).current_dir(dir));
        assert!(
            out.status.success(),
            "fmpy simulate {args:?} failed:\n{}{}",
            text(&out.stdout),
            text(&out.stderr)
        );
        let theirs = TextCsv::read(&fmpy_out);
        // tbi's CSV first, FMPy's second: numbers equal to 1e-9 (relative to max(1, |FMPy|))
        assert_text_csv_match(&ours, &theirs, 1e-9);
        // Both run the same binary with the same communication points, so even the text
        // (number formatting included) is the same.
        assert_eq!(
            std::fs::read_to_string(&tbi_out).unwrap(),
            std::fs::read_to_string(&fmpy_out).unwrap(),
            "the CSV files differ in their text"
        );
    }
    ours
}

fn times(csv: &TextCsv) -> Vec<f64> {
    csv.rows.iter().map(|r| r[0].parse().unwrap()).collect()
}

/// The unforced oscillator of tests/c-fmu/oscillator.c, `m x'' + d x' + k x = 0`, released
/// at rest from `x0` (the FMU starts from v = 0): underdamped, so with ωn = √(k/m),
/// ζ = d / (2√(k m)), σ = ζ ωn and ωd = ωn √(1 − ζ²):
/// `x(t) = x0 e^{−σt} (cos ωd t + σ/ωd sin ωd t)` and
/// `v(t) = −x0 (ωn²/ωd) e^{−σt} sin ωd t`.
struct FreeResponse {
    m: f64,
    k: f64,
    d: f64,
    x0: f64,
}

impl FreeResponse {
    /// (x(t), v(t)).
    fn at(&self, t: f64) -> (f64, f64) {
        let wn = (self.k / self.m).sqrt();
        let zeta = self.d / (2.0 * (self.k * self.m).sqrt());
        assert!(zeta < 1.0, "underdamped");
        let sigma = zeta * wn;
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        let (s, c) = (wd * t).sin_cos();
        let e = (-sigma * t).exp();
        (
            self.x0 * e * (c + sigma / wd * s),
            -self.x0 * wn * wn / wd * e * s,
        )
    }
}

/// Bounds of |x − x(t)| (m) and |v − v(t)| (m/s) over every row of a free run.
///
/// The FMU integrates with classical RK4 on a 1 ms grid (h). Its error here is RK4's phase
/// lag, not round-off: ωn t (ωn h)⁴ / 120 radians after t, so |x − x(t)| grows like
/// |x0| e^{−σt} ωn t (ωn h)⁴ / 120 and |v − v(t)| like ωn times that (4.4e-13 m and
/// 2.6e-12 m at t = 3 s for the two runs below, measured 3.8e-13 m and 2.3e-12 m; a Python
/// replica of the C integrator gives the measured values to within 5 %). Each test's bounds
/// are about twice the errors measured once over its 301 rows.
struct Tolerance {
    x: f64,
    v: f64,
}

/// Asserts every row of a free run's CSV (`time,x,v,steps,moving_right`, a row at the start
/// and after each DoStep) against the closed form: x and v within `tol`, the step counter
/// equal to the row number, and `moving_right` ⇔ v > 0 (against the sign of the closed form
/// too where |v(t)| is clear of the tolerance).
fn assert_free_response(csv: &TextCsv, osc: &FreeResponse, tol: Tolerance) {
    assert_eq!(
        csv.header,
        "\"time\",\"x\",\"v\",\"steps\",\"moving_right\""
    );
    let (mut ex, mut ev) = (0.0_f64, 0.0_f64);
    for (i, r) in csv.rows.iter().enumerate() {
        let num = |j: usize| -> f64 {
            r[j].parse()
                .unwrap_or_else(|e| panic!("row {i}, column {j}: {:?}: {e}", r[j]))
        };
        let (t, x, v) = (num(0), num(1), num(2));
        let (xe, ve) = osc.at(t);
        ex = ex.max((x - xe).abs());
        ev = ev.max((v - ve).abs());
        assert!(
            (x - xe).abs() <= tol.x,
            "row {i}, t = {t}: x = {x}, closed form {xe} (difference {:e})",
            x - xe
        );
        assert!(
            (v - ve).abs() <= tol.v,
            "row {i}, t = {t}: v = {v}, closed form {ve} (difference {:e})",
            v - ve
        );
        assert_eq!(r[3], i.to_string(), "row {i}: steps");
        let moving_right = match r[4].as_str() {
            "True" => true,
            "False" => false,
            other => panic!("row {i}: moving_right = {other:?}"),
        };
        assert_eq!(
            moving_right,
            v > 0.0,
            "row {i}, t = {t}: moving_right, v = {v}"
        );
        if ve.abs() > 10.0 * tol.v {
            assert_eq!(moving_right, ve > 0.0, "row {i}, t = {t}: v(t) = {ve}");
        }
    }
    println!(
        "max |x − x(t)| = {ex:e}, max |v − v(t)| = {ev:e} over {} rows",
        csv.rows.len()
    );
}

#[test]
fn defaults_match_fmpy() {
    let fmu = build_fmu(&Variant::new("Oscillator"));
    let csv = compare(&fmu, &[], &[]);
    // outputs grouped by type: Real (x, v), Integer (steps), Boolean (moving_right)
    assert_eq!(
        csv.header,
        "\"time\",\"x\",\"v\",\"steps\",\"moving_right\""
    );
    // DefaultExperiment: 0 to 3 s in steps of 0.01 s, a row at the start and after each step
    assert_eq!(csv.rows.len(), 301);
    assert_eq!(csv.rows[0][0], "0.0");
    assert_eq!(csv.rows[1][0], "0.01");
    assert_eq!(csv.rows[300][0], "3.0");
    assert_eq!(csv.rows[300][3], "300");
    // x(0) = x0 = 1, then the free oscillation of m = 1, k = 4, d = 0.4 (ωn = 2 rad/s,
    // ζ = 0.1; x(3) = 0.505106, v(3) = 0.339950) in every row
    assert_eq!(csv.rows[0][1], "1.0");
    assert_free_response(
        &csv,
        &FreeResponse {
            m: 1.0,
            k: 4.0,
            d: 0.4,
            x0: 1.0,
        },
        // measured: 3.8e-13 m, 8.7e-13 m/s
        Tolerance { x: 8e-13, v: 2e-12 },
    );
    assert!(csv.rows.iter().any(|r| r[4] == "True") && csv.rows.iter().any(|r| r[4] == "False"));
}

#[test]
fn step_size_from_fmpy_rule_without_default_experiment() {
    let variant = Variant::new("NoExperiment").replace(
        "<DefaultExperiment startTime=\"0\" stopTime=\"3\" stepSize=\"0.01\"/>",
        "",
    );
    let csv = compare(&build_fmu(&variant), &[], &[]);
    // stop = start + 1; auto_interval(1) = 0.002 → 500 steps
    let t = times(&csv);
    assert_eq!(t.len(), 501);
    assert_eq!(csv.rows[1][0], "0.002");
    assert_eq!(*t.last().unwrap(), 1.0);
}

#[test]
fn default_step_is_doubled_to_at_most_1000_steps() {
    let fmu = build_fmu(&Variant::new("LongRun"));
    let csv = compare(&fmu, &["--stop-time", "30"], &["--stop-time", "30"]);
    // 0.01 → 0.02 → 0.04: 750 steps
    assert_eq!(csv.rows.len(), 751);
    assert_eq!(csv.rows[1][0], "0.04");
}

#[test]
fn explicit_times_and_step() {
    let fmu = build_fmu(&Variant::new("Explicit"));
    let csv = compare(
        &fmu,
        &[
            "--start-time",
            "0.5",
            "--stop-time",
            "2.1",
            "--step-size",
            "0.025",
        ],
        &[
            "--start-time",
            "0.5",
            "--stop-time",
            "2.1",
            "--output-interval",
            "0.025",
        ],
    );
    let t = times(&csv);
    assert_eq!(t[0], 0.5);
    assert_eq!(*t.last().unwrap(), 2.1);
    assert_eq!(t.len(), 65);
}

#[test]
fn last_partial_step_is_skipped_without_variable_step_size() {
    let variant = Variant::new("FixedStep").replace(
        "canHandleVariableCommunicationStepSize=\"true\"",
        "canHandleVariableCommunicationStepSize=\"false\"",
    );
    let csv = compare(
        &build_fmu(&variant),
        &["--stop-time", "1", "--step-size", "0.3"],
        &["--stop-time", "1", "--output-interval", "0.3"],
    );
    // 0, 0.3, 0.6, 0.9 (a step to 1.2 would pass the stop time)
    assert_eq!(times(&csv).len(), 4);
}

#[test]
fn start_values_match_fmpy() {
    let fmu = build_fmu(&Variant::new("Parameters"));
    let csv = compare(
        &fmu,
        &[
            "--set",
            "k=9",
            "--set",
            "d=0.1",
            "--set",
            "x0=-0.5",
            "--set",
            "label=abc",
        ],
        &[
            "--start-values",
            "k",
            "9",
            "d",
            "0.1",
            "x0",
            "-0.5",
            "label",
            "abc",
        ],
    );
    assert_eq!(csv.rows[0][1], "-0.5");
    // the whole run is the free oscillation with the set parameters (m stays 1): ωn = 3 rad/s,
    // ζ = 1/60, released from -0.5 over the default experiment, 0–3 s
    assert_eq!(csv.rows.len(), 301);
    assert_free_response(
        &csv,
        &FreeResponse {
            m: 1.0,
            k: 9.0,
            d: 0.1,
            x0: -0.5,
        },
        // measured: 2.3e-12 m, 7.4e-12 m/s (ωn = 3 and lighter damping: larger than the
        // defaults')
        Tolerance {
            x: 5e-12,
            v: 1.5e-11,
        },
    );
}

#[test]
fn inputs_with_ramp_and_jump_match_fmpy() {
    let fmu = build_fmu(&Variant::new("Forced").gain(Some("2.5")));
    let dir = fmu.parent().unwrap();
    let input = dir.join("input.csv");
    // a ramp, a jump at t = 1.2345 (not on the step grid: variable steps end on it), a
    // hold after the table ends; d is tunable and changes at t = 2
    std::fs::write(
        &input,
        "\"time\",\"F\",\"d\"\n0,0,0.4\n1,3,0.4\n1.2345,3,0.4\n1.2345,-2,0.4\n2,-2,1.5\n2.5,1,1.5\n",
    )
    .unwrap();
    let input = input.to_str().unwrap();
    let csv = compare(&fmu, &["--input", input], &["--input-file", input]);
    let t = times(&csv);
    assert!(
        t.contains(&1.2345),
        "the jump time is a communication point"
    );
    assert!(t.contains(&2.0));
    // the forced response differs from the free one
    let free = compare(&build_fmu(&Variant::new("Free")), &[], &[]);
    assert_ne!(csv.rows.last().unwrap()[1], free.rows.last().unwrap()[1]);
}

#[test]
fn termination_requested_by_the_fmu_matches_fmpy() {
    let variant = Variant::new("EndOfData")
        .define("-DDISCARD_AT=1.005")
        .define("-DDISCARD_TERMINATE=1");
    let fmu = build_fmu(&variant);
    let csv = compare(&fmu, &[], &[]);
    let t = times(&csv);
    // steps up to 1.0, then the step to 1.01 ends at 1.005 with a last row
    assert_eq!(t.len(), 102);
    assert_eq!(*t.last().unwrap(), 1.005);
}

#[test]
fn default_output_file_and_standard_output() {
    let fmu = build_fmu(&Variant::new("Named"));
    let dir = fmu.parent().unwrap();
    let run = tbi_in(
        dir,
        &["simulate", "Named.fmu", "--stop-time", "0.1", "--quiet"],
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert!(
        run.stderr.is_empty(),
        "--quiet prints nothing: {}",
        text(&run.stderr)
    );
    let csv = TextCsv::read(&dir.join("Named_out.csv"));
    assert_eq!(csv.rows.len(), 11);

    let run = tbi_in(
        dir,
        &[
            "simulate",
            "Named.fmu",
            "--stop-time",
            "0.1",
            "--output",
            "-",
        ],
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let stdout = text(&run.stdout);
    assert_eq!(
        stdout,
        std::fs::read_to_string(dir.join("Named_out.csv")).unwrap()
    );
    // without --quiet the FMU's log messages are shown, with instance name and category
    assert!(
        text(&run.stderr)
            .contains("[oscillator] fmi2OK [logEvents] initialized: x=1 gain=1 label=osc"),
        "{}",
        text(&run.stderr)
    );
}

#[test]
fn unusable_arguments_are_refused() {
    let fmu = build_fmu(&Variant::new("Args"));
    let dir = fmu.parent().unwrap();
    std::fs::write(dir.join("in.csv"), "time,F,Fq\n0,1,2\n1,1,2\n").unwrap();
    let cases: [(&[&str], &str); 8] = [
        (&["--set", "nope=1"], "Args.fmu: --set nope: the FMU has no variable \"nope\""),
        (&["--set", "k"], "--set k: expected NAME=VALUE"),
        (&["--set", "k=abc"], "--set k=abc: \"abc\" is not a finite number"),
        (&["--set", "k=nan"], "--set k=nan: \"nan\" is not a finite number"),
        (&["--set", "k=1e999"], "--set k=1e999: \"1e999\" is not a finite number"),
        (&["--input", "in.csv"], "in.csv: column \"Fq\" names no input or tunable parameter of the FMU"),
        (&["--set", "x=1"], "--set x: the variable cannot be set before or during initialisation (causality=\"output\", variability=\"continuous\")"),
        (&["--stop-time", "-1"], "Args.fmu: the stop time -1 is not after the start time 0"),
    ];
    for (extra, expected) in cases {
        let mut args = vec!["simulate", "Args.fmu", "--output", "x.csv"];
        args.extend_from_slice(extra);
        let run = tbi_in(dir, &args);
        assert_eq!(run.status.code(), Some(1), "{args:?}");
        assert!(
            text(&run.stderr).contains(expected),
            "{args:?}: {}",
            text(&run.stderr)
        );
    }
}

/// `tbi simulate` runs the FMU in process: an FMU that segfaults ends it, but every row
/// computed before is in `<output>.partial`, and no result file pretends to be whole.
#[test]
fn rows_before_a_crash_stay_in_the_partial_file() {
    let fmu = build_fmu(
        &Variant::new("Crash")
            .define("-DCRASH_AT=0.505")
            .define("-DCRASH_HOW=1"),
    );
    let dir = fmu.parent().unwrap();
    let run = tbi_in(
        dir,
        &[
            "simulate",
            "Crash.fmu",
            "--step-size",
            "0.01",
            "--output",
            "o.csv",
            "--in-process",
        ],
    );
    // in process, the crash ends tbi itself: each row was flushed as it ended
    assert!(!run.status.success());
    assert!(!dir.join("o.csv").exists());
    let rows = std::fs::read_to_string(dir.join("o.csv.partial")).unwrap();
    // the header and the rows from t = 0 through the steps before the crash (t > 0.5)
    let last: f64 = rows
        .lines()
        .last()
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        rows.lines().count() >= 52 && (0.5..0.52).contains(&last),
        "{rows}"
    );
}
