//! A train running backward (`train.direction = "backward"`, towards −x from the deck end).
//!
//! * **Symmetry.** Turning the whole system end for end about the vertical axis maps a
//!   forward run on a simply supported span with the track at eccentricity e onto the
//!   backward run with the track at −e: at every time, the deck at x ↔ L − x has the same
//!   vertical response and the opposite lateral one, the car bodies the same accelerations
//!   (in their own frames), the wheels the same vertical force and the opposite lateral
//!   force and roll moment; the deck's torsion turns round with it. Checked on the
//!   monolithic solver's histories to 1e-9 of each column's largest value for a coach with
//!   every force component active on an ideal track (its accelerations, made by the
//!   iterative solve to round-off, agree to about 5e-11), and to 1e-12 for moving forces.
//! * **Co-simulation ≡ monolithic** for the backward train (the train FMU runs it; the
//!   bridge FMU takes its positions) to 1e-8 per column.
//! * A backward train starting before the deck start is refused, naming the key.

mod cli_support;

use cli_support::{run, span_40m, Scenario, PROBES_40M, TIGHT_COUPLING};
use tbi_tests::{assert_same_table, require_fmu_libraries, scratch, Table};

/// A 40 m span (vertical, lateral and torsional modes), one Xia coach at 120 km/h on an
/// ideal track at eccentricity `e`, probes at 10, 20 and 30 m.
fn scenario(e: f64, direction: &str) -> Scenario {
    with_train(e, direction, COACH)
}

/// One Xia coach.
const COACH: &str = "kind = \"coach_27dof\"\npreset = \"xia2000\"\nvehicles = 1";

/// The monolithic histories of `train` running forward with the track at e = 1.2 m and
/// backward with it at −1.2 m: the same system turned end for end.
fn forward_and_backward(label: &str, train: &str) -> (Table, Table) {
    let dir = scratch(label);
    let forward = with_train(1.2, "forward", train).write(&dir, "forward.toml");
    let backward = with_train(-1.2, "backward", train).write(&dir, "backward.toml");
    let f = run(&forward, "monolithic", &dir.join("f"), &[]);
    f.expect_ok("forward");
    let b = run(&backward, "monolithic", &dir.join("b"), &[]);
    b.expect_ok("backward");
    let (f, b) = (f.history(), b.history());
    assert_eq!(f.rows.len(), b.rows.len());
    (f, b)
}

/// [`scenario`] with the train `train` (its `[train]` keys but the direction).
fn with_train(e: f64, direction: &str, train: &str) -> Scenario {
    let bridge = span_40m(&format!(
        "track_eccentricity_m = {e:?}\ntrack_height_m = 1.5"
    ));
    Scenario::parse(&format!(
        r#"name = "backward"
[run]
speed_kmh = 120.0
dt_s = 0.002
free_vibration_s = 0.3
{bridge}[train]
{train}
direction = "{direction}"
{PROBES_40M}{TIGHT_COUPLING}"#
    ))
}

/// Largest |a − s·b| over the rows, relative to the largest |a| (0 when both are zero).
fn mismatch(a: &[f64], b: &[f64], sign: f64) -> f64 {
    let scale = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - sign * y).abs())
        .fold(0.0, f64::max);
    if scale == 0.0 {
        worst
    } else {
        worst / scale
    }
}

/// Each probe and its mirror image about midspan.
const MIRRORED_PROBES: [(&str, &str); 3] = [("p10", "p30"), ("p20", "p20"), ("p30", "p10")];

/// The deck's columns and their sign in the mirror image: the lateral displacement and the
/// torsion (about x, which turns round) change sign.
const DECK: [(&str, f64); 5] = [
    ("vertical_displacement_m", 1.0),
    ("vertical_acceleration_m_s2", 1.0),
    ("lateral_displacement_m", -1.0),
    ("lateral_acceleration_m_s2", -1.0),
    ("torsion_rad", -1.0),
];

/// Moving forces (three axles at the track's eccentricity): the deck's displacement and
/// torsion histories of the backward run are the mirror images of the forward run's to
/// 1e-12 (the load is linear in the shapes at the axles, which the two runs place at x and
/// L − x, equal to the round-off of those positions, about 1e-15 of the load). The
/// accelerations are held to 1e-11: at 120 km/h the span responds almost statically, so
/// `q̈ = F − 2ζω q̇ − ω² q` is a small difference of the load, and the load's round-off
/// is thousands of times larger against it (measured: 6e-12).
#[test]
fn backward_moving_forces_mirror_the_forward_run_to_1e_12() {
    let axles = "kind = \"moving_force\"\naxles = [{ offset_m = 0.0, load_n = 2.0e5 }, { offset_m = 3.0, load_n = 1.5e5 }, { offset_m = 11.0, load_n = 1.8e5 }]";
    let (f, b) = forward_and_backward("backward-symmetry-forces", axles);
    for (p, q) in MIRRORED_PROBES {
        // moving forces are vertical: no lateral response to mirror
        for (quantity, sign) in DECK.iter().filter(|d| !d.0.starts_with("lateral")) {
            let (ours, theirs) = (format!("{p}.{quantity}"), format!("{q}.{quantity}"));
            let d = mismatch(&f.column(&ours), &b.column(&theirs), *sign);
            let tol = if quantity.contains("acceleration") {
                1e-11
            } else {
                1e-12
            };
            assert!(d <= tol, "{ours} against {theirs} (×{sign}): {d:e}");
        }
    }
    let torsion = f.column("p20.torsion_rad");
    assert!(torsion.iter().any(|v| v.abs() > 1e-7), "no torsion");
}

#[test]
fn a_backward_run_is_the_forward_run_turned_end_for_end() {
    let (f, b) = forward_and_backward("backward-symmetry", COACH);
    let mut checked = 0;
    let mut check = |ours: &str, theirs: &str, sign: f64| {
        let d = mismatch(&f.column(ours), &b.column(theirs), sign);
        assert!(d <= 1e-9, "{ours} against {theirs} (×{sign}): {d:e}");
        checked += 1;
    };
    for (p, q) in MIRRORED_PROBES {
        for (quantity, sign) in DECK {
            check(&format!("{p}.{quantity}"), &format!("{q}.{quantity}"), sign);
        }
    }
    for quantity in ["vertical_acceleration_m_s2", "lateral_acceleration_m_s2"] {
        let name = format!("veh1.{quantity}");
        check(&name, &name, 1.0);
    }
    for w in 1..=4 {
        for (quantity, sign) in [
            ("vertical_force_n", 1.0),
            ("lateral_force_n", -1.0),
            ("roll_moment_nm", -1.0),
            // Q/P, signed with the lateral force
            ("derail_factor", -1.0),
            ("offload_factor", 1.0),
        ] {
            let name = format!("ws{w}.{quantity}");
            check(&name, &name, sign);
        }
    }
    assert_eq!(checked, 37);
    // the response is not trivial: the deck moves both ways and the wheels push sideways
    let lateral = f.column("ws1.lateral_force_n");
    assert!(
        lateral.iter().any(|v| v.abs() > 1.0),
        "no lateral wheel force"
    );
    let d = f.column("p20.vertical_displacement_m");
    assert!(d.iter().any(|v| v.abs() > 1e-4), "no deck displacement");
}

#[test]
fn a_backward_cosimulation_equals_the_monolithic_solution() {
    require_fmu_libraries();
    let dir = scratch("backward-cosim");
    let s = scenario(-1.2, "backward").write(&dir, "backward.toml");
    let mono = run(&s, "monolithic", &dir.join("mono"), &[]);
    mono.expect_ok("monolithic");
    let cosim = run(&s, "cosim", &dir.join("cosim"), &[]);
    cosim.expect_ok("cosim");
    assert_same_table(
        &mono.history(),
        &cosim.history(),
        1e-8,
        "backward co-simulation",
    );
}

#[test]
fn a_backward_train_must_start_after_the_deck_start() {
    let dir = scratch("backward-refused");
    let s = scenario(0.0, "backward")
        .set("run", "start_x_m", -5.0)
        .write(&dir, "s.toml");
    let r = run(&s, "monolithic", &dir.join("out"), &[]);
    assert!(!r.ok());
    assert!(
        r.stderr.contains("run.start_x_m") && r.stderr.contains("backward train"),
        "{}",
        r.stderr
    );
    let bad = scenario(0.0, "sideways").write(&dir, "bad.toml");
    let r = run(&bad, "monolithic", &dir.join("bad"), &[]);
    assert!(
        r.stderr.contains("train.direction") && r.stderr.contains("\"sideways\""),
        "{}",
        r.stderr
    );
}
