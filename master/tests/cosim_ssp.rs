//! `tbi cosim SYSTEM.ssp`, the master standalone:
//!
//! * on the exported Yang–Yau system it gives the histories of `tbi run --solver cosim`
//!   (which runs the same SSP), to round-off;
//! * a parameter binding in the SSD (the train's `speed`) gives the result of the scenario
//!   at that speed;
//! * bad systems are refused with a message naming the file and the element.

use std::path::{Path, PathBuf};
use tbi_tests::fmu::{rewrite_zip, rewrite_zip_file};
use tbi_tests::{run, run_ok, scratch, tbi_command, text, Table};

fn yang_yau() -> PathBuf {
    tbi_tests::repo_path("master/tests/data/yang-yau.toml")
}

/// Export the Yang–Yau scenario into `dir/fmus`; returns the SSP.
fn export(dir: &Path) -> PathBuf {
    run_ok(
        tbi_command()
            .arg("export")
            .arg(yang_yau())
            .arg("--out")
            .arg(dir.join("fmus")),
    );
    dir.join("fmus/system.ssp")
}

/// A copy of `ssp` whose SystemStructure.ssd is `edit(ssd)`.
fn edited(ssp: &Path, to: &Path, edit: impl Fn(&str) -> String) -> PathBuf {
    rewrite_zip_file(ssp, to, |name, bytes| {
        if name == "SystemStructure.ssd" {
            edit(&String::from_utf8(bytes).unwrap()).into_bytes()
        } else {
            bytes
        }
    });
    to.to_path_buf()
}

fn cosim(ssp: &Path, out: &Path, extra: &[&str]) -> Table {
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(ssp)
            .args([
                "--quiet",
                "--record-all",
                "--record",
                "bridge.probe[1].z",
                "--output",
            ])
            .arg(out)
            .args(extra),
    );
    Table::read(out)
}

/// Largest |a − b| over the rows both have, relative to the largest |b|.
fn worst(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn cosim_on_the_exported_system_equals_tbi_run() {
    let dir = scratch("cosim-equals-run");
    let ssp = export(&dir);
    let table = cosim(&ssp, &dir.join("out.csv"), &[]);
    run_ok(
        tbi_command()
            .arg("run")
            .arg(yang_yau())
            .args(["--solver", "cosim", "--quiet", "--out"])
            .arg(dir.join("run")),
    );
    let history = Table::read(&dir.join("run/history.csv"));
    assert_eq!(table.rows.len(), history.rows.len());
    for (ours, theirs) in [
        ("train.ws[1].F_z", "ws1.vertical_force_n"),
        ("bridge.probe[1].z", "mid.vertical_displacement_m"),
        ("time", "time_s"),
    ] {
        let d = worst(&table.column(ours), &history.column(theirs));
        assert!(d <= 1e-12, "{ours} vs {theirs}: {d:e}");
    }
    let json = tbi_tests::read_json(&dir.join("out.csv.json"));
    assert_eq!(json["steps"], 3800);
    assert_eq!(json["scheme"], "implicit");
    assert_eq!(json["accepted_unconverged"], 0);
    // the steps by their sweeps, as in summary.json: every step once
    let (by, counted, _) = tbi_tests::steps_by_sweeps(&json["steps_by_iterations"]);
    assert_eq!(counted, 3800);
    assert_eq!(Some(by.len() as u64), json["iterations_max"].as_u64());
}

/// `--output-interval` keeps the rows of every k-th step (and the last) of the full result,
/// bit for bit; an interval that is not a whole number of steps is refused, naming it.
#[test]
fn an_output_interval_keeps_every_kth_row() {
    let dir = scratch("cosim-output-interval");
    let ssp = export(&dir);
    let full = cosim(&ssp, &dir.join("full.csv"), &[]);
    let h = tbi_tests::read_json(&dir.join("full.csv.json"))["step_size_s"]
        .as_f64()
        .unwrap();
    let every = 7;
    let sparse = cosim(
        &ssp,
        &dir.join("sparse.csv"),
        &["--output-interval", &(every as f64 * h).to_string()],
    );
    let steps = full.rows.len() - 1;
    let mut want: Vec<&Vec<f64>> = full.rows.iter().step_by(every).collect();
    if !steps.is_multiple_of(every) {
        want.push(full.rows.last().unwrap());
    }
    assert_eq!(sparse.columns, full.columns);
    assert_eq!(sparse.rows.len(), want.len());
    for (got, want) in sparse.rows.iter().zip(want) {
        assert!(
            got.iter()
                .zip(want)
                .all(|(a, b)| a.to_bits() == b.to_bits()),
            "row at t = {} differs",
            want[0]
        );
    }
    let out = run(tbi_command()
        .arg("cosim")
        .arg(&ssp)
        .args([
            "--quiet",
            "--output-interval",
            &(1.5 * h).to_string(),
            "--output",
        ])
        .arg(dir.join("bad.csv")));
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("--output-interval") && err.contains("whole multiple of the step size"),
        "{err}"
    );
}

#[test]
fn a_parameter_binding_sets_the_train_speed() {
    let dir = scratch("cosim-binding");
    let ssp = export(&dir);
    let v = 80.0 / 3.6;
    let binding = format!(
        r#"<ssd:Component name="train" type="application/x-fmu-sharedlibrary" source="resources/train.fmu">
        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
          <ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="speed">
            <ssv:Parameters><ssv:Parameter name="speed"><ssv:Real value="{v:e}"/></ssv:Parameter></ssv:Parameters>
          </ssv:ParameterSet>
        </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"#
    );
    let bound = edited(&ssp, &dir.join("bound.ssp"), |ssd| {
        ssd.replace(
            r#"<ssd:Component name="train" type="application/x-fmu-sharedlibrary" source="resources/train.fmu">"#,
            &binding,
        )
    });
    let table = cosim(&bound, &dir.join("out.csv"), &[]);
    run_ok(
        tbi_command()
            .arg("run")
            .arg(yang_yau())
            .args(["--speed-kmh", "80", "--solver", "cosim", "--quiet", "--out"])
            .arg(dir.join("run80")),
    );
    let history = Table::read(&dir.join("run80/history.csv"));
    // the SSD's stop time is the 100 km/h run's: compare the rows both have
    let n = table.rows.len().min(history.rows.len());
    let ours = &table.column("train.ws[1].F_z")[..n];
    let theirs = &history.column("ws1.vertical_force_n")[..n];
    let d = worst(ours, theirs);
    assert!(d <= 1e-12, "F_z at 80 km/h: {d:e}");
    let x = table.column("train.ws[1].vx");
    assert!((x[1] - v).abs() <= 1e-12 * v, "speed {}", x[1]);
}

#[test]
fn bad_systems_are_refused_naming_the_file_and_element() {
    let dir = scratch("cosim-bad");
    let ssp = export(&dir);
    // (the FMUs are loaded side by side: a missing first and a missing second component)
    let cases: [(&str, &str, &str, &str); 12] = [
        (
            "missing-fmu",
            "resources/train.fmu",
            "resources/nothere.fmu",
            "nothere.fmu",
        ),
        (
            "missing-first-fmu",
            "resources/bridge.fmu",
            "resources/gone.fmu",
            "component \"bridge\": its FMU resources/gone.fmu does not exist",
        ),
        (
            "unknown-variable",
            r#"endConnector="ws[1].F_z""#,
            r#"endConnector="ws[1].F_q""#,
            "has no variable \"ws[1].F_q\"",
        ),
        (
            "output-to-output",
            r#"startElement="train" startConnector="ws[1].x" endElement="bridge" endConnector="ws[1].x""#,
            r#"startElement="train" startConnector="ws[1].x" endElement="bridge" endConnector="ws[1].y""#,
            "the end is not an input",
        ),
        (
            "unknown-component",
            r#"endElement="bridge" endConnector="ws[1].vx""#,
            r#"endElement="deck" endConnector="ws[1].vx""#,
            "unknown component \"deck\"",
        ),
        (
            "malformed",
            "</ssd:Connections>",
            "</ssd:Connection>",
            "malformed XML",
        ),
        (
            "unknown-parameter",
            r#"<ssd:Component name="train" type="application/x-fmu-sharedlibrary" source="resources/train.fmu">"#,
            r#"<ssd:Component name="train" type="application/x-fmu-sharedlibrary" source="resources/train.fmu"><ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet xmlns:ssv="v" version="1.0" name="p"><ssv:Parameters><ssv:Parameter name="warp"><ssv:Real value="1"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"#,
            "has no variable \"warp\"",
        ),
        (
            "nan-binding",
            r#"<ssd:Component name="train" type="application/x-fmu-sharedlibrary" source="resources/train.fmu">"#,
            r#"<ssd:Component name="train" type="application/x-fmu-sharedlibrary" source="resources/train.fmu"><ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="p"><ssv:Parameters><ssv:Parameter name="speed"><ssv:Real value="NaN"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"#,
            "parameter speed = \"NaN\" is not a finite number",
        ),
        (
            "foreign-namespace",
            "xmlns:ssd=\"http://ssp-standard.org/SSP1/SystemStructureDescription\"",
            "xmlns:ssd=\"urn:other\"",
            "not SSP 1.0's",
        ),
        (
            "version-2",
            "version=\"1.0\" name=\"train-bridge\"",
            "version=\"2.0\" name=\"train-bridge\"",
            "only SSP version \"1.0\" is read",
        ),
        (
            "ssp-package",
            r#"name="train" type="application/x-fmu-sharedlibrary""#,
            r#"name="train" type="application/x-ssp-package""#,
            "only FMUs (application/x-fmu-sharedlibrary) are run",
        ),
        (
            "absolute-source",
            "source=\"resources/train.fmu\"",
            "source=\"/tmp/train.fmu\"",
            "lies outside the archive",
        ),
    ];
    for (label, from, to, needle) in cases {
        let bad = edited(&ssp, &dir.join(format!("{label}.ssp")), |ssd| {
            assert!(ssd.contains(from), "{label}: {from} not in the SSD");
            ssd.replacen(from, to, 1)
        });
        let out = run(tbi_command()
            .arg("cosim")
            .arg(&bad)
            .args(["--quiet", "--output"])
            .arg(dir.join(format!("{label}.csv"))));
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{label}: {err}");
        assert!(
            err.contains(&format!("{label}.ssp")) && err.contains(needle),
            "{label}: expected {needle:?} in: {err}"
        );
        assert!(
            !dir.join(format!("{label}.csv")).exists(),
            "{label}: a result was written"
        );
    }
    // an SSD cut in half, and a NaN --set value, even with the times given on the command line
    let half = edited(&ssp, &dir.join("half.ssp"), |ssd| {
        ssd[..ssd.find("<ssd:Connections>").expect("connections")].to_owned()
    });
    for (label, system, set, needle) in [
        (
            "half",
            &half,
            "train.speed=20",
            "the document ends inside <System>",
        ),
        (
            "nan-set",
            &ssp,
            "train.speed=nan",
            "--set train.speed = \"nan\" is not a finite number",
        ),
    ] {
        let out = run(tbi_command()
            .arg("cosim")
            .arg(system)
            .args([
                "--quiet",
                "--stop-time",
                "0.1",
                "--step-size",
                "0.01",
                "--set",
                set,
            ])
            .arg("--output")
            .arg(dir.join(format!("{label}.csv"))));
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{label}: {err}");
        assert!(
            err.contains(needle),
            "{label}: expected {needle:?} in: {err}"
        );
        assert!(
            !dir.join(format!("{label}.csv")).exists(),
            "{label}: a result was written"
        );
    }
}

#[test]
fn the_implicit_scheme_refuses_an_fmu_that_cannot_roll_back() {
    let dir = scratch("cosim-no-rollback");
    let ssp = export(&dir);
    // the SSP with a train.fmu whose description denies FMU state
    let bad = dir.join("norollback.ssp");
    rewrite_zip_file(&ssp, &bad, |name, bytes| {
        if name != "resources/train.fmu" {
            return bytes;
        }
        rewrite_zip(&bytes, |entry, md| {
            if entry != "modelDescription.xml" {
                return md;
            }
            String::from_utf8(md)
                .unwrap()
                .replace(
                    "canGetAndSetFMUstate=\"true\"",
                    "canGetAndSetFMUstate=\"false\"",
                )
                .replace(
                    "canSerializeFMUstate=\"true\"",
                    "canSerializeFMUstate=\"false\"",
                )
                .into_bytes()
        })
    });
    let out = run(tbi_command()
        .arg("cosim")
        .arg(&bad)
        .args(["--quiet", "--output"])
        .arg(dir.join("o.csv")));
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("norollback.ssp")
            && err.contains("\"train\"")
            && err.contains("cannot roll back"),
        "{err}"
    );
    // an explicit scheme runs it
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&bad)
            .args(["--quiet", "--scheme", "jacobi", "--output"])
            .arg(dir.join("j.csv")),
    );
}

/// The bridge FMU's modal damping ratios are parameters (`mode[n].damping_ratio`): SSD
/// bindings of them change the result as a scenario with that damping does (1e-10 of each
/// column's largest value), and `--set` does the same; a ratio out of [0, 1) is refused by
/// name.
#[test]
fn bindings_of_the_bridge_damping_equal_a_scenario_with_it() {
    let dir = scratch("cosim-damping");
    let ssp = export(&dir);
    let text = std::fs::read_to_string(yang_yau()).unwrap();
    assert!(
        text.contains("damping_ratio = 0.0"),
        "yang-yau.toml is undamped"
    );
    let damped_text = text.replace("damping_ratio = 0.0", "damping_ratio = 0.02");
    let damped = dir.join("damped.toml");
    std::fs::write(&damped, &damped_text).unwrap();
    run_ok(
        tbi_command()
            .arg("export")
            .arg(&damped)
            .arg("--out")
            .arg(dir.join("damped-fmus")),
    );
    let want = cosim(
        &dir.join("damped-fmus/system.ssp"),
        &dir.join("want.csv"),
        &[],
    );
    let modes = 20;
    let parameters: String = (1..=modes)
        .map(|n| {
            format!(
                r#"<ssv:Parameter name="mode[{n}].damping_ratio"><ssv:Real value="0.02"/></ssv:Parameter>"#
            )
        })
        .collect();
    let binding = format!(
        r#"<ssd:Component name="bridge" type="application/x-fmu-sharedlibrary" source="resources/bridge.fmu">
        <ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues>
          <ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="damping">
            <ssv:Parameters>{parameters}</ssv:Parameters>
          </ssv:ParameterSet>
        </ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"#
    );
    let bound = edited(&ssp, &dir.join("bound.ssp"), |ssd| {
        ssd.replace(
            r#"<ssd:Component name="bridge" type="application/x-fmu-sharedlibrary" source="resources/bridge.fmu">"#,
            &binding,
        )
    });
    let got = cosim(&bound, &dir.join("bound.csv"), &[]);
    let sets: Vec<String> = (1..=modes)
        .map(|n| format!("bridge.mode[{n}].damping_ratio=0.02"))
        .collect();
    let mut extra: Vec<&str> = Vec::new();
    for s in &sets {
        extra.extend(["--set", s.as_str()]);
    }
    let set = cosim(&ssp, &dir.join("set.csv"), &extra);
    let undamped = cosim(&ssp, &dir.join("undamped.csv"), &[]);
    for column in ["bridge.probe[1].z", "train.ws[1].F_z", "bridge.ws[1].z_dd"] {
        let w = want.column(column);
        let (b, s) = (
            worst(&got.column(column), &w),
            worst(&set.column(column), &w),
        );
        println!("{column}: binding {b:e}, --set {s:e}");
        assert!(
            b <= 1e-10 && s <= 1e-10,
            "{column}: binding {b:e}, --set {s:e}"
        );
        assert!(
            worst(&undamped.column(column), &w) > 1e-3,
            "{column}: damping changes it"
        );
    }
    // a ratio out of range, by name
    let r = tbi_tests::run(
        tbi_command()
            .arg("cosim")
            .arg(&ssp)
            .args([
                "--quiet",
                "--set",
                "bridge.mode[2].damping_ratio=1.5",
                "--output",
            ])
            .arg(dir.join("bad.csv")),
    );
    let err = tbi_tests::text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("mode[2].damping_ratio") && err.contains("1.5"),
        "{err}"
    );
}
