//! A train braking on the bridge, through the scenario (`train.braking`).
//!
//! * **Co-simulation ≡ monolithic**: a coach braking from 120 to 60 km/h across a span
//!   (the train FMU carries the speed change and the pitching moments; the bridge FMU takes
//!   its positions and speeds) equals the monolithic solver to 1e-8 per column.
//! * A braking that stops the train on the deck is refused unless `to_speed_kmh = 0` says
//!   so; with it the run ends when the train has stopped, plus the free vibration; a final
//!   speed the braking cannot reach is refused.

mod cli_support;

use cli_support::{run, span_40m, Scenario, TIGHT_COUPLING};
use tbi_tests::{assert_same_table, require_fmu_libraries, scratch};

/// A 40 m span with vertical, lateral and torsional modes; one coach at `speed` km/h
/// braking as `braking` says.
fn scenario(speed: f64, braking: &str) -> Scenario {
    let bridge = span_40m("track_eccentricity_m = 1.2\ntrack_height_m = 1.5");
    Scenario::parse(&format!(
        r#"name = "braking"
[run]
speed_kmh = {speed:?}
dt_s = 0.002
free_vibration_s = 0.5
{bridge}[train]
kind = "coach_27dof"
vehicles = 1
braking = {braking}
[track]
irregularity = {{ spectrum = "fra-5", seed = 11 }}
[[probe]]
name = "mid"
x_m = 20.0
{TIGHT_COUPLING}"#
    ))
}

#[test]
fn a_braking_cosimulation_equals_the_monolithic_solution() {
    require_fmu_libraries();
    let dir = scratch("braking-cosim");
    let s = scenario(
        120.0,
        "{ from_x_m = 5.0, deceleration_m_s2 = 2.5, to_speed_kmh = 60.0 }",
    )
    .write(&dir, "braking.toml");
    let mono = run(&s, "monolithic", &dir.join("mono"), &[]);
    mono.expect_ok("monolithic");
    let co = run(&s, "cosim", &dir.join("co"), &[]);
    co.expect_ok("cosim");
    assert_same_table(
        &mono.history(),
        &co.history(),
        1e-8,
        "a braking coach, cosim against monolithic",
    );
    // the run lasts until the last axle (18.1 m behind the first) has left the span,
    // braking from 5 m on: s = 5 + v₀ u − a u²/2 = 58.1 m, then 0.5 s of free vibration
    let (v0, a) = (120.0 / 3.6, 2.5);
    let u = (v0 - (v0 * v0 - 2.0 * a * 53.1_f64).sqrt()) / a;
    let t_end = 5.0 / v0 + u + 0.5;
    let steps = mono.summary()["steps"].as_f64().unwrap();
    assert_eq!(steps, (t_end / 0.002 - 1e-9).ceil(), "{t_end} s");
}

#[test]
fn a_braking_that_stops_the_train_on_the_deck_must_say_so() {
    let dir = scratch("braking-stop");
    // 30 km/h at 3 m/s² stops within 12 m, the last axle still before the deck's end
    let unsaid =
        scenario(30.0, "{ from_x_m = 2.0, deceleration_m_s2 = 3.0 }").write(&dir, "unsaid.toml");
    let r = run(&unsaid, "monolithic", &dir.join("unsaid"), &[]);
    assert_eq!(r.status.code(), Some(1), "{}", r.stderr);
    for part in ["train.braking.to_speed_kmh", "to_speed_kmh = 0"] {
        assert!(r.stderr.contains(part), "{}", r.stderr);
    }
    let said = scenario(
        30.0,
        "{ from_x_m = 2.0, deceleration_m_s2 = 3.0, to_speed_kmh = 0.0 }",
    )
    .write(&dir, "said.toml");
    let r = run(&said, "monolithic", &dir.join("said"), &[]);
    r.expect_ok("stopping on the deck, said");
    // it brakes from 2 m at 30 km/h: stopped at t = 2/v + v/a, then 0.5 s of free vibration
    let v = 30.0 / 3.6;
    let t_end = 2.0 / v + v / 3.0 + 0.5;
    let simulated = r.summary()["simulated_time_s"].as_f64().unwrap();
    assert!(
        (simulated - t_end).abs() <= 0.002,
        "{simulated} s against {t_end} s"
    );
    let faster = scenario(
        30.0,
        "{ from_x_m = 2.0, deceleration_m_s2 = 3.0, to_speed_kmh = 40.0 }",
    )
    .write(&dir, "faster.toml");
    let r = run(&faster, "monolithic", &dir.join("faster"), &[]);
    assert_eq!(r.status.code(), Some(1), "{}", r.stderr);
    assert!(
        r.stderr.contains("train.braking.to_speed_kmh"),
        "{}",
        r.stderr
    );
}

/// The car bodies' wind loads take a constant speed: a wind on a braking train is refused,
/// naming the braking.
#[test]
fn a_wind_on_a_braking_train_is_refused() {
    let dir = scratch("braking-wind");
    let s = scenario(
        120.0,
        "{ from_x_m = 5.0, deceleration_m_s2 = 2.5, to_speed_kmh = 60.0 }",
    )
    .set("wind", "mean_speed_m_s", 10.0)
    .write(&dir, "windy.toml");
    let text = std::fs::read_to_string(&s).unwrap();
    let deck = "[wind.deck]\nwidth_m = 10.0\ndrag = 1.0\nlift = 0.1\nmoment = 0.01\n";
    std::fs::write(&s, format!("{text}{deck}")).unwrap();
    let r = run(&s, "monolithic", &dir.join("out"), &[]);
    assert_eq!(r.status.code(), Some(1), "{}", r.stderr);
    assert!(
        r.stderr.contains("train.braking") && r.stderr.contains("constant speed"),
        "{}",
        r.stderr
    );
}
