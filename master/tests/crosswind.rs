//! The characteristic wind curve: `tbi sweep --speeds … --wind-speeds …` on two coaches over
//! the 60 m span (`tests/data/coaches-60m.toml` with a `[wind]` deck). The largest wheel
//! unloading ΔQ/Q₀ grows with the wind at every train speed, and the wind that brings it
//! to the limit falls with the train speed (the relative wind grows and turns towards the
//! train's axis, where the coefficients rise fastest). Bad options are refused by name.

mod cli_support;

use cli_support::Scenario;
use tbi_tests::{assert_same_table, run, run_ok, scratch, tbi_command, text};

#[test]
fn the_characteristic_wind_curve_falls_with_train_speed() {
    let dir = scratch("wind-curve");
    let deck: toml::Table = toml::from_str("width_m = 12.0\ndrag = 1.5").unwrap();
    let path = Scenario::from_data("coaches-60m.toml")
        .set("wind", "mean_speed_m_s", 0.0)
        .set("wind", "deck", toml::Value::Table(deck))
        .write(&dir, "scenario.toml");
    let out = run_ok(
        tbi_command()
            .arg("sweep")
            .arg(&path)
            .args([
                "--solver",
                "monolithic",
                "--speeds",
                "200,250,300",
                "--wind-speeds",
                "0:60:10",
                "--out",
            ])
            .arg(dir.join("sweep")),
    );
    let stdout = text(&out.stdout);
    let cases = std::fs::read_to_string(dir.join("sweep/wind_cases.csv")).unwrap();
    let mut lines = cases.lines();
    assert_eq!(
        lines.next(),
        Some("speed_kmh,wind_speed_m_s,wheel_unloading_max,derail_factor_wheel_max")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 3 * 7);
    for v in [200.0, 250.0, 300.0] {
        let mine: Vec<&Vec<f64>> = rows.iter().filter(|r| r[0] == v).collect();
        for w in mine.windows(2) {
            assert!(
                w[1][1] > w[0][1] && w[1][2] > w[0][2],
                "ΔQ/Q₀ must grow with the wind: {mine:?}"
            );
        }
    }
    let curve = std::fs::read_to_string(dir.join("sweep/wind_curve.csv")).unwrap();
    let winds: Vec<f64> = curve
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
                .nth(1)
                .unwrap()
                .parse()
                .expect("every speed reaches the limit")
        })
        .collect();
    assert_eq!(winds.len(), 3, "{curve}");
    assert!(
        winds[0] > winds[1] && winds[1] > winds[2],
        "curve {winds:?}"
    );
    // the crossing lies between the bracketing cases
    for (k, v) in [200.0, 250.0, 300.0].iter().enumerate() {
        let at = |u: f64| {
            rows.iter()
                .find(|r| r[0] == *v && r[1] == u)
                .map(|r| r[2])
                .unwrap()
        };
        let lo = (winds[k] / 10.0).floor() * 10.0;
        assert!(at(lo) <= 0.9 && at(lo + 10.0) > 0.9, "{v} km/h: {curve}");
    }
    assert!(
        stdout.contains("characteristic wind speed (ΔQ/Q₀ = 0.9"),
        "{stdout}"
    );
    let svg = std::fs::read_to_string(dir.join("sweep/wind_curve.svg")).unwrap();
    assert!(svg.starts_with("<svg"), "wind_curve.svg");
    // refusals
    for (args, needle) in [
        (vec!["--wind-speeds", "-5"], "wind.mean_speed_m_s"),
        (vec!["--wind-speeds", "10:0:5"], "--wind-speeds 10:0:5"),
        (
            vec!["--wind-speeds", "10", "--wheel-unloading-limit", "0"],
            "--wheel-unloading-limit",
        ),
    ] {
        let r = run(tbi_command()
            .arg("sweep")
            .arg(&path)
            .args(["--speeds", "200"])
            .args(&args)
            .arg("--out")
            .arg(dir.join("bad")));
        let err = text(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{err}");
        assert!(err.contains(needle), "{needle:?} not in {err}");
    }
}

/// A measured wind record (`[wind] record`) that holds exactly the field the generator makes
/// at the deck points gives the monolithic run of the generated turbulence (to round-off:
/// the record is read at the same points and times), and through the three FMUs (the wind
/// FMU carrying the record) the same solution to 1e-8 per column; a record together with
/// `turbulence`, or one with a missing point, is refused by name.
#[test]
fn a_recorded_wind_gives_the_run_of_the_field_it_records() {
    use cli_support::run;
    let dir = scratch("wind-record");
    let deck: toml::Table = toml::from_str(
        "width_m = 12.0\ndrag = 1.5\nlift = 0.3\nmoment = 0.1\nlift_slope = 3.0\nmoment_slope = 0.8",
    )
    .unwrap();
    let base = Scenario::from_data("coaches-60m.toml")
        .set("track", "irregularity", "none")
        .set("wind", "mean_speed_m_s", 25.0)
        .set("wind", "deck_points", 16)
        .set("wind", "deck", toml::Value::Table(deck));
    let generated = base
        .clone()
        .set("wind", "turbulence", toml::Value::Table(toml::Table::new()))
        .write(&dir, "generated.toml");
    let reference = run(&generated, "monolithic", &dir.join("generated"), &[]);
    reference.expect_ok("generated turbulence");
    let steps = reference.summary()["steps"].as_u64().unwrap() as f64;
    // the field the run generated: default turbulence, 16 points over the 60 m deck, the
    // run's duration
    let x: Vec<f64> = (0..16).map(|j| 60.0 * j as f64 / 15.0).collect();
    let field =
        tbi_wind::WindField::generate(&Default::default(), 25.0, &x, steps * 0.001).unwrap();
    assert!((field.n_times() - 1) as f64 * field.dt_s >= steps * 0.001);
    let mut csv = String::from("time_s,x_m,u_m_s,w_m_s\n");
    for i in 0..field.n_times() {
        for (j, xj) in x.iter().enumerate() {
            csv.push_str(&format!(
                "{},{xj},{},{}\n",
                field.t0_s + i as f64 * field.dt_s,
                field.u[j][i],
                field.w[j][i]
            ));
        }
    }
    std::fs::write(dir.join("wind.csv"), &csv).unwrap();
    // the interface iterated to rtol = 1e-12, as in the other equivalence tests
    let recorded = base.clone().set("wind", "record", "wind.csv").coupling(
        "scheme = \"implicit\"\nacceleration = \"iqn-ils\"\nrtol = 1e-12\natol = 1e-12\n",
    );
    let path = recorded.write(&dir, "recorded.toml");
    let mono = run(&path, "monolithic", &dir.join("recorded"), &[]);
    mono.expect_ok("recorded turbulence");
    assert_same_table(
        &reference.history(),
        &mono.history(),
        1e-12,
        "recorded against generated turbulence",
    );
    let cosim = run(&path, "cosim", &dir.join("recorded-cosim"), &[]);
    cosim.expect_ok("recorded turbulence through the three FMUs");
    assert!(dir.join("recorded-cosim/fmus/wind.fmu").is_file());
    assert_same_table(
        &mono.history(),
        &cosim.history(),
        1e-8,
        "three FMUs with the record against the monolithic solver",
    );
    // refusals
    let both = recorded
        .clone()
        .set("wind", "turbulence", toml::Value::Table(toml::Table::new()))
        .write(&dir, "both.toml");
    let out = run(&both, "monolithic", &dir.join("both"), &[]);
    assert!(
        !out.ok() && out.stderr.contains("wind.record"),
        "{}",
        out.stderr
    );
    let broken: String = csv
        .lines()
        .enumerate()
        .filter(|(i, _)| *i != 5)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    std::fs::write(dir.join("broken.csv"), broken).unwrap();
    let bad = recorded
        .set("wind", "record", "broken.csv")
        .write(&dir, "broken.toml");
    let out = run(&bad, "monolithic", &dir.join("broken"), &[]);
    assert!(
        !out.ok() && out.stderr.contains("wind.record") && out.stderr.contains("broken.csv"),
        "{}",
        out.stderr
    );
}
