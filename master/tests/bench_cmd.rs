//! `tbi bench --quick --json FILE`: the figures under the stable names the performance issue
//! defines, and what they are made of agreeing with each other (one repeat of the bench case
//! on each solver, in process and through FMU workers; timings are not asserted).

use tbi_tests::{read_json, require_fmu_libraries, run_ok, scratch, steps_by_sweeps, tbi_command};

#[test]
fn bench_json_has_the_stable_names_and_consistent_figures() {
    require_fmu_libraries();
    let dir = scratch("bench-quick");
    let json = dir.join("bench.json");
    run_ok(
        tbi_command()
            .arg("bench")
            .args(["--quick", "--repeat", "1", "--out"])
            .arg(dir.join("runs"))
            .arg("--json")
            .arg(&json),
    );
    let f = read_json(&json);
    let number = |name: &str| {
        f[name]
            .as_f64()
            .unwrap_or_else(|| panic!("{name} is not a number: {}", f[name]))
    };
    let (mono, cosim, ratio) = (
        number("monolithic_realtime_factor"),
        number("cosim_realtime_factor"),
        number("cosim_over_monolithic"),
    );
    assert!(mono > 0.0 && cosim > 0.0, "{mono} {cosim}");
    assert!(
        (ratio - mono / cosim).abs() <= 1e-9 * ratio,
        "{ratio} vs {mono}/{cosim}"
    );
    // the bench case's steps by their sweeps give its mean sweeps per step
    let (by, steps, sweeps) = steps_by_sweeps(&f["cosim_steps_by_iterations"]);
    assert_eq!(steps, 22_378, "{by:?}");
    assert_eq!(
        sweeps as f64 / steps as f64,
        number("cosim_iterations_per_step")
    );
    // through workers, a sweep costs one round trip per FMU (inputs, step and outputs in
    // one): two per sweep, plus the wiring's few
    let per_step = number("isolated_round_trips_per_step");
    let sweeps_per_step = number("cosim_iterations_per_step");
    assert!(
        per_step >= 2.0 * sweeps_per_step && per_step < 2.0 * sweeps_per_step + 0.01,
        "{per_step} round trips per step for {sweeps_per_step} sweeps"
    );
    assert!(number("isolated_over_in_process") > 0.0);
    assert!(number("isolated_round_trip_us") >= 0.0);
    let load = &f["load_average_before"];
    assert!(load.is_null() || load.as_f64().is_some(), "{load}");
    assert!(f["cores"].as_u64().is_some_and(|c| c >= 1));
}
