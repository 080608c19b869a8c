//! Implicit co-simulation of the bridge and train FMUs (`tbi run --solver cosim`) against the
//! monolithic solver (`--solver monolithic`) of the same scenario, column by column of
//! `history.csv`, and the iterations per step each acceleration needs.
//!
//! For the same Newmark integrators, the converged interface iteration reproduces the
//! monolithic step, so every column must agree to max |difference| / max |value| ≤ 1e-8
//! (all-zero columns exactly). The interface tolerance is tightened to rtol = 1e-12 so that
//! the iteration error stays well below that bound in derived columns such as the offload
//! factor (P0 − P)/P0, whose dynamic part is a few percent of P. The absolute floor is
//! atol = 1e-12 in every case. Lateral forces and roll moments pass through zero (case b);
//! the measure compares each value with the largest of its group (same FMU, same unit), so a
//! force near zero is held to rtol × the largest wheel force rather than to the rounding
//! noise of its own computation.
//!
//! Run with `cargo test --release -p tbi --test cosim_implicit -- --nocapture` to see the
//! iteration table.

mod cli_support;

/// Absolute floor of the interface tolerance (N, N·m, m, m/s).
const ATOL: f64 = 1e-12;

use cli_support::{number_after, run, Scenario};
use tbi_tests::{assert_same_table, compare, require_fmu_libraries, scratch, worst, Table};

/// Bound of max |cosim − monolithic| / max |monolithic| in every column.
const TOL: f64 = 1e-8;
/// Sweeps allowed per step in the implicit runs.
const MAX_ITERATIONS: u64 = 100;

/// One coupling configuration of the comparison.
struct Method {
    label: &'static str,
    scheme: &'static str,
    acceleration: &'static str,
    relaxation: f64,
    /// IQN-ILS: the steps whose secant columns are reused.
    reuse_steps: usize,
}

const PLAIN: Method = Method {
    label: "implicit, constant ω = 1 (plain Gauss–Seidel)",
    scheme: "implicit",
    acceleration: "constant",
    relaxation: 1.0,
    reuse_steps: 0,
};
const CONSTANT_HALF: Method = Method {
    label: "implicit, constant ω = 0.5",
    scheme: "implicit",
    acceleration: "constant",
    relaxation: 0.5,
    reuse_steps: 0,
};
const AITKEN: Method = Method {
    label: "implicit, Aitken (ω₀ = 0.5)",
    scheme: "implicit",
    acceleration: "aitken",
    relaxation: 0.5,
    reuse_steps: 0,
};
const IQN_ILS: Method = Method {
    label: "implicit, IQN-ILS (ω₀ = 0.5), within the step",
    scheme: "implicit",
    acceleration: "iqn-ils",
    relaxation: 0.5,
    reuse_steps: 0,
};
/// The default acceleration: IQN-ILS with the columns of the last 8 steps. It learns across
/// steps, so it is left out of the comparison of sweeps with Newton, which learns within one.
const IQN_ILS_REUSE: Method = Method {
    label: "implicit, IQN-ILS (ω₀ = 0.5), 8 steps reused",
    scheme: "implicit",
    acceleration: "iqn-ils",
    relaxation: 0.5,
    reuse_steps: 8,
};
const NEWTON: Method = Method {
    label: "implicit, Newton (finite-difference Jacobian)",
    scheme: "implicit",
    acceleration: "newton",
    relaxation: 0.5,
    reuse_steps: 0,
};
const EXPLICIT_GS: Method = Method {
    label: "explicit Gauss–Seidel",
    scheme: "gauss-seidel",
    acceleration: "aitken",
    relaxation: 0.5,
    reuse_steps: 0,
};

impl Method {
    fn coupling(&self) -> String {
        format!(
            "scheme = \"{}\"\nacceleration = \"{}\"\nrelaxation = {:?}\nrtol = 1e-12\n\
             atol = {ATOL:e}\nmax_iterations = {MAX_ITERATIONS}\non_non_convergence = \"stop\"\n\
             reuse_steps = {}\n",
            self.scheme, self.acceleration, self.relaxation, self.reuse_steps
        )
    }
}

/// What one co-simulation run gave.
struct Outcome {
    label: &'static str,
    ok: bool,
    stderr: String,
    coupling: serde_json::Value,
    /// Worst column and its max |cosim − monolithic| / max |monolithic| (successful runs).
    error: Option<(String, f64)>,
    history: Option<Table>,
}

impl Outcome {
    fn mean(&self) -> f64 {
        self.coupling["iterations_mean"]
            .as_f64()
            .unwrap_or(f64::NAN)
    }
}

/// Runs `scenario` monolithically and with each method; returns the monolithic history and
/// the outcomes.
fn run_case(label: &str, scenario: &Scenario, methods: &[&Method]) -> (Table, Vec<Outcome>) {
    require_fmu_libraries();
    let dir = scratch(label);
    let path = scenario.write(&dir, "scenario.toml");
    let mono = run(&path, "monolithic", &dir.join("monolithic"), &[]);
    mono.expect_ok("monolithic reference");
    let reference = mono.history();
    let steps = mono.summary()["steps"].as_u64().expect("steps");
    assert_eq!(
        reference.rows.len() as u64,
        steps + 1,
        "monolithic history rows"
    );
    let outcomes = methods
        .iter()
        .enumerate()
        .map(|(k, m)| {
            let p = Scenario::parse(&scenario.text())
                .coupling(&m.coupling())
                .write(&dir, &format!("cosim-{k}.toml"));
            let r = run(&p, "cosim", &dir.join(format!("cosim-{k}")), &[]);
            let summary = r.summary();
            let mut o = Outcome {
                label: m.label,
                ok: r.ok(),
                stderr: r.stderr.clone(),
                coupling: summary["coupling"].clone(),
                error: None,
                history: None,
            };
            if r.ok() {
                assert_eq!(summary["status"], "ok", "{}: status", m.label);
                let c = &summary["coupling"];
                assert_eq!(c["scheme"], m.scheme, "{}: coupling.scheme", m.label);
                if m.scheme == "implicit" {
                    assert_eq!(c["acceleration"], m.acceleration, "{}", m.label);
                }
                assert_eq!(
                    c["steps"].as_u64(),
                    Some(steps),
                    "{}: coupling.steps",
                    m.label
                );
                assert_eq!(c["accepted_unconverged"], 0, "{}", m.label);
                assert_eq!(c["rejected"], 0, "{}", m.label);
                let (mean, max) = (o.mean(), c["iterations_max"].as_u64().expect("max"));
                assert!(
                    mean >= 1.0 && mean <= max as f64 && max <= MAX_ITERATIONS,
                    "{}: iterations mean {mean}, max {max}",
                    m.label
                );
                if m.scheme != "implicit" {
                    assert_eq!((mean, max), (1.0, 1), "{}: one sweep per step", m.label);
                }
                // the steps by their sweeps: every step once, the mean and the largest as
                // reported
                let (by, counted, sweeps) = tbi_tests::steps_by_sweeps(&c["steps_by_iterations"]);
                assert_eq!(counted, steps, "{}: steps by sweeps", m.label);
                assert_eq!(sweeps as f64 / steps as f64, mean, "{}: mean", m.label);
                assert_eq!(by.len() as u64, max, "{}: largest", m.label);
                assert!(by.last().is_some_and(|&n| n > 0), "{}: {by:?}", m.label);
                let h = r.history();
                o.error = Some(worst(&compare(&reference, &h)));
                o.history = Some(h);
            } else {
                assert_eq!(summary["status"], "failed", "{}: status", m.label);
            }
            o
        })
        .collect();
    (reference, outcomes)
}

/// The iteration table of one case.
fn table(case: &str, outcomes: &[Outcome]) -> String {
    let mut s = format!(
        "\n{case}\n  {:<46} {:>10} {:>8} {:>7} {:>22}\n",
        "coupling", "iter mean", "iter max", "steps", "max rel. diff (column)"
    );
    for o in outcomes {
        if o.ok {
            let (col, e) = o.error.clone().unwrap_or_default();
            s.push_str(&format!(
                "  {:<46} {:>10.3} {:>8} {:>7} {:>10.2e} ({col})\n",
                o.label,
                o.mean(),
                o.coupling["iterations_max"].as_u64().unwrap_or_default(),
                o.coupling["steps"].as_u64().unwrap_or_default(),
                e
            ));
        } else {
            let why = if o.stderr.contains("did not converge") {
                format!(
                    "did not converge at t = {} s (residual {:.3e} after {MAX_ITERATIONS} sweeps)",
                    number_after(&o.stderr, "stopped at t = ").unwrap_or(f64::NAN),
                    number_after(&o.stderr, "residual ").unwrap_or(f64::NAN)
                )
            } else if o.stderr.contains("non-finite") {
                format!(
                    "blew up (non-finite values) at t = {} s",
                    number_after(&o.stderr, "stopped at t = ").unwrap_or(f64::NAN)
                )
            } else {
                o.stderr.lines().last().unwrap_or_default().to_string()
            };
            s.push_str(&format!("  {:<46} FAILED: {why}\n", o.label));
        }
    }
    s
}

fn equivalent(reference: &Table, o: &Outcome, case: &str) {
    assert!(
        o.ok,
        "{case}, {}: co-simulation failed:\n{}",
        o.label, o.stderr
    );
    assert_same_table(
        reference,
        o.history.as_ref().expect("history"),
        TOL,
        &format!("{case}, {} vs monolithic", o.label),
    );
}

/// The explicit scheme's first-order coupling error must be visible with the same measure,
/// so the comparison is not blind.
/// On these linear interface problems a Newton update with a fresh Jacobian converges in
/// one update plus the confirming sweep: fewer sweeps per step than every other method that
/// learns within the step (IQN-ILS reusing earlier steps' columns may need as few).
fn newton_needs_fewest_iterations(outcomes: &[Outcome], case: &str) {
    let newton = outcomes
        .iter()
        .find(|o| o.label == NEWTON.label)
        .expect("newton ran");
    for o in outcomes.iter().filter(|o| {
        o.ok && ![NEWTON.label, IQN_ILS_REUSE.label].contains(&o.label)
            && !o.label.starts_with("explicit")
    }) {
        assert!(
            newton.mean() < o.mean(),
            "{case}: Newton needs {} sweeps per step, {} needs {}",
            newton.mean(),
            o.label,
            o.mean()
        );
    }
}

fn explicit_error_visible(o: &Outcome, case: &str) {
    let (col, e) = o.error.clone().expect("explicit run succeeded");
    assert!(
        e > 1e-4,
        "{case}: explicit Gauss–Seidel differs from the monolithic solution by only {e:e} ({col})"
    );
}

/// (a) Yang & Yau (1997) sprung mass on a 25 m simply supported span, 20 modes.
#[test]
fn cosim_implicit_matches_monolithic_yang_yau() {
    let case = "(a) Yang–Yau sprung mass, 25 m span, 100 km/h, dt 0.5 ms, 20 modes";
    let scenario = Scenario::from_data("yang-yau.toml");
    let methods = [
        &PLAIN,
        &CONSTANT_HALF,
        &AITKEN,
        &IQN_ILS,
        &EXPLICIT_GS,
        &NEWTON,
        &IQN_ILS_REUSE,
    ];
    let (reference, outcomes) = run_case("yang-yau", &scenario, &methods);
    println!("{}", table(case, &outcomes));
    for o in outcomes[..4].iter().chain(&outcomes[5..]) {
        equivalent(&reference, o, case);
    }
    explicit_error_visible(&outcomes[4], case);
    newton_needs_fewest_iterations(&outcomes, case);
}

/// (b) Two 27-DOF coaches with German low-interference irregularity on a 60 m box girder with
/// vertical, lateral and torsional modes.
#[test]
fn cosim_implicit_matches_monolithic_two_coaches_with_irregularity() {
    let case = "(b) 2 × coach_27dof (xia2000), german-low, 60 m box girder, 160 km/h, dt 1 ms";
    let scenario = Scenario::from_data("coaches-60m.toml");
    let methods = [
        &PLAIN,
        &CONSTANT_HALF,
        &AITKEN,
        &IQN_ILS,
        &EXPLICIT_GS,
        &NEWTON,
        &IQN_ILS_REUSE,
    ];
    let (reference, outcomes) = run_case("coaches-60m", &scenario, &methods);
    println!("{}", table(case, &outcomes));
    // every response component is active, so the comparison covers all of them
    for name in [
        "mid.vertical_displacement_m",
        "mid.lateral_displacement_m",
        "quarter.lateral_acceleration_m_s2",
        "veh1.lateral_acceleration_m_s2",
        "veh2.vertical_acceleration_m_s2",
        "ws1.lateral_force_n",
        "ws1.roll_moment_nm",
        "ws8.derail_factor",
    ] {
        assert!(
            reference.max_abs(name) > 0.0,
            "{case}: column {name} is all zero in the monolithic run"
        );
    }
    for o in outcomes[..4].iter().chain(&outcomes[5..]) {
        equivalent(&reference, o, case);
    }
    explicit_error_visible(&outcomes[4], case);
    newton_needs_fewest_iterations(&outcomes, case);
}

/// (b′) The same case, on smooth track with 20 modes, in a mean crosswind (`[wind]`, 30 m/s on a 12 m deck with
/// drag, lift and moment, self-excited damping from flutter derivatives H₁* and A₂*,
/// buffeting by the default turbulence through Davenport's admittance, and on the car bodies
/// (in the turbulence itself) with the
/// default coefficients): the bridge
/// starts in its static response, whose midspan lateral and vertical displacements equal the
/// closed form 5 q L⁴ / (384 E I) of the simply supported span under a uniform load to 1e-3
/// (the modes kept); the first coach's four wheelsets carry its rolling moment
/// ½ρV²A h C_MR(β) (the moment balance; β = atan(U/v)); and co-simulation (Aitken, IQN-ILS)
/// equals the monolithic solver to the same 1e-8 per column.
#[test]
fn cosim_implicit_matches_monolithic_in_a_mean_crosswind() {
    let case = "(b′) case (b) with a 30 m/s mean wind on the deck";
    // smooth track: at t = 0 the coaches stand in their static equilibrium with no damper
    // force, so the rail forces are the moment balance of the body loads alone
    let mut scenario = Scenario::from_data("coaches-60m.toml")
        .set("track", "irregularity", "none")
        .set("bridge", "modes", 20)
        .set("wind", "mean_speed_m_s", 30.0);
    let deck: toml::Table = toml::from_str(
        "width_m = 12.0\ndrag = 1.5\nlift = 0.3\nmoment = 0.1\nadmittance = 7.0\n\
         flutter = { reduced_velocity = [0.5, 5.0], h1 = [-0.5, -3.0], a2 = [-0.05, 0.1] }",
    )
    .unwrap();
    scenario = scenario.set("wind", "deck", toml::Value::Table(deck)).set(
        "wind",
        "turbulence",
        toml::Value::Table(toml::Table::new()),
    );
    let (reference, outcomes) = run_case(
        "coaches-60m-wind",
        &scenario,
        &[&AITKEN, &IQN_ILS, &IQN_ILS_REUSE],
    );
    println!("{}", table(case, &outcomes));
    for o in &outcomes {
        equivalent(&reference, o, case);
    }
    // the static response at t = 0 against the closed forms (values of coaches-60m.toml)
    let (l, e, iv, ih) = (60.0_f64, 3.5e10, 9.0, 60.0);
    let qb = 0.5 * 1.225 * 30.0_f64.powi(2) * 12.0;
    let (qy, qz) = (qb * 1.5, -qb * 0.3);
    for (column, expected) in [
        (
            "mid.lateral_displacement_m",
            5.0 * qy * l.powi(4) / (384.0 * e * ih),
        ),
        (
            "mid.vertical_displacement_m",
            5.0 * qz * l.powi(4) / (384.0 * e * iv),
        ),
    ] {
        let got = reference.column(column)[0];
        assert!(
            (got / expected - 1.0).abs() < 1e-3,
            "{column} at t = 0: {got} m, closed form {expected} m"
        );
    }
    // the rolling moment of the default table (C_MR 1.9 at 30°, 2.4 at 40°; A = 10 m², h = 3 m)
    let (v, u) = (160.0 / 3.6_f64, 30.0_f64);
    let beta = u.atan2(v).to_degrees();
    let c_mr = 1.9 + (beta - 30.0) / 10.0 * (2.4 - 1.9);
    let m_r = 0.5 * 1.225 * (v * v + u * u) * 10.0 * 3.0 * c_mr;
    let carried: f64 = (1..=4)
        .map(|k| reference.column(&format!("ws{k}.roll_moment_nm"))[0])
        .sum();
    assert!(
        (carried / m_r - 1.0).abs() < 1e-6,
        "Σ M_x of coach 1 at t = 0: {carried} N·m, rolling moment {m_r} N·m"
    );
}

/// (c) Light stiff 20 m span, heavy coaches: plain Gauss–Seidel iteration diverges and the
/// explicit scheme is unstable, while Aitken and IQN-ILS converge to the monolithic solution;
/// IQN-ILS needs no more iterations than Aitken.
#[test]
fn cosim_stiff_span_needs_acceleration() {
    let case =
        "(c) light stiff 20 m span (1 t/m), 2 heavy coaches (5 t wheelsets), 120 km/h, dt 1 ms";
    let scenario = Scenario::from_data("stiff-20m.toml");
    let methods = [
        &PLAIN,
        &CONSTANT_HALF,
        &AITKEN,
        &IQN_ILS,
        &EXPLICIT_GS,
        &NEWTON,
        &IQN_ILS_REUSE,
    ];
    let (reference, outcomes) = run_case("stiff-20m", &scenario, &methods);
    println!("{}", table(case, &outcomes));
    let [plain, _half, aitken, iqn, explicit, newton, iqn_reuse] = &outcomes[..] else {
        unreachable!()
    };

    // Plain Gauss–Seidel: the interface iteration does not converge within 100 sweeps.
    assert!(
        !plain.ok,
        "{case}: plain Gauss–Seidel was expected to fail but converged (mean {} iterations)",
        plain.mean()
    );
    assert!(
        plain.stderr.contains("did not converge") && plain.stderr.contains("residual"),
        "{case}: plain Gauss–Seidel failure message:\n{}",
        plain.stderr
    );
    let residual = number_after(&plain.stderr, "residual ").expect("residual in message");
    assert!(residual > 1.0, "reported residual {residual} ≤ 1");

    // Explicit staggering is unstable here: the run fails on non-finite values, or its
    // result is off by more than 100 %.
    match &explicit.error {
        None => assert!(!explicit.ok),
        Some((col, e)) => assert!(
            *e > 1.0,
            "{case}: explicit Gauss–Seidel was expected to be unstable, error only {e:e} ({col})"
        ),
    }

    for o in [aitken, iqn, newton, iqn_reuse] {
        equivalent(&reference, o, case);
    }
    newton_needs_fewest_iterations(&outcomes, case);
    assert!(
        iqn.mean() <= aitken.mean(),
        "{case}: IQN-ILS needs more iterations per step ({}) than Aitken ({})",
        iqn.mean(),
        aitken.mean()
    );
}
