//! `tbi validate`: both solvers on one scenario, and the report of their differences.
//!
//! The worst difference it reports equals the one the shared comparison of the test support
//! computes from the two `history.csv` files it wrote (the definition of the equivalence
//! tests); it is within the co-simulation's tolerance; `--tolerance 1e-20` fails.

use tbi_tests::{compare, read_json, run, run_ok, scratch, tbi_command, text, worst, Table};

#[test]
fn validate_reports_the_worst_difference_of_the_two_histories() {
    let dir = scratch("validate");
    let scenario = tbi_tests::repo_path("master/tests/data/yang-yau.toml");
    let out = run_ok(
        tbi_command()
            .arg("validate")
            .arg(&scenario)
            .args(["--quiet", "--tolerance", "1e-7", "--out"])
            .arg(&dir),
    );
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("| deck |") && stdout.contains("| wheelsets |"),
        "{stdout}"
    );
    let report = read_json(&dir.join("validation.json"));
    assert_eq!(report["passed"], true);
    let mono = Table::read(&dir.join("monolithic/history.csv"));
    let co = Table::read(&dir.join("cosim/history.csv"));
    let (column, rel) = worst(&compare(&mono, &co));
    assert_eq!(report["worst"]["column"], column.as_str());
    let reported = report["worst"]["relative"].as_f64().unwrap();
    assert!(
        (reported - rel).abs() <= 1e-12 * rel.max(1e-300),
        "{reported:e} vs {rel:e}"
    );
    assert!(rel <= 1e-7, "{column}: {rel:e}");
    assert!(dir.join("validation_worst.svg").is_file());

    let strict = run(tbi_command()
        .arg("validate")
        .arg(&scenario)
        .args(["--quiet", "--tolerance", "1e-20", "--out"])
        .arg(dir.join("strict")));
    let err = text(&strict.stderr);
    assert_eq!(strict.status.code(), Some(1), "{err}");
    assert!(
        err.contains("exceeds --tolerance 1e-20") && err.contains(&column),
        "{err}"
    );
    assert_eq!(
        read_json(&dir.join("strict/validation.json"))["passed"],
        false
    );
}
