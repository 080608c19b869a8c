//! The EN 1991-2 dynamic design check as an engineer files it (`tbi sweep --trains`):
//!
//! * outputs sized for a sweep: a 1130-case HSLM-A check writes at most 100 MB, and its
//!   estimate before the run is within a factor 2 of what it writes; `--keep-histories`
//!   past the limit is refused before any run;
//! * one truth per number: `tbi run governing/<check>.toml` reproduces every governing
//!   value of `envelope.csv` to 1e-9;
//! * peaks found, not sampled: on a span with ζ = 0.5 % the refined 10 km/h grid finds the
//!   peak deck acceleration within 1 % of a 0.1 km/h grid's maximum;
//! * exit codes scripts can trust (3 a check FAILs, 0 all pass) and a closed pipe that
//!   ends the printing quietly;
//! * summaries that fit the model: no safety, comfort or car-body figures for moving forces;
//! * the report: rendered by headless Chromium without console messages, with the scenario's
//!   SHA-256 and every train's resonance speeds as markers (counted against f₁ D / i from
//!   the closed-form f₁ of the span and the standard's coach lengths).

use std::path::{Path, PathBuf};
use tbi_tests::{read_summary, run, run_checked, scratch, tbi_command, text};

/// A 20 m simply supported prestressed-concrete span (f₁ = π/(2L²) √(EI/m) = 6.4 Hz).
const SPAN_20: &str = r#"name = "span-20m"
[run]
speed_kmh = 300.0
dt_s = 0.001
solver = "monolithic"
free_vibration_s = 0.0
[bridge]
kind = "simply_supported"
span_m = 20.0
youngs_modulus_pa = 3.5e10
inertia_vertical_m4 = 0.9
mass_per_length_kg_m = 12000.0
modes = 3
damping = { rule = "en1991-2", structure = "prestressed_concrete" }
[train]
kind = "hslm_a"
name = "A1"
[track]
irregularity = "none"
[[probe]]
name = "mid"
x_m = 10.0
"#;

/// Coach lengths D of HSLM-A1 … A10, m (EN 1991-2 Table E.1).
const COACH_LENGTHS: [f64; 10] = [18.0, 19.0, 20.0, 21.0, 22.0, 23.0, 24.0, 25.0, 26.0, 27.0];

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The rows of envelope.csv as maps from column name to text.
fn envelope(path: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

fn num(row: &std::collections::HashMap<String, String>, key: &str) -> f64 {
    row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key}: {}", row[key]))
}

/// Bytes of every file below `dir`.
fn bytes_below(dir: &Path) -> u64 {
    let mut total = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let e = e.unwrap();
        let m = e.metadata().unwrap();
        total += if m.is_dir() {
            bytes_below(&e.path())
        } else {
            m.len()
        };
    }
    total
}

/// 1130 cases (10 trains × 113 speeds) with the default outputs: at most 100 MB in all,
/// the estimate printed before the run within a factor 2 of the bytes written; every
/// governing value reproduced by `tbi run` of its scenario file; `--keep-histories` refused.
#[test]
fn a_1130_case_check_fits_on_a_disk_and_its_governing_cases_reproduce() {
    let dir = scratch("design-1130");
    let s = write(&dir, "span.toml", SPAN_20);
    let out = dir.join("check");
    let o = run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--speeds", "140:420:2.5", "--trains", "hslm-a", "--out"])
            .arg(&out),
    );
    let said = text(&o.stdout);
    let rows = envelope(&out.join("envelope.csv"));
    let grid = rows.iter().filter(|r| r["point"] == "grid").count();
    assert_eq!(grid, 1130, "10 trains × 113 speeds");
    let written = bytes_below(&out);
    println!("{} cases wrote {written} bytes", rows.len());
    assert!(written <= 100_000_000, "{written} bytes");
    let estimate_mib: f64 = said
        .split("(about ")
        .nth(1)
        .and_then(|t| t.split(" MiB estimated").next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no estimate in {said}"));
    let estimate = estimate_mib * (1u64 << 20) as f64;
    let ratio = estimate / written as f64;
    println!("estimated {estimate:.0} bytes, ratio {ratio:.2}");
    assert!(
        (0.5..=2.0).contains(&ratio),
        "estimate {estimate} vs {written}"
    );
    // one truth per number: the governing rows name their checks
    for check in ["deck-acceleration", "deck-displacement"] {
        let named: Vec<_> = rows
            .iter()
            .filter(|r| r["governing"].split(';').any(|c| c == check))
            .collect();
        assert_eq!(named.len(), 1, "{check}");
    }
    let largest = |key: &str| {
        rows.iter()
            .map(|r| num(r, key))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    for (check, key, read) in [
        (
            "deck-acceleration",
            "deck_acceleration_max_m_s2",
            "vertical_acceleration_max_m_s2",
        ),
        (
            "deck-displacement",
            "deck_displacement_max_mm",
            "vertical_displacement_max_m",
        ),
    ] {
        let file = out.join("governing").join(format!("{check}.toml"));
        let run_out = dir.join(format!("run-{check}"));
        run_checked(
            tbi_command()
                .arg("run")
                .arg(&file)
                .args(["--quiet", "--out"])
                .arg(&run_out),
        );
        let mut got = read_summary(&run_out)["probes"]["mid"][read]
            .as_f64()
            .unwrap();
        if key.ends_with("_mm") {
            got *= 1e3;
        }
        let want = largest(key);
        assert!(
            (got / want - 1.0).abs() <= 1e-9,
            "{check}: tbi run {got} vs envelope {want}"
        );
        assert!(said.contains(&format!(
            "reproduce: tbi run {}",
            out.join("governing/deck-acceleration.toml").display()
        )));
    }
    // every history kept would pass the limit: refused before any case runs
    let r = run(tbi_command()
        .arg("sweep")
        .arg(&s)
        .args([
            "--speeds",
            "140:420:2.5",
            "--trains",
            "hslm-a",
            "--keep-histories",
            "--out",
        ])
        .arg(dir.join("all")));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("MiB") && err.contains("every history kept") && err.contains("--allow-large"),
        "{err}"
    );
    assert!(!dir.join("all/envelope.csv").exists());
}

/// With vehicles (a sprung mass under every axle) the car-body governing case reproduces too.
#[test]
fn the_car_body_governing_case_reproduces() {
    let dir = scratch("design-car-body");
    let text_ = SPAN_20.replace(
        "name = \"A1\"",
        "name = \"A1\"\nvehicle = { model = \"sprung_mass\", frequency_hz = 1.0, damping_ratio = 0.1, wheel_mass_kg = 2000.0 }",
    );
    let s = write(&dir, "span.toml", &text_);
    let out = dir.join("check");
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args([
                "--speeds",
                "300:400:20",
                "--trains",
                "A1,A4",
                "--comfort",
                "good",
                "--out",
            ])
            .arg(&out),
    );
    let rows = envelope(&out.join("envelope.csv"));
    let want = rows
        .iter()
        .map(|r| num(r, "car_body_acceleration_max_m_s2"))
        .fold(f64::NEG_INFINITY, f64::max);
    let run_out = dir.join("run");
    run_checked(
        tbi_command()
            .arg("run")
            .arg(out.join("governing/car-body-acceleration.toml"))
            .args(["--quiet", "--out"])
            .arg(&run_out),
    );
    let got = read_summary(&run_out)["vehicles"]["vertical_acceleration_max_m_s2"]
        .as_f64()
        .unwrap();
    assert!((got / want - 1.0).abs() <= 1e-9, "{got} vs {want}");
}

/// ζ = 0.5 %: the refined 10 km/h grid finds the peak within 1 % of a 0.1 km/h grid's.
#[test]
fn refinement_finds_a_narrow_peak() {
    let dir = scratch("design-refine");
    let light = SPAN_20.replace(
        "damping = { rule = \"en1991-2\", structure = \"prestressed_concrete\" }",
        "damping_ratio = 0.005",
    );
    let s = write(&dir, "span.toml", &light);
    let sweep = |speeds: &str, out: &str| {
        run_checked(
            tbi_command()
                .arg("sweep")
                .arg(&s)
                .args(["--speeds", speeds, "--trains", "A3", "--out"])
                .arg(dir.join(out)),
        );
        envelope(&dir.join(out).join("envelope.csv"))
    };
    let coarse = sweep("200:400:10", "coarse");
    let fine = sweep("200:400:0.1", "fine");
    let max = |rows: &[std::collections::HashMap<String, String>]| {
        rows.iter()
            .map(|r| num(r, "deck_acceleration_max_m_s2"))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let (found, reference) = (max(&coarse), max(&fine));
    let grid_only = coarse
        .iter()
        .filter(|r| r["point"] == "grid")
        .map(|r| num(r, "deck_acceleration_max_m_s2"))
        .fold(f64::NEG_INFINITY, f64::max);
    println!("10 km/h grid {grid_only}, refined {found}, 0.1 km/h grid {reference}");
    assert!(coarse.iter().any(|r| r["point"] == "refined"));
    assert!(
        (found / reference - 1.0).abs() <= 0.01,
        "refined {found} vs fine grid {reference}"
    );
}

/// Exit code 3 when a check FAILs, 0 when every check passes; a closed pipe ends quietly.
#[test]
fn exit_codes_and_a_closed_pipe() {
    let dir = scratch("design-exit");
    let failing = write(&dir, "fail.toml", SPAN_20);
    let r = run(tbi_command()
        .arg("sweep")
        .arg(&failing)
        .args(["--speeds", "300:420:20", "--trains", "A1", "--out"])
        .arg(dir.join("fail")));
    assert_eq!(r.status.code(), Some(3), "{}", text(&r.stderr));
    assert!(text(&r.stdout).contains("FAIL: deck vertical acceleration"));
    let stiff = SPAN_20
        .replace("inertia_vertical_m4 = 0.9", "inertia_vertical_m4 = 4.0")
        .replace(
            "mass_per_length_kg_m = 12000.0",
            "mass_per_length_kg_m = 20000.0",
        );
    let passing = write(&dir, "pass.toml", &stiff);
    let r = run(tbi_command()
        .arg("sweep")
        .arg(&passing)
        .args(["--speeds", "144:200:8", "--trains", "A1,A2", "--out"])
        .arg(dir.join("pass")));
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stdout));
    assert!(!text(&r.stdout).contains("FAIL"));
    // `tbi run … | head -1` with the pipe's status: tbi's own (A1 at its resonance speed
    // f₁ D = 412 km/h on the 20 m span FAILs the deck acceleration)
    for (file, speed, code) in [(&passing, 300.0, 0), (&failing, 412.3, 3)] {
        let r = run(std::process::Command::new("bash").arg("-c").arg(format!(
            "set -o pipefail; '{}' run '{}' --speed-kmh {speed} --quiet --out '{}' | head -1",
            tbi_tests::tbi().display(),
            file.display(),
            dir.join("piped").display()
        )));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(code), "{err}");
        assert!(
            !err.contains("panicked") && !err.contains("Broken pipe"),
            "{err}"
        );
        assert_eq!(text(&r.stdout).lines().count(), 1);
    }
}

/// Moving forces: no car bodies, wheel–rail safety or Sperling figures in summary.json or
/// the printed summary; the modes rule is reported.
#[test]
fn a_moving_force_summary_holds_what_the_model_gives() {
    let dir = scratch("design-forces");
    let s = write(&dir, "span.toml", SPAN_20);
    let o = run_checked(
        tbi_command()
            .arg("run")
            .arg(&s)
            .args(["--speed-kmh", "200", "--out"])
            .arg(dir.join("out")),
    );
    let said = text(&o.stdout);
    let summary = read_summary(&dir.join("out"));
    assert!(summary.get("vehicles").is_none(), "{summary}");
    assert!(summary.get("safety").is_none(), "{summary}");
    assert!(
        !said.contains("derail") && !said.contains("Sperling"),
        "{said}"
    );
    assert!(
        said.contains("car bodies: none modelled (moving forces)"),
        "{said}"
    );
    assert_eq!(summary["bridge"]["modes_rule"], "en1990");
    assert!(said.contains("modes_rule = \"en1990\""), "{said}");
    assert!(
        said.contains(" mm (mid)") && said.contains(" m/s² (mid)"),
        "{said}"
    );
}

/// The report renders in headless Chromium with no console message; its inputs hold the
/// scenario's SHA-256; every train's resonance markers are in the acceleration chart.
#[test]
fn the_report_an_engineer_files() {
    let dir = scratch("design-report");
    let s = write(&dir, "span.toml", SPAN_20);
    let (lo, hi) = (150.0, 420.0);
    run_checked(
        tbi_command()
            .arg("sweep")
            .arg(&s)
            .args(["--speeds", "150:420:10", "--trains", "hslm-a", "--out"])
            .arg(dir.join("check")),
    );
    let report = dir.join("check/report.html");
    let html = std::fs::read_to_string(&report).unwrap();
    tbi_tests::browser::assert_self_contained(&html);
    let sha = run(std::process::Command::new("sha256sum").arg(&s));
    let sha = text(&sha.stdout)
        .split_whitespace()
        .next()
        .unwrap()
        .to_string();
    assert!(html.contains(&format!("<td>{sha}</td>")), "SHA-256 {sha}");
    for needle in [
        "LM71",
        "Φ₂",
        "Φ₃",
        "φ''",
        "EN 1990 A2.4.4.2.3",
        "displacement (mm)",
    ] {
        assert!(html.contains(needle), "{needle}");
    }
    // the resonance markers, labelled train/i, in the first chart
    let (l, ei, m): (f64, f64, f64) = (20.0, 3.5e10 * 0.9, 12000.0);
    let f1 = std::f64::consts::PI / (2.0 * l * l) * (ei / m).sqrt();
    let first_chart = html.split("</svg>").next().unwrap();
    for (k, d) in COACH_LENGTHS.iter().enumerate() {
        let expected = (1..100)
            .map(|i| f1 * d * 3.6 / i as f64)
            .filter(|v| (lo..=hi).contains(v))
            .count();
        // "A1/" is not in "A10/": the train's labels alone
        let label = format!("A{}/", k + 1);
        let found = first_chart.matches(&label).count();
        assert_eq!(
            found,
            expected,
            "A{}: {found} markers, {expected} resonance speeds",
            k + 1
        );
        assert!(expected >= 1);
    }
    // headless Chromium: no console message; a screenshot among the test artifacts
    let artifacts = tbi_tests::paths::target_dir().join("test-artifacts");
    std::fs::create_dir_all(&artifacts).unwrap();
    let shot = artifacts.join("design-check-report.png");
    let _ = std::fs::remove_file(&shot);
    let out = tbi_tests::browser::open(
        &report,
        &dir.join("profile"),
        &[
            "--window-size=1100,4200".to_string(),
            format!("--screenshot={}", shot.display()),
        ],
    );
    let log = text(&out.stderr);
    assert!(out.status.success(), "chromium failed:\n{log}");
    assert!(!log.contains("CONSOLE"), "console messages:\n{log}");
    assert!(
        std::fs::metadata(&shot).unwrap().len() > 10_000,
        "{}",
        shot.display()
    );
}
