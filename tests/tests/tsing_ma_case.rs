//! The paper's case study end to end: the embedded Tsing Ma scenario.
//!
//! * `tbi sweep` at 20, 40, 70 and 120 km/h (monolithic solver, for speed): deck vertical
//!   displacement maxima within 10 % of the paper's Table 2, increasing with speed as in the
//!   paper; derail and offload maxima below the 0.8 / 0.6 limits; the table files written.
//! * `tbi run` (the main job: co-simulation of the two FMUs) at 70 km/h equals the monolithic
//!   solver at the scenario's interface tolerance, with the plots of Figures 8–11 written,
//!   and through the FMI 3.0 FMUs gives the same history.
mod common;
use common::tbi;
use std::process::Command;
use tbi::output::summary::Summary;
use tbi_tests::{compare, run_ok, scratch, worst, Table};

const PAPER_DECK_DISPLACEMENT_CM: [f64; 4] = [49.39, 49.52, 51.29, 54.04];

/// `summary.json` of a run, as the typed summary `tbi` writes.
fn read_summary(out: &std::path::Path) -> Summary {
    Summary::read(&out.join("summary.json")).unwrap()
}

fn deck_max_cm(s: &Summary) -> f64 {
    ["A", "B", "C", "D"]
        .iter()
        .map(|p| s.probes[*p].vertical_displacement_max_m)
        .fold(0.0, f64::max)
        * 100.0
}

#[test]
fn table2_deck_displacement_and_safety() {
    let out = scratch("tsing-ma-sweep");
    run_ok(
        Command::new(tbi())
            .args([
                "sweep",
                "--solver",
                "monolithic",
                "--speeds",
                "20,40,70,120",
                "--out",
            ])
            .arg(&out),
    );
    assert!(out.join("table.md").is_file() && out.join("table.csv").is_file());
    let mut last = 0.0;
    for (k, v) in ["20", "40", "70", "120"].iter().enumerate() {
        let s = read_summary(&out.join(format!("v{v}")));
        let ours = deck_max_cm(&s);
        let paper = PAPER_DECK_DISPLACEMENT_CM[k];
        println!(
            "{v} km/h: deck vertical displacement {ours:.2} cm (paper {paper} cm, ratio {:.3})",
            ours / paper
        );
        assert!(
            (ours / paper - 1.0).abs() <= 0.10,
            "{v} km/h: {ours} cm vs the paper's {paper} cm"
        );
        assert!(
            ours > last,
            "deck displacement does not grow with speed at {v} km/h"
        );
        last = ours;
        let safety = s
            .safety
            .as_ref()
            .expect("coaches have wheel-rail safety maxima");
        let (derail, offload) = (safety.derail_factor_max, safety.offload_factor_max);
        assert!(
            derail > 0.0 && derail < 0.8,
            "{v} km/h: derail factor {derail}"
        );
        assert!(
            offload > 0.0 && offload < 0.6,
            "{v} km/h: offload factor {offload}"
        );
    }
    let csv = std::fs::read_to_string(out.join("table.csv")).unwrap();
    assert!(
        csv.lines().count() == 9,
        "Table 2 has eight rows plus the header:\n{csv}"
    );
}

#[test]
fn default_cosimulation_equals_monolithic() {
    let co = scratch("tsing-ma-cosim");
    let mono = scratch("tsing-ma-mono");
    run_ok(
        Command::new(tbi())
            .args(["run", "--quiet", "--out"])
            .arg(&co),
    );
    run_ok(
        Command::new(tbi())
            .args(["run", "--quiet", "--solver", "monolithic", "--out"])
            .arg(&mono),
    );
    let s = read_summary(&co);
    assert_eq!(s.solver, "cosim");
    let coupling = s.coupling.expect("a co-simulation reports its coupling");
    assert_eq!(coupling.accepted_unconverged, 0);
    assert!(coupling.iterations_mean >= 2.0);
    for plot in [
        "deck_vertical.svg",
        "deck_lateral.svg",
        "vehicle1_acceleration.svg",
    ] {
        assert!(co.join(plot).is_file(), "{plot} missing");
    }
    let a = Table::read(&co.join("history.csv"));
    let b = Table::read(&mono.join("history.csv"));
    // The default interface tolerance is rtol = 1e-10 (weighted RMS). Measured: the worst
    // column (B.vertical_acceleration_m_s2) differs by 2.9e-8 of its max |value| (the
    // README's 3e-8, since the monolithic solver's iterations start from extrapolated
    // corrections; 7.1e-8 before, 3.8e-8 before its preconditioner was carried forward in
    // time, 6.3e-8 before its sums were reordered; its own round-off in that column, against
    // a direct solve, was 4–7e-8); the bound, set at twice the 6.3e-8, is unchanged. The
    // tests of the master show 1e-8 at rtol = 1e-12.
    let (column, rel) = worst(&compare(&b, &a));
    println!("worst column {column} at {rel:e}");
    assert!(
        rel < 1.3e-7,
        "co-simulation differs from monolithic in {column} by {rel:e}"
    );
    // through the FMI 3.0 FMUs (the same binaries): the same history, row for row
    let co3 = scratch("tsing-ma-cosim-fmi3");
    run_ok(
        Command::new(tbi())
            .args(["run", "--quiet", "--fmi-version", "3", "--out"])
            .arg(&co3),
    );
    let c = Table::read(&co3.join("history.csv"));
    assert_eq!(c.columns, a.columns);
    assert!(
        c.rows == a.rows,
        "the FMI 3.0 co-simulation differs from the FMI 2.0 one"
    );
}

/// `tbi run --meeting`: two 8-coach trains, one per track (e = ±2.05 m), meeting at mid
/// main span. Through the bridge FMU and two train FMUs it equals the monolithic solver at
/// the default case's bound; the summary reports both trains and the meeting at x = 1141 m.
#[test]
fn meeting_cosimulation_equals_monolithic() {
    let co = scratch("tsing-ma-meeting-cosim");
    let mono = scratch("tsing-ma-meeting-mono");
    run_ok(
        Command::new(tbi())
            .args(["run", "--meeting", "--quiet", "--out"])
            .arg(&co),
    );
    run_ok(
        Command::new(tbi())
            .args([
                "run",
                "--meeting",
                "--quiet",
                "--solver",
                "monolithic",
                "--out",
            ])
            .arg(&mono),
    );
    assert!(
        co.join("fmus/train2.fmu").is_file(),
        "one train FMU per train"
    );
    assert!(co.join("train2_vehicle1_acceleration.svg").is_file());
    let s = read_summary(&co);
    let coupling = s
        .coupling
        .as_ref()
        .expect("a co-simulation reports its coupling");
    assert_eq!(coupling.accepted_unconverged, 0);
    assert_eq!(s.trains.len(), 2);
    assert_eq!((s.trains[0].track, s.trains[1].track), (1, 2));
    assert_eq!(s.meetings.len(), 1, "{:?}", s.meetings);
    let m = &s.meetings[0];
    assert!((m.x_m - 1141.0).abs() < 1e-6, "they meet at {} m", m.x_m);
    let a = Table::read(&mono.join("history.csv"));
    let b = Table::read(&co.join("history.csv"));
    assert!(b
        .columns
        .iter()
        .any(|c| c == "train2.ws32.vertical_force_n"));
    let (column, rel) = worst(&compare(&a, &b));
    println!("worst column {column} at {rel:e}");
    assert!(
        rel < 1.3e-7,
        "co-simulation differs from monolithic in {column} by {rel:e}"
    );
}
