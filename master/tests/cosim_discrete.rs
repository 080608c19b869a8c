//! Integer and Boolean connections in `tbi cosim`: two instances of the C counter FMU
//! (tests/c-fmu/counter.c: after each step `n_out = n_in + increment`, `b_out = !b_in`,
//! `y_out = u_in + h`, outputs 0/false/0 before the first step) fed by each other in a loop.
//! The closed forms after step k (h = 0.5 s):
//!
//! * Jacobi (both use the other's outputs at t): `n = k` and `b = (k odd)` for both, `y = k h`;
//! * Gauss–Seidel (A first, B gets A's new outputs): A `n = 2k − 1`, `b = true`,
//!   `y = (2k − 1) h`; B `n = 2k`, `b = false`, `y = 2k h`.
//!
//! The implicit scheme refuses the system (the counter cannot roll back, and Integer and
//! Boolean values are not iterated).

mod fmu_support;

use fmu_support::{build_fmu, Variant};
use std::path::{Path, PathBuf};
use tbi_tests::{run, run_ok, scratch, tbi_command, text, Table};

fn system(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::copy(
        build_fmu(&Variant::model("counter", "counter")),
        dir.join("counter.fmu"),
    )
    .unwrap();
    let component = |name: &str| {
        format!(
            r#"<ssd:Component name="{name}" type="application/x-fmu-sharedlibrary" source="counter.fmu">
        <ssd:Connectors>
          <ssd:Connector name="n_in" kind="input"><ssc:Integer/></ssd:Connector>
          <ssd:Connector name="b_in" kind="input"><ssc:Boolean/></ssd:Connector>
          <ssd:Connector name="u_in" kind="input"><ssc:Real/></ssd:Connector>
          <ssd:Connector name="n_out" kind="output"><ssc:Integer/></ssd:Connector>
          <ssd:Connector name="b_out" kind="output"><ssc:Boolean/></ssd:Connector>
          <ssd:Connector name="y_out" kind="output"><ssc:Real/></ssd:Connector>
        </ssd:Connectors>
      </ssd:Component>"#
        )
    };
    let connections: String = [("A", "B"), ("B", "A")]
        .iter()
        .flat_map(|(from, to)| {
            [("n_out", "n_in"), ("b_out", "b_in"), ("y_out", "u_in")].map(|(o, i)| {
                format!(
                    "<ssd:Connection startElement=\"{from}\" startConnector=\"{o}\" \
                     endElement=\"{to}\" endConnector=\"{i}\"/>\n      "
                )
            })
        })
        .collect();
    let ssd = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<ssd:SystemStructureDescription xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" version="1.0" name="counters">
  <ssd:System name="counters">
    <ssd:Elements>
      {a}
      {b}
    </ssd:Elements>
    <ssd:Connections>
      {connections}
    </ssd:Connections>
  </ssd:System>
  <ssd:DefaultExperiment startTime="0" stopTime="3"/>
</ssd:SystemStructureDescription>
"#,
        a = component("A"),
        b = component("B"),
    );
    let path = dir.join("SystemStructure.ssd");
    std::fs::write(&path, ssd).unwrap();
    path
}

fn cosim(ssd: &Path, scheme: &str) -> Table {
    let out = ssd.with_file_name(format!("{scheme}.csv"));
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(ssd)
            .args([
                "--scheme",
                scheme,
                "--step-size",
                "0.5",
                "--quiet",
                "--output",
            ])
            .arg(&out),
    );
    Table::read(&out)
}

fn at(t: &Table, k: usize, name: &str) -> f64 {
    let j = t.columns.iter().position(|c| c == name).unwrap();
    t.rows[k][j]
}

#[test]
fn integer_and_boolean_connections_follow_each_explicit_scheme() {
    let dir = scratch("discrete");
    let ssd = system(&dir);
    let h = 0.5;

    let j = cosim(&ssd, "jacobi");
    assert_eq!(j.rows.len(), 7);
    for k in 0..=6usize {
        let n = k as f64;
        let b = if k % 2 == 1 { 1.0 } else { 0.0 };
        for c in ["A", "B"] {
            assert_eq!(
                at(&j, k, &format!("{c}.n_out")),
                n,
                "jacobi {c}.n_out at k = {k}"
            );
            assert_eq!(
                at(&j, k, &format!("{c}.b_out")),
                b,
                "jacobi {c}.b_out at k = {k}"
            );
            assert_eq!(
                at(&j, k, &format!("{c}.y_out")),
                n * h,
                "jacobi {c}.y_out at k = {k}"
            );
        }
    }

    let g = cosim(&ssd, "gauss-seidel");
    for k in 1..=6usize {
        let n = k as f64;
        assert_eq!(
            at(&g, k, "A.n_out"),
            2.0 * n - 1.0,
            "gauss-seidel A.n_out at k = {k}"
        );
        assert_eq!(
            at(&g, k, "B.n_out"),
            2.0 * n,
            "gauss-seidel B.n_out at k = {k}"
        );
        assert_eq!(at(&g, k, "A.b_out"), 1.0, "gauss-seidel A.b_out at k = {k}");
        assert_eq!(at(&g, k, "B.b_out"), 0.0, "gauss-seidel B.b_out at k = {k}");
        assert_eq!(at(&g, k, "A.y_out"), (2.0 * n - 1.0) * h);
        assert_eq!(at(&g, k, "B.y_out"), 2.0 * n * h);
    }
    // the side-car names the connections each scheme lagged: Gauss–Seidel breaks the cycle
    // A ⇄ B at B → A, Jacobi lags both directions
    let lagged = |scheme: &str| {
        let json = std::fs::read_to_string(dir.join(format!("{scheme}.csv.json"))).unwrap();
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        v["lagged_connections"].clone()
    };
    assert_eq!(
        lagged("gauss-seidel"),
        serde_json::json!([{"from": "B", "to": "A", "connections": 3}])
    );
    assert_eq!(
        lagged("jacobi"),
        serde_json::json!([
            {"from": "A", "to": "B", "connections": 3},
            {"from": "B", "to": "A", "connections": 3}
        ])
    );
    // integers are written as integers
    let csv = std::fs::read_to_string(dir.join("jacobi.csv")).unwrap();
    assert!(csv.lines().nth(3).unwrap().contains(",2,"), "{csv}");

    // Integer parameters are typed by the variable: increment = 3 on both
    let out = dir.join("increment.csv");
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&ssd)
            .args(["--scheme", "jacobi", "--step-size", "0.5", "--quiet"])
            .args([
                "--set",
                "A.increment=3",
                "--set",
                "B.increment=3",
                "--output",
            ])
            .arg(&out),
    );
    assert_eq!(at(&Table::read(&out), 6, "A.n_out"), 18.0);
    let bad = run(tbi_command()
        .arg("cosim")
        .arg(&ssd)
        .args(["--scheme", "jacobi", "--step-size", "0.5", "--quiet"])
        .args(["--set", "A.increment=1.5", "--output"])
        .arg(dir.join("bad.csv")));
    let err = text(&bad.stderr);
    assert_eq!(bad.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--set A.increment = \"1.5\" is not an integer"),
        "{err}"
    );

    // the implicit scheme cannot take this system
    let r = run(tbi_command()
        .arg("cosim")
        .arg(&ssd)
        .args([
            "--scheme",
            "implicit",
            "--step-size",
            "0.5",
            "--quiet",
            "--output",
        ])
        .arg(dir.join("implicit.csv")));
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("SystemStructure.ssd")
            && err.contains("\"A\"")
            && err.contains("cannot roll back"),
        "{err}"
    );
}

#[test]
fn type_mismatches_and_bindings_to_outputs_are_refused() {
    let dir = scratch("discrete-bad");
    let ssd = system(&dir);
    let good = std::fs::read_to_string(&ssd).unwrap();
    let binding = r#"<ssd:Component name="B" type="application/x-fmu-sharedlibrary" source="counter.fmu"><ssd:ParameterBindings><ssd:ParameterBinding><ssd:ParameterValues><ssv:ParameterSet xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="p"><ssv:Parameters><ssv:Parameter name="n_out"><ssv:Integer value="4"/></ssv:Parameter></ssv:Parameters></ssv:ParameterSet></ssd:ParameterValues></ssd:ParameterBinding></ssd:ParameterBindings>"#;
    let cases = [
        (
            "integer-to-real",
            r#"startElement="A" startConnector="n_out" endElement="B" endConnector="n_in""#,
            r#"startElement="A" startConnector="n_out" endElement="B" endConnector="u_in""#,
            "connection A.n_out → B.u_in: an Integer output cannot feed a Real input",
        ),
        (
            "boolean-to-integer",
            r#"startElement="B" startConnector="b_out" endElement="A" endConnector="b_in""#,
            r#"startElement="B" startConnector="b_out" endElement="A" endConnector="n_in""#,
            "connection B.b_out → A.n_in: a Boolean output cannot feed an Integer input",
        ),
        (
            "binding-to-an-output",
            r#"<ssd:Component name="B" type="application/x-fmu-sharedlibrary" source="counter.fmu">"#,
            binding,
            "B.n_out is not a parameter or input and cannot be set",
        ),
    ];
    for (label, from, to, needle) in cases {
        assert!(good.contains(from), "{label}");
        let bad = dir.join(format!("{label}.ssd"));
        std::fs::write(&bad, good.replacen(from, to, 1)).unwrap();
        let out = dir.join(format!("{label}.csv"));
        let r = run(tbi_command()
            .arg("cosim")
            .arg(&bad)
            .args([
                "--scheme",
                "jacobi",
                "--step-size",
                "0.5",
                "--quiet",
                "--output",
            ])
            .arg(&out));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{label}: {err}");
        assert!(
            err.contains(&format!("{label}.ssd")) && err.contains(needle),
            "{label}: expected {needle:?} in {err}"
        );
        assert!(!out.exists(), "{label}: a result was written");
    }
}
