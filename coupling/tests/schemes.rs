//! Coupling schemes against the monolithic Newmark solution of the same linear system.

mod coupling_support;

use coupling_support::{relative_error, spectral_radius, Case, OUT};
use tbi_coupling::acceleration::{Acceleration, ConstantRelaxation, IqnIls};
use tbi_coupling::{
    build_scheme, CouplingConfig, CouplingScheme, GaussSeidel, Implicit, OnNonConvergence,
    Predictor, WeightedRms,
};

const H: f64 = 1e-3;
const STEPS: usize = 200;

fn config(text: &str) -> CouplingConfig {
    toml::from_str(text).unwrap_or_else(|e| panic!("{text}: {e}"))
}

fn implicit(acceleration: Box<dyn Acceleration>, max_iterations: usize) -> Implicit {
    Implicit::new(acceleration, WeightedRms::new(1e-10, 1e-12), max_iterations)
}

/// Spectral radius of the interface map just below 1: plain iteration crawls, constant
/// relaxation ω = 0.5 converges.
fn moderate() -> Case {
    Case::track(2, 200.0, 2e9)
}

/// Spectral radius ≈ 6: plain and ω = 0.5 iteration diverge.
fn stiff() -> Case {
    Case::track(4, 50.0, 1e10)
}

fn max_abs(u: &[Vec<f64>]) -> f64 {
    u.iter().flatten().fold(0.0, |m, &v| m.max(v.abs()))
}

#[test]
fn coupling_implicit_matches_monolithic_for_every_acceleration() {
    let case = moderate();
    let mono = case.monolithic(&[H; STEPS]);
    assert!(
        max_abs(&mono) > 1e-3,
        "the test needs a non-trivial response"
    );
    for text in [
        "acceleration = \"constant\"\nmax_iterations = 100",
        "acceleration = \"aitken\"",
        "acceleration = \"iqn-ils\"",
        "acceleration = \"iqn-ils\"\nreuse_steps = 2",
    ] {
        let mut scheme = build_scheme(&config(text)).unwrap();
        let run = case
            .run(scheme.as_mut(), H, STEPS, OnNonConvergence::Stop)
            .unwrap();
        let err = relative_error(&run.u, &mono);
        eprintln!(
            "{}: {} | error vs monolithic {err:.2e}",
            text.replace('\n', ", "),
            run.stats
        );
        assert_eq!(run.stats.steps, STEPS);
        assert_eq!(run.stats.accepted_unconverged, 0);
        assert!(run.stats.max_residual <= 1.0);
        assert!(err <= 1e-9, "{text}: relative error {err:e}");
    }
    // The comparison resolves coupling errors: a loose tolerance is visible in it.
    let mut loose = build_scheme(&config("acceleration = \"constant\"\nrtol = 1e-4")).unwrap();
    let run = case
        .run(loose.as_mut(), H, STEPS, OnNonConvergence::Stop)
        .unwrap();
    let err = relative_error(&run.u, &mono);
    assert!(err > 1e-8, "rtol = 1e-4 gave error {err:e}");
}

#[test]
fn coupling_predictor_changes_iterations_not_result() {
    let case = moderate();
    let mono = case.monolithic(&[H; STEPS]);
    for acceleration in ["constant", "iqn-ils"] {
        let mut runs = Vec::new();
        for predictor in ["quadratic", "linear", "constant"] {
            let text = format!(
                "acceleration = \"{acceleration}\"\npredictor = \"{predictor}\"\nmax_iterations = 100"
            );
            let mut scheme = build_scheme(&config(&text)).unwrap();
            let run = case
                .run(scheme.as_mut(), H, STEPS, OnNonConvergence::Stop)
                .unwrap();
            eprintln!("{acceleration}, predictor {predictor}: {}", run.stats);
            assert!(relative_error(&run.u, &mono) <= 1e-9);
            runs.push(run);
        }
        assert!(relative_error(&runs[0].u, &runs[2].u) <= 1e-9);
        assert!(relative_error(&runs[1].u, &runs[2].u) <= 1e-9);
        if acceleration == "constant" {
            let [q, l, c] = [0, 1, 2].map(|k| runs[k].stats.mean_iterations());
            assert!(
                q < l && l < c,
                "each higher order should save iterations of the linearly converging \
                 iteration on this smooth response: {q}, {l}, {c}"
            );
        }
    }
}

#[test]
fn coupling_explicit_schemes_are_first_order() {
    let case = Case::two_oscillators();
    let t_end = 2.0;
    for scheme in ["jacobi", "gauss-seidel"] {
        let mut errors = Vec::new();
        let mut defects = Vec::new();
        for h in [1e-2_f64, 5e-3, 2.5e-3] {
            let steps = (t_end / h).round() as usize;
            let mono = case.monolithic(&vec![h; steps]);
            let mut s = build_scheme(&config(&format!("scheme = \"{scheme}\""))).unwrap();
            let run = case
                .run(s.as_mut(), h, steps, OnNonConvergence::Stop)
                .unwrap();
            assert_eq!(run.stats.iterations, steps, "explicit: one sweep per step");
            errors.push(relative_error(&run.u, &mono));
            defects.push(run.stats.max_residual);
        }
        for pair in errors.windows(2) {
            let order = (pair[0] / pair[1]).log2();
            eprintln!("{scheme}: errors {errors:.3?}, observed order {order:.3}");
            assert!(
                (0.8..=1.3).contains(&order),
                "{scheme}: observed order {order}"
            );
        }
        // The reported interface defect is the change of the lagged values over one step in
        // the weighted measure: proportional to h on a smooth response, and far above the
        // implicit tolerance (1) at these steps.
        for pair in defects.windows(2) {
            let ratio = pair[1] / pair[0];
            eprintln!("{scheme}: defects {defects:.3?}, ratio {ratio:.3}");
            assert!(
                (0.4..=0.6).contains(&ratio),
                "{scheme}: defect ratio {ratio}"
            );
        }
        assert!(defects[2] > 1e3, "{scheme}: defect {}", defects[2]);
        assert!(
            errors[2] > 1e-3,
            "{scheme}: the splitting error must be visible"
        );
    }
}

#[test]
fn coupling_gauss_seidel_beats_jacobi_and_equals_one_implicit_sweep() {
    let case = Case::two_oscillators();
    let (h, steps) = (1e-2, 200);
    let mono = case.monolithic(&vec![h; steps]);
    let mut jacobi = build_scheme(&config("scheme = \"jacobi\"")).unwrap();
    let mut gs = GaussSeidel::new(WeightedRms::new(1e-10, 1e-12));
    let rj = case
        .run(jacobi.as_mut(), h, steps, OnNonConvergence::Stop)
        .unwrap();
    let rg = case.run(&mut gs, h, steps, OnNonConvergence::Stop).unwrap();
    assert!(relative_error(&rg.u, &mono) < relative_error(&rj.u, &mono));
    // One sweep of the implicit scheme with the start value as guess is Gauss–Seidel; the
    // unconverged steps must be accepted explicitly and are counted.
    let mut one =
        implicit(Box::new(ConstantRelaxation::new(1.0)), 1).with_predictor(Predictor::Constant);
    assert!(case
        .run(&mut one, h, steps, OnNonConvergence::Stop)
        .is_err());
    let mut one =
        implicit(Box::new(ConstantRelaxation::new(1.0)), 1).with_predictor(Predictor::Constant);
    let ri = case
        .run(&mut one, h, steps, OnNonConvergence::Accept)
        .unwrap();
    assert_eq!(ri.stats.accepted_unconverged, steps);
    assert!(ri.stats.to_string().contains("WITHOUT convergence"));
    assert_eq!(ri.u, rg.u);
}

#[test]
fn coupling_stiff_case_needs_acceleration() {
    let case = stiff();
    let rho = spectral_radius(&case.interface_jacobian(H));
    assert!(rho > 2.0, "spectral radius of H' = {rho}");

    // Plain (ω = 1) and ω = 0.5 iteration diverge: the contact forces of the last sweep grow
    // without bound (the relative residual saturates near 1/rtol and cannot show it).
    for omega in [1.0, 0.5] {
        let sweep = |iterations| {
            let (mut sys, _) = case.system();
            let mut s = implicit(Box::new(ConstantRelaxation::new(omega)), iterations);
            s.initialize(&mut sys).unwrap();
            let report = s.step(&mut sys, 0.0, H).unwrap();
            let mut forces = vec![0.0; case.wheels.len()];
            let vrs: Vec<u32> = (0..forces.len() as u32).map(|j| OUT + j).collect();
            sys.participants[1].get_real(&vrs, &mut forces).unwrap();
            (report, forces.iter().fold(0.0_f64, |m, f| m.max(f.abs())))
        };
        let ((_, first), (last, after)) = (sweep(1), sweep(30));
        eprintln!(
            "ω = {omega}: max contact force {first:.2e} N after 1 sweep, {after:.2e} N after 30"
        );
        assert!(!last.converged);
        assert!(after > 1e6 * first, "ω = {omega}: {first:e} → {after:e}");
    }

    let mono = case.monolithic(&[H; STEPS]);
    let mut means = Vec::new();
    for text in [
        "acceleration = \"aitken\"",
        "acceleration = \"iqn-ils\"",
        "acceleration = \"iqn-ils\"\nreuse_steps = 4",
    ] {
        let mut scheme = build_scheme(&config(text)).unwrap();
        let run = case
            .run(scheme.as_mut(), H, STEPS, OnNonConvergence::Stop)
            .unwrap();
        let err = relative_error(&run.u, &mono);
        eprintln!(
            "stiff, {}: {} | error {err:.2e}",
            text.replace('\n', ", "),
            run.stats
        );
        assert!(err <= 1e-9, "{text}: error {err:e}");
        means.push(run.stats.mean_iterations());
    }
    let [aitken, iqn, iqn_reuse] = means[..] else {
        unreachable!()
    };
    assert!(
        iqn <= aitken,
        "IQN-ILS {iqn} vs Aitken {aitken} iterations per step"
    );
    assert!(iqn_reuse <= iqn, "reuse {iqn_reuse} vs {iqn}");
    // A linear interface of n = 4 unknowns: IQN-ILS needs n + 2 sweeps per step in exact
    // arithmetic; the filter may cost one more.
    assert!(iqn <= 6.5, "IQN-ILS {iqn} iterations per step");
}

#[test]
fn coupling_rollback_is_used() {
    let case = moderate();
    let steps = 20;
    let mut scheme = build_scheme(&config("acceleration = \"iqn-ils\"")).unwrap();
    let run = case
        .run(scheme.as_mut(), H, steps, OnNonConvergence::Stop)
        .unwrap();
    let sweeps = run.stats.iterations;
    assert!(sweeps > steps);
    for probe in &run.probes {
        let p = probe.borrow();
        assert_eq!(p.saves, steps, "one save per step");
        assert_eq!(
            p.restores,
            sweeps - steps,
            "one restore before every sweep but the first"
        );
        assert_eq!(p.steps, sweeps);
    }

    // Explicit schemes never roll back.
    let mut gs = build_scheme(&config("scheme = \"gauss-seidel\"")).unwrap();
    let run = Case::two_oscillators()
        .run(gs.as_mut(), 1e-2, steps, OnNonConvergence::Stop)
        .unwrap();
    for probe in &run.probes {
        assert_eq!(
            *probe.borrow(),
            coupling_support::Probe {
                steps,
                saves: 0,
                restores: 0
            }
        );
    }

    // With a restore that does nothing the iteration cannot work.
    let mut scheme = implicit(Box::new(IqnIls::new(0.5, 0)), 50);
    let err = case
        .run_system(
            case.system_with(true),
            &mut scheme,
            H,
            steps,
            OnNonConvergence::Stop,
        )
        .err()
        .expect("iterating without rollback must fail");
    assert!(err.to_string().contains("do_step at t = 0"), "{err}");
}

/// [`Case::track`] with four wheels whose train is two vehicles (wheels 1–2 under one body,
/// 3–4 under another): its step map is block-diagonal by vehicle.
fn two_vehicles() -> Case {
    use coupling_support::{Load, Structure};
    let mut case = Case::track(4, 200.0, 2e9);
    // wheels 0, 1 under body 4, wheels 2, 3 under body 5
    let mut train = Structure::wheels_under_bodies(4, 6, |j| 4 + j / 2);
    for (body, omega) in [(4, 25.0), (5, 31.0)] {
        train.m[body][body] = 4.0e4;
        train.loads.push(Load {
            dof: body,
            amplitude: 2.0e5,
            omega,
        });
    }
    case.train = train;
    case
}

/// The Newton update's step Jacobian (participant by participant through rollback, chain
/// rule) equals a dense finite-difference Jacobian of the whole sweep (every unknown moved,
/// all participants rolled back) and the closed form `H' = −(Kc⁻¹ + G_T)⁻¹ G_B` of the test
/// system, to 1e-6 of its largest entry: the first Jacobian (every input moved alone), a
/// reused one (one check probe per participant), and a coloured one (the train's two
/// vehicles' inputs moved together, two probes for four inputs).
#[test]
fn coupling_step_jacobian_equals_dense_finite_differences() {
    use tbi_coupling::jacobian::{step_jacobian, sweep, StepJacobian};
    use tbi_coupling::{advance, save_all};
    for (label, case) in [
        ("one vehicle", Case::track(3, 200.0, 2e9)),
        ("two vehicles", two_vehicles()),
    ] {
        let (mut sys, _) = case.system();
        let mut s = implicit(Box::new(tbi_coupling::acceleration::Aitken::new(0.5)), 50);
        s.initialize(&mut sys).unwrap();
        let mut t = 0.0;
        for _ in 0..20 {
            advance(&mut s, &mut sys, t, H, OnNonConvergence::Stop).unwrap();
            t += H;
        }
        let n = s.interface_size();
        assert_eq!(n, case.wheels.len(), "one contact force per wheel");
        save_all(&mut sys).unwrap();
        let x = sweep(&mut sys, t, H, &vec![0.0; n]).unwrap();
        let base = sweep(&mut sys, t, H, &x).unwrap();
        let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let exact = case.interface_jacobian(H);
        let mut dense = vec![vec![0.0; n]; n];
        for u in 0..n {
            let eps = 1e-6 * x[u].abs().max(scale);
            let mut xp = x.clone();
            xp[u] += eps;
            let moved = sweep(&mut sys, t, H, &xp).unwrap();
            for i in 0..n {
                dense[i][u] = (moved[i] - base[i]) / eps;
            }
        }
        // (Jacobian, its probes): the first, then again with what was learnt
        let mut computed = Vec::new();
        for (known, names) in [
            (StepJacobian::new(), ["first", "reused"]),
            (StepJacobian::new().reuse(false), ["first", "coloured"]),
        ] {
            let mut known = known;
            for what in names {
                let before = known.probes();
                let j = step_jacobian(&mut known, &mut sys, t, H, &x).unwrap();
                computed.push((what, j, known.probes() - before));
            }
        }
        for (what, j, probes) in &computed {
            let largest = j.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!(largest > 1e-3, "a coupled interface: |J| = {largest}");
            for u in 0..n {
                for i in 0..n {
                    assert!(
                        (j[(i, u)] - dense[i][u]).abs() <= 1e-6 * largest,
                        "{label}, {what}: J[{i},{u}] = {} vs dense differences {}",
                        j[(i, u)],
                        dense[i][u]
                    );
                    assert!(
                        (j[(i, u)] - exact[i][u]).abs() <= 1e-6 * largest,
                        "{label}, {what}: J[{i},{u}] = {} vs closed form {}",
                        j[(i, u)],
                        exact[i][u]
                    );
                }
            }
            println!("{label}, {what}: {probes} participant steps");
        }
        // bridge and train each: every input alone, then one check, or the colours
        let probes: Vec<usize> = computed.iter().map(|c| c.2).collect();
        let colours = if label == "two vehicles" { 2 } else { n };
        assert_eq!(probes, vec![2 * n, 2, 2 * n, n + colours], "{label}");
    }
}
