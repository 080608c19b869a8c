//! Interoperability: the exported default system (`tbi export`, the Tsing Ma case) runs in
//! libcosim (`libcosimpy`, installed into the test venv by tests/python/setup-venv.sh) through
//! tests/python/libcosim_run.py, and its result equals `tbi cosim --scheme jacobi` on the same
//! `system.ssp` to 1e-8 of each column's largest magnitude.
//!
//! libcosim's fixed-step algorithm is Gauss–Jacobi, like `--scheme jacobi`, and both record
//! the outputs after initialisation and after each step, so row k of one file is row k of the
//! other. The step is 2⁻⁹ s: libcosim counts time in integer nanoseconds and tbi in floating
//! point, and only for a step whose multiples are exact in both do the two hand the FMUs the
//! same `fmi2DoStep` times (with 1 ms they differ by one ulp at some steps, which moves the
//! step in which a wheelset's load reaches the bridge, a first-order Jacobi difference).

use tbi_tests::fmpy::{python, venv};
use tbi_tests::{repo_path, run, run_ok, scratch, tbi_command, text, Table};

/// 2⁻⁹ s, and 1024 steps of it.
const STEP: &str = "0.001953125";
const STOP: &str = "2.0";

#[test]
fn the_exported_default_system_runs_in_libcosim_as_in_tbi_jacobi() {
    let Some(venv) = venv() else { return };
    let dir = scratch("libcosim");
    run_ok(
        tbi_command()
            .arg("export")
            .arg("--out")
            .arg(dir.join("fmus")),
    );
    let ssp = dir.join("fmus/system.ssp");

    let ours = dir.join("tbi.csv");
    run_ok(
        tbi_command()
            .arg("cosim")
            .arg(&ssp)
            .args([
                "--scheme",
                "jacobi",
                "--step-size",
                STEP,
                "--stop-time",
                STOP,
            ])
            .args(["--quiet", "--record-all", "--output"])
            .arg(&ours),
    );
    let theirs = dir.join("libcosim.csv");
    let out = run(python(venv)
        .arg(repo_path("tests/python/libcosim_run.py"))
        .arg(&ssp)
        .args(["--step-size", STEP, "--stop-time", STOP, "--output"])
        .arg(&theirs));
    assert!(
        out.status.success(),
        "libcosim_run.py failed:\n{}\n{}",
        text(&out.stdout),
        text(&out.stderr)
    );

    let (a, b) = (Table::read(&ours), Table::read(&theirs));
    assert_eq!(a.columns, b.columns, "the same columns in the same order");
    assert_eq!(
        a.rows.len(),
        1025,
        "a row after initialisation and after each step"
    );
    assert_eq!(a.rows.len(), b.rows.len());
    let mut worst = (0.0_f64, String::new());
    for (j, name) in a.columns.iter().enumerate() {
        let col = |t: &Table| t.rows.iter().map(|r| r[j]).collect::<Vec<f64>>();
        let (x, y) = (col(&a), col(&b));
        let scale = y.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let diff = x
            .iter()
            .zip(&y)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        let rel = if scale > 0.0 { diff / scale } else { diff };
        if rel > worst.0 {
            worst = (rel, name.clone());
        }
    }
    println!(
        "libcosim vs tbi jacobi: worst relative difference {:.3e} in {}",
        worst.0, worst.1
    );
    assert!(worst.0 <= 1e-8, "{} differs by {:.3e}", worst.1, worst.0);
    // the rail moved under the wheels: not a comparison of two resting systems
    let z = a
        .columns
        .iter()
        .position(|h| h == "bridge.ws[1].z")
        .expect("bridge.ws[1].z");
    assert!(
        a.rows.iter().any(|r| r[z].abs() > 1e-4),
        "rail motion under wheelset 1 > 0.1 mm"
    );
}
