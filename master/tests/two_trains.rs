//! Several trains on a double-track deck (`[[train]]`, `[[bridge.track]]`).
//!
//! * **Superposition.** On a linear bridge under moving forces the deck's response is linear
//!   in the loads: two trains running in opposite directions on the two tracks (opposite
//!   eccentricities) give deck histories equal to the sum of each train's run alone, to 1e-9
//!   of each column's largest value, in the monolithic solver and through the FMUs (one train
//!   FMU per train).
//! * **Co-simulation ≡ monolithic** with two train FMUs of coaches (one running backward,
//!   with hunting, on an irregular track) to 1e-8 per column.
//! * Refusals, each naming the field: a track that does not exist, two trains on one track
//!   running towards each other, overlapping at the start or running into each other
//!   later, `[[bridge.track]]` beside `track_eccentricity_m`, two ways of placing one train.

mod cli_support;

use cli_support::{run, span_40m, Scenario, PROBES_40M, TIGHT_COUPLING};
use tbi_tests::{assert_same_table, require_fmu_libraries, scratch, Table};

/// Two tracks at ±2.05 m (on [`span_40m`]).
const TRACKS: &str = r#"[[bridge.track]]
eccentricity_m = 2.05
height_m = 1.25
[[bridge.track]]
eccentricity_m = -2.05
height_m = 1.25
"#;

/// Train 1: four axles forward at 200 km/h on track 1 from the deck start; train 2: two
/// lighter axles backward at 150 km/h on track 2, its first axle 12 m beyond the deck end.
const FORCES: [&str; 2] = [
    r#"
[[train]]
kind = "moving_force"
axles = [{ offset_m = 0.0, load_n = 1.5e5 }, { offset_m = 2.5, load_n = 1.5e5 }, { offset_m = 17.5, load_n = 1.5e5 }, { offset_m = 20.0, load_n = 1.5e5 }]
track = 1
speed_kmh = 200.0
start_x_m = 0.0
"#,
    r#"
[[train]]
kind = "moving_force"
axles = [{ offset_m = 0.0, load_n = 1.2e5 }, { offset_m = 3.0, load_n = 1.2e5 }]
track = 2
direction = "backward"
speed_kmh = 150.0
start_x_m = 52.0
"#,
];

/// A scenario of `trains` on the bridge.
fn scenario(trains: &[&str]) -> Scenario {
    let head = "name = \"two\"\n[run]\ndt_s = 0.002\nfree_vibration_s = 0.3\n";
    let bridge = span_40m(&format!("{TRACKS}{PROBES_40M}"));
    Scenario::parse(&format!(
        "{head}{bridge}{TIGHT_COUPLING}{}",
        trains.concat()
    ))
}

/// The deck's columns of `t` (the probes') that respond to vertical loads (moving forces
/// load no lateral mode).
fn deck_columns(t: &Table) -> Vec<String> {
    (t.columns.iter())
        .filter(|c| c.starts_with('p') && !c.contains("lateral"))
        .cloned()
        .collect()
}

/// `both − (a + b)` over the rows all three have, relative to each column's largest |value|
/// in `both`: the worst column and its figure.
fn superposition_defect(both: &Table, a: &Table, b: &Table) -> (String, f64) {
    let n = both.rows.len().min(a.rows.len()).min(b.rows.len());
    assert!(n > 300, "{n} rows in common");
    let mut worst = (String::new(), 0.0);
    for name in deck_columns(both) {
        let (cb, ca, cc) = (both.column(&name), a.column(&name), b.column(&name));
        let scale = cb[..n].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        assert!(scale > 0.0, "{name} is all zero");
        let d = (0..n)
            .map(|i| (cb[i] - ca[i] - cc[i]).abs())
            .fold(0.0, f64::max)
            / scale;
        if d > worst.1 {
            worst = (name, d);
        }
    }
    worst
}

fn superposition(solver: &str) {
    let dir = scratch(&format!("two-trains-superposition-{solver}"));
    let mut out = Vec::new();
    for (name, trains) in [
        ("both", &FORCES[..]),
        ("first", &FORCES[..1]),
        ("second", &FORCES[1..]),
    ] {
        let s = scenario(trains).write(&dir, &format!("{name}.toml"));
        let r = run(&s, solver, &dir.join(name), &[]);
        r.expect_ok(name);
        out.push(r.history());
    }
    let (name, d) = superposition_defect(&out[0], &out[1], &out[2]);
    assert!(d <= 1e-9, "{solver}: {name} differs from the sum by {d:e}");
    // the trains twist the deck, each its own way
    for (t, name) in out.iter().zip(["both", "first", "second"]) {
        let torsion = t.column("p20.torsion_rad");
        assert!(torsion.iter().any(|v| v.abs() > 1e-7), "{name}: no torsion");
    }
}

#[test]
fn two_trains_superpose_in_the_monolithic_solver() {
    superposition("monolithic");
}

#[test]
fn two_trains_superpose_through_two_train_fmus() {
    require_fmu_libraries();
    superposition("cosim");
}

#[test]
fn two_train_fmus_of_coaches_equal_the_monolithic_solution() {
    require_fmu_libraries();
    let dir = scratch("two-trains-coaches");
    let trains = r#"
[[train]]
kind = "coach_27dof"
preset = "xia2000"
vehicles = 2
track = 1
speed_kmh = 200.0
[[train]]
kind = "coach_27dof"
preset = "xia2000"
vehicles = 1
track = 2
direction = "backward"
speed_kmh = 150.0
meet_at_x_m = 25.0
hunting = { amplitude_m = 0.003, wavelength_m = 15.0, seed = 3 }
[track]
irregularity = { spectrum = "fra-5", seed = 7 }
"#;
    let s = scenario(&[trains]).write(&dir, "coaches.toml");
    let mono = run(&s, "monolithic", &dir.join("mono"), &[]);
    mono.expect_ok("monolithic");
    let co = run(&s, "cosim", &dir.join("co"), &[]);
    co.expect_ok("cosim");
    assert!(
        dir.join("co/fmus/train2.fmu").is_file(),
        "one FMU per train"
    );
    let (m, c) = (mono.history(), co.history());
    assert!(m
        .columns
        .iter()
        .any(|c| c == "train2.veh1.lateral_acceleration_m_s2"));
    assert_same_table(
        &m,
        &c,
        1e-8,
        "two trains of coaches, cosim against monolithic",
    );
}

/// A train entering later (`enter_time_s`) and one accelerating: `summary.json`'s `trains[]`
/// says when each reaches and leaves the deck, as their kinematics give it (to 1e-9 s).
#[test]
fn the_summary_says_when_each_train_is_on_the_deck() {
    let dir = scratch("two-trains-times");
    let first = FORCES[0].replace(
        "start_x_m = 0.0",
        "accelerating = { from_x_m = 10.0, acceleration_m_s2 = 2.0, to_speed_kmh = 250.0 }",
    );
    let second = FORCES[1].replace("start_x_m = 52.0", "enter_time_s = 0.5");
    let s = scenario(&[&first, &second]).write(&dir, "times.toml");
    let r = run(&s, "monolithic", &dir.join("out"), &[]);
    r.expect_ok("times");
    let trains = r.summary()["trains"].clone();
    let at = |k: usize, key: &str| trains[k][key].as_f64().unwrap();
    // train 1: 200 km/h to x = 10 m, then 2 m/s² until its last axle (20 m behind) leaves
    // the 40 m span: s = 10 + v₀ u + u²/2 · 2 = 60 m (250 km/h is not reached)
    let v0 = 200.0 / 3.6;
    let u = (-v0 + (v0 * v0 + 2.0 * 2.0 * 50.0_f64).sqrt()) / 2.0;
    assert!(v0 + 2.0 * u < 250.0 / 3.6);
    assert!((at(0, "enters_deck_s") - 0.0).abs() < 1e-9);
    assert!((at(0, "leaves_deck_s") - (10.0 / v0 + u)).abs() < 1e-9);
    // train 2: at the deck end at 0.5 s, its last axle (3 m behind) off the start 43 m on
    let v = 150.0 / 3.6;
    assert!((at(1, "enters_deck_s") - 0.5).abs() < 1e-9);
    assert!((at(1, "leaves_deck_s") - (0.5 + 43.0 / v)).abs() < 1e-9);
    assert_eq!(trains[1]["direction"], "backward");
    assert_eq!(trains[0]["speed_change"]["rate_m_s2"], 2.0);
}

/// `tbi run` of the scenario with these trains fails naming `field` and saying `why`.
fn refused(label: &str, trains: &str, field: &str, why: &str) {
    let dir = scratch(&format!("two-trains-refused-{label}"));
    let s = scenario(&[trains]).write(&dir, "bad.toml");
    let r = run(&s, "monolithic", &dir.join("out"), &[]);
    assert_eq!(r.status.code(), Some(1), "{label}: {}", r.stderr);
    assert!(
        r.stderr.contains(field) && r.stderr.contains(why),
        "{label}: {}",
        r.stderr
    );
}

#[test]
fn impossible_trains_are_refused_naming_the_field() {
    let second = FORCES[1];
    refused(
        "no-such-track",
        &format!("{}{}", FORCES[0], second.replace("track = 2", "track = 3")),
        "train[2].track",
        "there are 2 tracks",
    );
    refused(
        "towards-each-other",
        &format!("{}{}", FORCES[0], second.replace("track = 2", "track = 1")),
        "train[2].track",
        "towards each other",
    );
    let follower = FORCES[0].replace("start_x_m = 0.0", "start_x_m = -10.0");
    refused(
        "overlapping",
        &format!("{}{follower}", FORCES[0]),
        "train[2].track",
        "overlap on this track at t = 0",
    );
    // a faster train 30 m behind on the same track catches up with the first
    let faster = FORCES[0]
        .replace("start_x_m = 0.0", "start_x_m = -30.0")
        .replace("speed_kmh = 200.0", "speed_kmh = 400.0");
    refused(
        "catching-up",
        &format!("{}{faster}", FORCES[0]),
        "train[2].track",
        "would run into each other on this track",
    );
    refused(
        "placed-twice",
        &format!(
            "{}{}",
            FORCES[0],
            second.replace("start_x_m = 52.0", "start_x_m = 52.0\nenter_time_s = 1.0")
        ),
        "train[2].enter_time_s",
        "not start_x_m and enter_time_s",
    );
    refused(
        "track-zero",
        &FORCES[0].replace("track = 1", "track = 0"),
        "train[1].track",
        "numbered from 1",
    );
    let dir = scratch("two-trains-refused-both-track-forms");
    let s = scenario(&[FORCES[0]])
        .set("bridge", "track_eccentricity_m", 1.0)
        .write(&dir, "bad.toml");
    let r = run(&s, "monolithic", &dir.join("out"), &[]);
    assert_eq!(r.status.code(), Some(1), "{}", r.stderr);
    assert!(r.stderr.contains("bridge.track"), "{}", r.stderr);
}
