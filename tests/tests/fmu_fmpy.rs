//! The exported FMUs and SSP in FMPy 0.3.32, the reference importer: `fmpy validate`,
//! `fmpy simulate` of each FMU alone (also the three of a turbulent crosswind) (the bridge also with an input file, against its static
//! deflection), and FMPy's SSP master against the monolithic solver as the step shrinks.
//!
//! The venv comes from `tests/python/setup-venv.sh`; if it is missing and cannot be created
//! these tests fail, unless `TBI_SKIP_PYTHON=1` asks to skip them.

mod common;

use common::reference::truncated_series;
use common::scenarios::{self, FORCE_PROBES_M};
use std::path::Path;
use std::process::Command;
use std::sync::OnceLock;
use tbi_tests::fmpy::{self, fmpy, python};
use tbi_tests::fmu::{export, unpack, Export};
use tbi_tests::{repo_path, run, run_ok, Table};

fn coach2() -> &'static Export {
    static E: OnceLock<Export> = OnceLock::new();
    E.get_or_init(|| export("fmpy-coach2", &scenarios::coach2()))
}

/// The three FMUs of a turbulent crosswind (bridge and train with their wind inputs, wind).
fn windy() -> &'static Export {
    static E: OnceLock<Export> = OnceLock::new();
    E.get_or_init(|| export("fmpy-windy", &scenarios::coach2_windy()))
}

/// The FMUs of an export.
fn fmus(e: &Export) -> Vec<&Path> {
    let mut v = vec![e.bridge.as_path(), e.train.as_path()];
    v.extend(e.wind.as_deref());
    v
}

fn moving_force() -> &'static Export {
    static E: OnceLock<Export> = OnceLock::new();
    E.get_or_init(|| export("fmpy-force", &scenarios::moving_force()))
}

#[test]
fn fmpy_validate_finds_no_problems() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    assert!(windy().wind.is_some(), "a turbulent wind exports wind.fmu");
    for e in [coach2(), moving_force(), windy()] {
        for fmu in fmus(e) {
            let out = run(fmpy(venv).arg("validate").arg(fmu));
            let stdout = String::from_utf8_lossy(&out.stdout);
            assert!(
                out.status.success() && stdout.contains("No problems found"),
                "fmpy validate {} ({}):\n{stdout}\n{}",
                fmu.display(),
                out.status,
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

/// `fmpy simulate` of one FMU; returns the result table.
fn simulate(venv: &Path, fmu: &Path, csv: &Path, extra: &[&str]) -> Table {
    run_ok(
        fmpy(venv)
            .arg("simulate")
            .arg(fmu)
            .args(["--output-interval", "0.002"])
            .args(extra)
            .arg("--output-file")
            .arg(csv),
    );
    Table::read(csv)
}

fn outputs(fmu: &Path) -> Vec<String> {
    let u = unpack(fmu, &fmu.with_extension("unpacked"));
    u.md.outputs().map(|v| v.name.clone()).collect()
}

#[test]
fn fmpy_simulates_each_fmu_alone() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    for (e, label) in [
        (coach2(), "coach2"),
        (moving_force(), "force"),
        (windy(), "windy"),
    ] {
        for fmu in fmus(e) {
            let csv = e.dir.join(format!(
                "{}-alone.csv",
                fmu.file_stem().unwrap().to_string_lossy()
            ));
            let table = simulate(venv, fmu, &csv, &["--stop-time", "0.2"]);
            let want = outputs(fmu);
            assert!(!want.is_empty());
            let mut expected = vec!["time".to_string()];
            expected.extend(want);
            assert_eq!(
                table.columns,
                expected,
                "{label}: {} columns",
                fmu.display()
            );
            assert_eq!(table.rows.len(), 101, "{label}: rows of {}", csv.display());
            assert!((table.rows[100][0] - 0.2).abs() < 1e-12);
            assert!(table.rows.iter().flatten().all(|v| v.is_finite()));
        }
    }
    // The coach train alone on its default (zero) rail inputs carries its Table 1 weight
    // share on every wheelset: (m_w + M_t/2 + M_c/4)·g.
    let table = Table::read(&coach2().dir.join("train-alone.csv"));
    let share = (1_770.0 + 4_360.0 / 2.0 + 50_990.0 / 4.0) * 9.81;
    for w in 1..=8 {
        for v in table.column(&format!("ws[{w}].F_z")) {
            assert!((v - share).abs() < 1e-9 * share, "ws[{w}].F_z = {v}");
        }
    }
}

#[test]
fn fmpy_bridge_with_an_input_file_settles_to_the_static_deflection() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    let e = moving_force();
    let (a, f) = (12.0, 2.0e5);
    let input = e.dir.join("static-input.csv");
    std::fs::write(
        &input,
        format!(
            "\"time\",\"ws[1].x\",\"ws[1].vx\",\"ws[1].F_z\"\n0.0,{a},0.0,{f}\n5.0,{a},0.0,{f}\n"
        ),
    )
    .expect("write input file");
    let csv = e.dir.join("static-fmpy.csv");
    let table = simulate(
        venv,
        &e.bridge,
        &csv,
        &[
            "--stop-time",
            "5.0",
            "--input-file",
            input.to_str().expect("utf-8 path"),
            "--output-variables",
            "probe[1].z",
            "probe[2].z",
            "probe[3].z",
            "ws[1].z",
        ],
    );
    let last = table.rows.last().expect("rows");
    assert!((last[table.col("time")] - 5.0).abs() < 1e-9);
    let scale = truncated_series(a, a, f).0;
    for (k, &x) in FORCE_PROBES_M.iter().enumerate() {
        let got = last[table.col(&format!("probe[{}].z", k + 1))];
        let want = truncated_series(x, a, f).0;
        println!("FMPy: probe[{}].z = {got:e}, reference {want:e}", k + 1);
        assert!(
            (got - want).abs() < 1e-7 * scale,
            "probe[{}].z {got} vs {want}",
            k + 1
        );
    }
    let (za, tha) = truncated_series(a, a, f);
    let got = last[table.col("ws[1].z")];
    let want = za + scenarios::E_TRACK_M * tha;
    assert!((got - want).abs() < 1e-7 * scale, "ws[1].z {got} vs {want}");
}

/// Step sizes of the convergence study, s.
const STEPS: [f64; 3] = [2.0e-3, 1.0e-3, 5.0e-4];
/// End of the compared window, s (the sprung mass leaves the 25 m span at 0.9 s).
const T_CMP: f64 = 0.8;

/// Monolithic `tbi run` of the sprung-mass scenario with `dt = h`; returns history.csv.
fn monolithic(dir: &Path, h: f64) -> Table {
    let scenario = dir.join(format!("sprung-{h:e}.toml"));
    std::fs::write(&scenario, scenarios::sprung_mass(h)).expect("write scenario");
    let out = dir.join(format!("mono-{h:e}"));
    run_ok(
        Command::new(common::tbi())
            .arg("run")
            .arg(&scenario)
            .args(["--solver", "monolithic", "--quiet", "--out"])
            .arg(&out),
    );
    Table::read(&out.join("history.csv"))
}

#[test]
fn fmpy_ssp_simulation_converges_to_the_monolithic_solution_at_first_order() {
    let Some(venv) = fmpy::venv() else {
        return;
    };
    // One export: the FMUs do not depend on the scenario's dt (each DoStep is one Newmark
    // step of the size the master asks for).
    let e = export("fmpy-ssp", &scenarios::sprung_mass(STEPS[0]));
    let ssp_dir = e.dir.join("ssp");
    let columns = ["bridge.probe[1].z", "train.ws[1].F_z"];
    let script = repo_path("tests/python/ssp_run.py");
    let mut cmd = python(venv);
    cmd.arg(&script)
        .arg(&e.ssp)
        .args(["--stop-time", &T_CMP.to_string(), "--step-size"])
        .args(STEPS.map(|h| h.to_string()))
        .arg("--columns")
        .args(columns)
        .arg("--out-dir")
        .arg(&ssp_dir);
    run_ok(&mut cmd);

    let mut errors: Vec<(f64, f64, f64)> = Vec::new(); // h, deflection error, force error
    for (k, &h) in STEPS.iter().enumerate() {
        let ssp = Table::read(&ssp_dir.join(format!("ssp_{k}.csv")));
        let mono = monolithic(&e.dir, h);
        let (st, sz, sf) = (
            ssp.column("time"),
            ssp.column(columns[0]),
            ssp.column(columns[1]),
        );
        let (mt, mz, mf) = (
            mono.column("time_s"),
            mono.column("mid.vertical_displacement_m"),
            mono.column("ws1.vertical_force_n"),
        );
        // FMPy's row stamped t holds the values after the step, at t + h = the monolithic
        // solver's row i + 1.
        let n = st.iter().filter(|&&t| t + h <= T_CMP + 1e-9).count();
        assert!(
            n >= (0.99 * T_CMP / h) as usize,
            "only {n} SSP rows for h = {h}"
        );
        assert!(mt.len() > n, "monolithic history too short for h = {h}");
        let (mut ez, mut ef, mut zmax, mut fmax) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for i in 0..n {
            assert!(
                (st[i] + h - mt[i + 1]).abs() < 1e-9,
                "time mismatch at row {i}: SSP {} + {h} vs monolithic {}",
                st[i],
                mt[i + 1]
            );
            ez = ez.max((sz[i] - mz[i + 1]).abs());
            ef = ef.max((sf[i] - mf[i + 1]).abs());
            zmax = zmax.max(mz[i + 1].abs());
            fmax = fmax.max(mf[i + 1].abs());
        }
        println!(
            "h = {h:e}: max |Δz_mid| = {ez:.3e} m ({:.2e} of max {zmax:.3e}), max |ΔF_z| = {ef:.3e} N ({:.2e} of max {fmax:.3e})",
            ez / zmax,
            ef / fmax
        );
        assert!(
            zmax > 1e-4,
            "the midspan deflection ({zmax} m) is too small to compare"
        );
        errors.push((h, ez / zmax, ef / fmax));
    }
    for w in errors.windows(2) {
        let (h0, ez0, ef0) = w[0];
        let (h1, ez1, ef1) = w[1];
        let pz = (ez0 / ez1).ln() / (h0 / h1).ln();
        let pf = (ef0 / ef1).ln() / (h0 / h1).ln();
        println!("observed order h = {h0:e} → {h1:e}: deflection {pz:.3}, wheel force {pf:.3}");
        assert!(
            (0.7..=1.5).contains(&pz),
            "deflection: observed order {pz} (errors {ez0:e}, {ez1:e}) outside [0.7, 1.5]"
        );
        assert!(
            (0.7..=1.5).contains(&pf),
            "wheel force: observed order {pf} (errors {ef0:e}, {ef1:e}) outside [0.7, 1.5]"
        );
    }
    // and the explicit coupling is close at the finest step
    let finest = errors.last().expect("errors");
    assert!(
        finest.1 < 0.05,
        "deflection error {} at h = {}",
        finest.1,
        finest.0
    );
}
