//! `tbi run` on bad input: every case exits with status 1 and a message on stderr that names
//! the field (or the data file and line) and the offending value, and the file. Also the
//! output contract of a valid run (`summary.json` keys, `history.csv` columns), the issue's
//! example scenario, a `modal_file` bridge against the analytic one, and partial results of a
//! run that fails.

mod cli_support;

use cli_support::{data, data_text, number_after, run, Scenario};
use std::f64::consts::PI;
use std::path::Path;
use tbi_tests::{
    assert_same_table, read_summary, require_fmu_libraries, scratch, tbi_command, Table,
};

/// The issue's example (`tests/data/yang-yau.toml`, verbatim).
fn example() -> String {
    data_text("yang-yau.toml")
}

/// `text` with `from` replaced by `to`; `from` must occur exactly once.
fn edit(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "`{from}` in the scenario");
    text.replacen(from, to, 1)
}

/// Writes a mode file of the simply supported Yang–Yau span from the closed form:
/// `φ_n(x) = √(2/(μL)) sin(nπx/L)` (mass-normalised), `f_n = (nπ/L)² √(EI/μ) / 2π`, at
/// `nodes` equally spaced nodes, `modes` vertical modes.
fn write_modes_csv(path: &Path, nodes: usize, modes: usize) {
    let (l, e, i, mu) = (25.0_f64, 2.87e9_f64, 2.9_f64, 2303.0_f64);
    let mut s = String::from(
        "# simply supported span, closed-form modes\n\
         mode,label,frequency_hz,damping_ratio,x_m,lateral,vertical,torsion\n",
    );
    for n in 1..=modes {
        let k = n as f64 * PI / l;
        let f = k * k * (e * i / mu).sqrt() / (2.0 * PI);
        let sym = if n % 2 == 1 { "S" } else { "A" };
        for j in 0..nodes {
            let x = l * j as f64 / (nodes - 1) as f64;
            let phi = (2.0 / (mu * l)).sqrt() * (k * x).sin();
            s.push_str(&format!("{n},V-{sym}-{n},{f:?},,{x:?},0.0,{phi:?},0.0\n"));
        }
    }
    std::fs::write(path, s).unwrap();
}

/// The example with a `modal_file` bridge reading `modes_file` (relative to the scenario).
fn modal_file_scenario(modes_file: &str) -> Scenario {
    let mut s = Scenario::parse(&example());
    let b = s.0["bridge"].as_table_mut().unwrap();
    for k in [
        "span_m",
        "youngs_modulus_pa",
        "inertia_vertical_m4",
        "mass_per_length_kg_m",
    ] {
        b.remove(k).expect("key of the example");
    }
    s.set("bridge", "kind", "modal_file")
        .set("bridge", "path", modes_file)
}

/// One bad-input case: scenario text (None: the example), extra arguments, and the pieces
/// the message must contain (`{file}` stands for the scenario path).
struct Case {
    name: &'static str,
    scenario: Option<String>,
    args: Vec<String>,
    expect: Vec<String>,
}

fn case(name: &'static str, scenario: String, expect: &[&str]) -> Case {
    Case {
        name,
        scenario: Some(scenario),
        args: Vec::new(),
        expect: expect.iter().map(|s| s.to_string()).collect(),
    }
}

fn check_failure(
    what: &str,
    status: std::process::ExitStatus,
    stderr: &str,
    expect: &[String],
) -> Result<(), String> {
    let mut problems = Vec::new();
    if status.code() != Some(1) {
        problems.push(format!("exit status {status} (expected 1)"));
    }
    if !stderr.contains("tbi: error:") {
        problems.push("no `tbi: error:` line".into());
    }
    for e in expect {
        if !stderr.contains(e.as_str()) {
            problems.push(format!("message lacks `{e}`"));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{what}: {}\n    stderr: {}",
            problems.join("; "),
            stderr.trim()
        ))
    }
}

#[test]
fn cli_bad_input_is_refused_with_field_value_and_file() {
    let dir = scratch("bad-input");
    let ex = example();
    let modes_base = modal_file_scenario("modes.csv").text();
    let with_track = |file: &str| {
        edit(
            &ex,
            "irregularity = \"none\"",
            &format!("irregularity = {{ file = \"{file}\" }}"),
        )
    };
    let coach_train = |coach: &str| {
        edit(
            &ex,
            "kind = \"sprung_mass\"\naxles = [{ offset_m = 0.0, sprung_mass_kg = 5750.0, \
             stiffness_n_m = 1.595e6, damping_ns_m = 0.0 }]",
            &format!("kind = \"coach_27dof\"\npreset = \"xia2000\"\ncoach = {coach}"),
        )
    };

    // data files next to the scenarios
    write_modes_csv(&dir.join("modes.csv"), 11, 3);
    let good_modes = std::fs::read_to_string(dir.join("modes.csv")).unwrap();
    // line 5 is the third data row (line 1 comment, line 2 header)
    let mut lines: Vec<String> = good_modes.lines().map(str::to_string).collect();
    lines[4].push_str(",0.0");
    std::fs::write(dir.join("bad-columns.csv"), lines.join("\n")).unwrap();
    let mut lines: Vec<String> = good_modes.lines().map(str::to_string).collect();
    let cells: Vec<&str> = lines[6].split(',').collect();
    lines[6] = format!("{},abc,{}", cells[..6].join(","), cells[7]);
    std::fs::write(dir.join("bad-number.csv"), lines.join("\n")).unwrap();
    std::fs::write(
        dir.join("bad-track-columns.csv"),
        "# record\nx_m,lateral_m,vertical_m,cross_level_rad\n-10.0,0,0,0\n0.0,0,0\n40.0,0,0,0\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("bad-track-number.csv"),
        "x_m,lateral_m,vertical_m,cross_level_rad\n-10.0,0,0,0\n0.0,0,abc,0\n40.0,0,0,0\n",
    )
    .unwrap();

    let cases = vec![
        case(
            "unknown key at top level",
            edit(
                &ex,
                "name = \"yang-yau\"\n",
                "name = \"yang-yau\"\ncolour = \"red\"\n",
            ),
            &["{file}:2:", "unknown field", "colour"],
        ),
        case(
            "unknown key in [run]",
            edit(
                &ex,
                "dt_s = 0.0005\n",
                "dt_s = 0.0005\ntime_step_s = 0.001\n",
            ),
            &["{file}:5:", "unknown field", "time_step_s"],
        ),
        case(
            "unknown key in [bridge]",
            edit(&ex, "span_m = 25.0\n", "span_m = 25.0\nwidth_m = 12.0\n"),
            &["{file}:10:", "unknown field", "width_m"],
        ),
        case(
            "unknown key in an axle table",
            edit(
                &ex,
                "damping_ns_m = 0.0 }",
                "damping_ns_m = 0.0, mass_kg = 10.0 }",
            ),
            &[
                "{file}",
                "train.axles[0]",
                "mass_kg = 10.0",
                "unknown field `mass_kg`",
            ],
        ),
        case(
            "negative speed",
            edit(&ex, "speed_kmh = 100.0", "speed_kmh = -5.0"),
            &["{file}", "run.speed_kmh", "= -5"],
        ),
        case(
            "zero speed",
            edit(&ex, "speed_kmh = 100.0", "speed_kmh = 0.0"),
            &["{file}", "run.speed_kmh", "= 0"],
        ),
        case(
            "zero time step",
            edit(&ex, "dt_s = 0.0005", "dt_s = 0.0"),
            &["{file}", "run.dt_s", "= 0"],
        ),
        case(
            "negative time step",
            edit(&ex, "dt_s = 0.0005", "dt_s = -0.001"),
            &["{file}", "run.dt_s", "= -0.001"],
        ),
        case(
            "negative free vibration time",
            edit(&ex, "free_vibration_s = 1.0", "free_vibration_s = -1.0"),
            &["{file}", "run.free_vibration_s", "= -1"],
        ),
        case(
            "zero modes",
            edit(&ex, "modes = 20", "modes = 0"),
            &["{file}", "bridge.modes", "= 0"],
        ),
        case(
            "NaN Young's modulus",
            edit(&ex, "youngs_modulus_pa = 2.87e9", "youngs_modulus_pa = nan"),
            &["{file}", "bridge.youngs_modulus_pa", "NaN"],
        ),
        case(
            "negative mass per length",
            edit(
                &ex,
                "mass_per_length_kg_m = 2303.0",
                "mass_per_length_kg_m = -2303.0",
            ),
            &["{file}", "bridge.mass_per_length_kg_m", "-2303"],
        ),
        case(
            "NaN damping ratio",
            edit(&ex, "damping_ratio = 0.0", "damping_ratio = nan"),
            &["{file}", "bridge.damping_ratio", "NaN"],
        ),
        case(
            "NaN sprung mass",
            edit(&ex, "sprung_mass_kg = 5750.0", "sprung_mass_kg = nan"),
            &["{file}", "train.axles[0].sprung_mass_kg", "NaN"],
        ),
        case(
            "negative suspension stiffness",
            edit(&ex, "stiffness_n_m = 1.595e6", "stiffness_n_m = -1.595e6"),
            &["{file}", "train.axles[0].stiffness_n_m", "-1595000"],
        ),
        case(
            "negative coach parameter",
            coach_train("{ k1v_n_m = -1.0 }"),
            &["{file}", "train.coach.k1v_n_m", "-1"],
        ),
        case(
            "unknown coach parameter",
            coach_train("{ spring_n_m = 1.0 }"),
            &[
                "{file}",
                "train.coach.spring_n_m",
                "unknown coach parameter",
            ],
        ),
        case(
            "unknown bridge kind",
            edit(&ex, "kind = \"simply_supported\"", "kind = \"arch\""),
            &["{file}", "bridge.kind", "\"arch\""],
        ),
        case(
            "unknown train kind",
            edit(&ex, "kind = \"sprung_mass\"", "kind = \"maglev\""),
            &["{file}", "train.kind", "\"maglev\""],
        ),
        case(
            "unknown spectrum",
            edit(
                &ex,
                "irregularity = \"none\"",
                "irregularity = { spectrum = \"martian\", seed = 1 }",
            ),
            &["{file}:19:", "spectrum", "\"martian\""],
        ),
        case(
            "probe beyond the deck end",
            edit(&ex, "x_m = 12.5", "x_m = 30.0"),
            &[
                "{file}",
                "probe[0].x_m",
                "= 30",
                "\"mid\"",
                "off the bridge",
            ],
        ),
        case(
            "probe before the deck start",
            edit(&ex, "x_m = 12.5", "x_m = -1.0"),
            &["{file}", "probe[0].x_m", "= -1", "off the bridge"],
        ),
        case(
            "coupling relaxation out of range",
            format!("{ex}[coupling]\nrelaxation = 1.5\n"),
            &["{file}", "relaxation", "1.5"],
        ),
        case(
            "missing modes file",
            modes_base.replace("modes.csv", "no-such-modes.csv"),
            &["no-such-modes.csv", "cannot read modes file"],
        ),
        case(
            "modes file with a wrong column count",
            modes_base.replace("modes.csv", "bad-columns.csv"),
            &["bad-columns.csv:5:", "expected 8 columns, found 9"],
        ),
        case(
            "modes file with a non-number",
            modes_base.replace("modes.csv", "bad-number.csv"),
            &["bad-number.csv:7:", "vertical", "`abc` is not a number"],
        ),
        case(
            "missing track file",
            with_track("no-such-track.csv"),
            &["{file}", "track.irregularity", "no-such-track.csv"],
        ),
        case(
            "track file with a wrong column count",
            with_track("bad-track-columns.csv"),
            &[
                "{file}",
                "track.irregularity",
                "bad-track-columns.csv:4:",
                "column count",
            ],
        ),
        case(
            "track file with a non-number",
            with_track("bad-track-number.csv"),
            &[
                "{file}",
                "track.irregularity",
                "bad-track-number.csv:3:",
                "vertical_m",
                "`abc`",
            ],
        ),
        Case {
            name: "--speed-kmh -5",
            scenario: None,
            args: vec!["--speed-kmh".into(), "-5".into()],
            expect: vec![
                "--speed-kmh".into(),
                "{file}".into(),
                "run.speed_kmh".into(),
                "= -5".into(),
            ],
        },
        Case {
            name: "--speed-kmh 0",
            scenario: None,
            args: vec!["--speed-kmh".into(), "0".into()],
            expect: vec!["--speed-kmh".into(), "run.speed_kmh".into(), "= 0".into()],
        },
    ];

    let mut failures = Vec::new();
    for (k, c) in cases.iter().enumerate() {
        let path = match &c.scenario {
            Some(text) => {
                let p = dir.join(format!("bad-{k}.toml"));
                std::fs::write(&p, text).unwrap();
                p
            }
            None => data("yang-yau.toml"),
        };
        let out = dir.join(format!("out-{k}"));
        let extra: Vec<&str> = c.args.iter().map(String::as_str).collect();
        let r = run(&path, "monolithic", &out, &extra);
        let file = path.display().to_string();
        let expect: Vec<String> = c
            .expect
            .iter()
            .map(|e| e.replace("{file}", &file))
            .collect();
        if let Err(e) = check_failure(c.name, r.status, &r.stderr, &expect) {
            failures.push(e);
        }
    }

    // a scenario path that does not exist
    let missing = dir.join("no-such-scenario.toml");
    let o = tbi_tests::run(tbi_command().args([
        "run",
        missing.to_str().unwrap(),
        "--solver",
        "monolithic",
        "--quiet",
        "--out",
        dir.join("out-missing").to_str().unwrap(),
    ]));
    if let Err(e) = check_failure(
        "nonexistent scenario",
        o.status,
        &String::from_utf8_lossy(&o.stderr),
        &[missing.display().to_string(), "cannot read scenario".into()],
    ) {
        failures.push(e);
    }
    // an unknown solver name
    let o = tbi_tests::run(tbi_command().args([
        "run",
        data("yang-yau.toml").to_str().unwrap(),
        "--solver",
        "spectral",
        "--quiet",
        "--out",
        dir.join("out-solver").to_str().unwrap(),
    ]));
    if let Err(e) = check_failure(
        "unknown --solver",
        o.status,
        &String::from_utf8_lossy(&o.stderr),
        &["--solver".into(), "spectral".into()],
    ) {
        failures.push(e);
    }

    assert!(
        failures.is_empty(),
        "{} of {} bad-input cases are not reported as required:\n  {}",
        failures.len(),
        cases.len() + 2,
        failures.join("\n  ")
    );
}

/// The keys every `summary.json` must have.
fn check_summary_keys(s: &serde_json::Value, probes: &[&str]) {
    for key in ["speed_kmh", "dt_s", "wall_time_s"] {
        assert!(s[key].is_number(), "summary.{key}: {}", s[key]);
    }
    assert!(s["steps"].is_u64(), "summary.steps: {}", s["steps"]);
    assert!(s["solver"].is_string(), "summary.solver");
    for p in probes {
        for key in [
            "vertical_displacement_max_m",
            "vertical_acceleration_max_m_s2",
            "lateral_displacement_max_m",
            "lateral_acceleration_max_m_s2",
        ] {
            assert!(
                s["probes"][p][key].is_number(),
                "summary.probes.{p}.{key}: {}",
                s["probes"][p][key]
            );
        }
    }
    for key in [
        "vertical_acceleration_max_m_s2",
        "lateral_acceleration_max_m_s2",
    ] {
        assert!(s["vehicles"][key].is_number(), "summary.vehicles.{key}");
    }
    for key in ["derail_factor_max", "offload_factor_max"] {
        assert!(s["safety"][key].is_number(), "summary.safety.{key}");
    }
}

fn probe_columns(name: &str) -> [String; 5] {
    [
        format!("{name}.vertical_displacement_m"),
        format!("{name}.vertical_acceleration_m_s2"),
        format!("{name}.lateral_displacement_m"),
        format!("{name}.lateral_acceleration_m_s2"),
        format!("{name}.torsion_rad"),
    ]
}

/// The issue's example runs with `--solver monolithic`; its outputs have the required keys
/// and columns, the summary maxima are those of the history, and the midspan peak is a
/// plausible multiple of the static deflection W L³ / (48 E I).
#[test]
fn cli_issue_example_runs_and_writes_required_outputs() {
    let dir = scratch("example");
    let out = dir.join("out");
    let r = run(&data("yang-yau.toml"), "monolithic", &out, &[]);
    r.expect_ok("the issue's example");
    let s = r.summary();
    check_summary_keys(&s, &["mid"]);
    assert_eq!(s["status"], "ok");
    assert_eq!(s["solver"], "monolithic");
    assert_eq!(s["speed_kmh"], 100.0);
    assert_eq!(s["dt_s"], 0.0005);
    // the sprung mass crosses 25 m at 100 km/h in 0.9 s, then 1 s of free vibration
    assert_eq!(s["steps"], 3800);
    let wall = s["wall_time_s"].as_f64().unwrap();
    assert!(wall >= 0.0, "wall_time_s = {wall}");
    // stdout: a short summary for a person (the whole one with --json, below)
    assert!(
        r.stdout
            .contains("yang-yau: monolithic at 100 km/h, 3800 steps")
            && r.stdout.contains("deck: vertical displacement")
            && r.stdout
                .contains("limit 3.5 m/s² (EN 1990 A2.4.4.2.1, ballasted): PASS")
            && r.stdout.contains("safety: offload factor"),
        "{}",
        r.stdout
    );
    let z = s["probes"]["mid"]["vertical_displacement_max_m"]
        .as_f64()
        .unwrap();
    assert!(r
        .stdout
        .contains(&format!("vertical displacement {:.3} mm (mid)", 1000.0 * z)));
    let j = run(
        &data("yang-yau.toml"),
        "monolithic",
        &dir.join("json"),
        &["--json"],
    );
    j.expect_ok("--json");
    let printed: serde_json::Value = serde_json::from_str(&j.stdout).expect("summary on stdout");
    assert_eq!(printed["steps"], s["steps"]);

    let h = r.history();
    let mut expected = vec!["time_s".to_string()];
    expected.extend(probe_columns("mid"));
    assert_eq!(h.columns[..6], expected[..], "history.csv columns");
    assert_eq!(h.rows.len(), 3801, "one row per step plus t = 0");
    for (k, row) in h.rows.iter().enumerate() {
        assert!(
            (row[0] - k as f64 * 0.0005).abs() < 1e-9,
            "row {k}: time {}",
            row[0]
        );
    }
    let p = &s["probes"]["mid"];
    for (key, col) in [
        ("vertical_displacement_max_m", 1),
        ("vertical_acceleration_max_m_s2", 2),
        ("lateral_displacement_max_m", 3),
        ("lateral_acceleration_max_m_s2", 4),
    ] {
        let from_history = h.max_abs(&h.columns[col]);
        let v = p[key].as_f64().unwrap();
        assert!(
            (v - from_history).abs() <= 1e-12 * from_history.max(1e-300),
            "probes.mid.{key} = {v}, history max {from_history}"
        );
    }
    assert_eq!(p["lateral_displacement_max_m"], 0.0, "no lateral modes");
    // closed-form static midspan deflection under the full weight, and a dynamic
    // amplification between 1 and 1.3 for this moderate speed (speed parameter v/(2 f1 L) ≈ 0.12)
    let static_m = 5750.0 * 9.81 * 25.0_f64.powi(3) / (48.0 * 2.87e9 * 2.9);
    let peak = p["vertical_displacement_max_m"].as_f64().unwrap();
    assert!(
        peak > static_m && peak < 1.3 * static_m,
        "midspan peak {peak} m, static deflection {static_m} m"
    );

    // several probes: four columns per probe, in probe order
    let mut two = Scenario::parse(&example());
    let mut quarter = toml::Table::new();
    quarter.insert("name".into(), "quarter".into());
    quarter.insert("x_m".into(), 6.25.into());
    two.0["probe"]
        .as_array_mut()
        .unwrap()
        .push(toml::Value::Table(quarter));
    let two = two.set("run", "free_vibration_s", 0.1);
    let path = two.write(&dir, "two-probes.toml");
    let r = run(&path, "monolithic", &dir.join("two-probes"), &[]);
    r.expect_ok("two probes");
    check_summary_keys(&r.summary(), &["mid", "quarter"]);
    let h = r.history();
    let mut expected = vec!["time_s".to_string()];
    expected.extend(probe_columns("mid"));
    expected.extend(probe_columns("quarter"));
    assert_eq!(h.columns[..11], expected[..], "history.csv columns");
}

/// A `modal_file` bridge whose modes file holds the closed-form shapes at 10 nodes (2.78 m
/// apart, midspan between two nodes) gives the analytic bridge's midspan peak within 0.5 %.
/// With linear interpolation (2 points) the same file is off by more than that, so the check
/// resolves the interpolation.
#[test]
fn cli_modal_file_matches_analytic_simply_supported() {
    let dir = scratch("modal-file");
    write_modes_csv(&dir.join("modes.csv"), 10, 20);
    let analytic = run(
        &data("yang-yau.toml"),
        "monolithic",
        &dir.join("analytic"),
        &[],
    );
    analytic.expect_ok("analytic bridge");
    let peak = |out: &Path| {
        read_summary(out)["probes"]["mid"]["vertical_displacement_max_m"]
            .as_f64()
            .unwrap()
    };
    let reference = peak(&analytic.out);
    let ra = read_summary(&analytic.out);

    let path = modal_file_scenario("modes.csv").write(&dir, "modal.toml");
    let r = run(&path, "monolithic", &dir.join("modal"), &[]);
    r.expect_ok("modal_file bridge");
    let s = r.summary();
    assert_eq!(s["bridge"]["modes"], 20);
    let (fa, fm) = (
        ra["bridge"]["frequencies_hz"].as_array().unwrap(),
        s["bridge"]["frequencies_hz"].as_array().unwrap(),
    );
    for (a, m) in fa.iter().zip(fm) {
        let (a, m) = (a.as_f64().unwrap(), m.as_f64().unwrap());
        assert!(
            (a - m).abs() <= 1e-12 * a,
            "frequency {m} Hz vs analytic {a} Hz"
        );
    }
    let modal = peak(&r.out);
    let dev = (modal - reference).abs() / reference;
    println!(
        "modal_file midspan peak {modal:.6e} m, analytic {reference:.6e} m, deviation {dev:.2e}"
    );
    assert!(
        dev <= 5e-3,
        "modal_file midspan peak {modal} m vs analytic {reference} m: {:.3} %",
        100.0 * dev
    );

    let linear = modal_file_scenario("modes.csv").set("bridge", "interpolation_points", 2);
    let path = linear.write(&dir, "modal-linear.toml");
    let r = run(&path, "monolithic", &dir.join("modal-linear"), &[]);
    r.expect_ok("modal_file bridge, linear interpolation");
    let dev_linear = (peak(&r.out) - reference).abs() / reference;
    assert!(
        dev_linear > 5e-3,
        "linear interpolation between nodes 2.78 m apart should miss the peak by more than \
         0.5 %, got {:.3} %",
        100.0 * dev_linear
    );
}

/// A co-simulation that stops (plain Gauss–Seidel iteration on the stiff span, policy
/// "stop") exits non-zero with a message naming the time, the residual and the connection
/// that changed most, and leaves the
/// rows up to the failure in history.csv and a summary.json with status "failed".
///
/// (`max_iterations = 1` cannot show partial rows: the first step has no predictor history,
/// so its first guess of the moving wheelset positions is always off and every run stops at
/// t = 0. The plain iteration instead converges while the first wheelset is near the support
/// and diverges once it is about a metre onto the span.)
#[test]
fn cli_failed_cosim_leaves_partial_results() {
    require_fmu_libraries();
    let dir = scratch("partial");
    let base = Scenario::from_data("stiff-20m.toml");
    let failing = Scenario::parse(&base.text()).coupling(
        "scheme = \"implicit\"\nacceleration = \"constant\"\nrelaxation = 1.0\n\
         max_iterations = 20\non_non_convergence = \"stop\"\n",
    );
    let path = failing.write(&dir, "failing.toml");
    let out = dir.join("cosim");
    let r = run(&path, "cosim", &out, &[]);
    assert_eq!(r.status.code(), Some(1), "stderr:\n{}", r.stderr);
    let t_fail = number_after(&r.stderr, "stopped at t = ")
        .unwrap_or_else(|| panic!("no failure time in:\n{}", r.stderr));
    let residual = number_after(&r.stderr, "residual ")
        .unwrap_or_else(|| panic!("no residual in:\n{}", r.stderr));
    assert!(residual > 1.0, "residual {residual}");
    assert!(
        r.stderr.contains("did not converge") && r.stderr.contains(&out.display().to_string()),
        "stderr:\n{}",
        r.stderr
    );
    // and the connection whose value changed most in the last sweep, by name
    assert!(
        r.stderr.contains("the largest change is in train.ws[")
            || r.stderr.contains("the largest change is in bridge.ws["),
        "stderr:\n{}",
        r.stderr
    );
    assert!(
        t_fail > 0.0,
        "the run should fail after some steps, not at t = 0"
    );

    let s = r.summary();
    assert_eq!(s["status"], "failed");
    let err = s["error"].as_str().expect("summary.error");
    assert!(
        err.contains(&format!("t = {t_fail}")) && err.contains("residual"),
        "summary.error: {err}"
    );
    check_summary_keys(&s, &["mid"]);

    // rows 0, dt, …, t_fail: the state before the failing step
    let h: Table = r.history();
    let dt = 0.001;
    let expected_rows = (t_fail / dt).round() as usize + 1;
    assert_eq!(h.rows.len(), expected_rows, "rows up to t = {t_fail} s");
    let last = h.rows.last().unwrap()[0];
    assert!((last - t_fail).abs() < 1e-12, "last row at t = {last} s");

    // and those rows are the converged co-simulation: the monolithic solution
    let mono = run(
        &base.write(&dir, "mono.toml"),
        "monolithic",
        &dir.join("mono"),
        &[],
    );
    mono.expect_ok("monolithic reference");
    let mut reference = mono.history();
    reference.rows.truncate(h.rows.len());
    assert_same_table(
        &reference,
        &h,
        1e-6,
        "partial co-simulation rows vs monolithic",
    );
}

/// An FMU the co-simulation cannot write (its path is a folder): the run fails with the
/// error naming that path once, before any step.
#[test]
fn cli_an_fmu_that_cannot_be_written_is_named_once() {
    require_fmu_libraries();
    let dir = scratch("unwritable-fmu");
    let path = Scenario::from_data("stiff-20m.toml").write(&dir, "case.toml");
    let out = dir.join("cosim");
    let blocked = out.join("fmus").join("bridge.fmu");
    std::fs::create_dir_all(&blocked).unwrap();
    let r = run(&path, "cosim", &out, &[]);
    assert_eq!(r.status.code(), Some(1), "stderr:\n{}", r.stderr);
    let named = blocked.display().to_string();
    assert!(
        r.stderr
            .contains(&format!("{named}: cannot write the archive")),
        "stderr:\n{}",
        r.stderr
    );
    assert_eq!(r.stderr.matches(&named).count(), 1, "stderr:\n{}", r.stderr);
}
