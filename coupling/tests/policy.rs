//! Non-convergence policies, discards, configuration and statistics of the coupling master.

mod coupling_support;

use std::cell::RefCell;
use std::rc::Rc;

use coupling_support::{relative_error, Case, Discarding};
use tbi_coupling::acceleration::{Aitken, ConstantRelaxation, IqnIls};
use tbi_coupling::{
    advance, build_scheme, AccelerationKind, AdvanceReport, Connection, CouplingConfig,
    CouplingError, CouplingScheme, CouplingStatistics, Implicit, NonConvergenceAction,
    OnNonConvergence, Predictor, SchemeKind, StepReport, Substep, System, WeightedRms,
};

const H: f64 = 1e-3;

fn implicit_constant(omega: f64, max_iterations: usize) -> Implicit {
    Implicit::new(
        Box::new(ConstantRelaxation::new(omega)),
        WeightedRms::new(1e-10, 1e-12),
        max_iterations,
    )
}

/// ω = 0.5 needs more than 30 sweeps per step at h = 1 ms but fewer at h = 0.5 ms.
fn retry_case() -> Case {
    Case::track(2, 100.0, 5e9)
}

#[test]
fn coupling_stop_names_time_residual_and_iterations() {
    let case = retry_case();
    let (mut sys, _) = case.system();
    // Five good steps, then a scheme limited to 2 sweeps takes over at t = 5 ms.
    let mut good = build_scheme(&CouplingConfig::default()).unwrap();
    good.initialize(&mut sys).unwrap();
    for k in 0..5 {
        advance(
            good.as_mut(),
            &mut sys,
            k as f64 * H,
            H,
            OnNonConvergence::Stop,
        )
        .unwrap();
    }
    let mut limited = implicit_constant(0.5, 2);
    let err = advance(&mut limited, &mut sys, 5.0 * H, H, OnNonConvergence::Stop).unwrap_err();
    let msg = err.to_string();
    assert!(msg.contains("t = 0.005 s"), "{msg}");
    assert!(msg.contains("h = 0.001 s"), "{msg}");
    assert!(msg.contains("residual"), "{msg}");
    assert!(msg.contains("after 2 iterations"), "{msg}");
    assert!(msg.contains("policy: stop"), "{msg}");
}

#[test]
fn coupling_retry_halves_the_step_and_stays_exact() {
    let case = retry_case();
    let steps = 40;
    let mut scheme = implicit_constant(0.5, 30);
    let run = case
        .run(
            &mut scheme,
            H,
            steps,
            OnNonConvergence::Retry { min_step: H / 8.0 },
        )
        .unwrap();
    eprintln!("retry: {}", run.stats);
    assert!(
        run.stats.rejected > 0,
        "the full step must fail at least once"
    );
    assert!(run.hs.iter().any(|&h| h == H / 2.0));
    assert!(run.hs.iter().all(|&h| h >= H / 8.0));
    assert_eq!(run.stats.accepted_unconverged, 0);
    // The substeps tile the macro steps.
    let total: f64 = run.hs.iter().sum();
    assert!((total - steps as f64 * H).abs() < 1e-12);
    // Converged substeps reproduce the monolithic solution with the same steps.
    let err = relative_error(&run.u, &case.monolithic_like(&run));
    assert!(err <= 1e-9, "error {err:e}");

    // One advance reports the rejected attempt and its two halves.
    let (mut sys, _) = case.system();
    let mut scheme = implicit_constant(0.5, 30);
    scheme.initialize(&mut sys).unwrap();
    let report = advance(
        &mut scheme,
        &mut sys,
        0.0,
        H,
        OnNonConvergence::Retry { min_step: H / 8.0 },
    )
    .unwrap();
    assert!(report.retried());
    assert_eq!(report.rejected[0].h, H);
    assert!(!report.rejected[0].report.converged);
    let t_end = report.steps.last().map(|s| s.t + s.h).unwrap();
    assert!((t_end - H).abs() < 1e-15);
    assert!(report.steps.iter().all(|s| s.report.converged));
}

#[test]
fn coupling_retry_stops_at_min_step() {
    let case = retry_case();
    let (mut sys, _) = case.system();
    let mut scheme = implicit_constant(0.5, 3);
    scheme.initialize(&mut sys).unwrap();
    let err = advance(
        &mut scheme,
        &mut sys,
        0.0,
        H,
        OnNonConvergence::Retry { min_step: H / 4.0 },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("min_step = 0.00025 s"), "{err}");
    assert!(err.contains("h = 0.00025 s"), "{err}");
    assert!(err.contains("residual"), "{err}");
}

#[test]
fn coupling_accept_is_reported() {
    let case = retry_case();
    let mut scheme = implicit_constant(0.5, 3);
    let run = case
        .run(&mut scheme, H, 10, OnNonConvergence::Accept)
        .unwrap();
    assert_eq!(run.stats.accepted_unconverged, 10);
    assert!(run.stats.max_residual > 1.0);
    assert!(run
        .stats
        .to_string()
        .contains("10 steps accepted WITHOUT convergence"));
}

/// The train discards steps longer than `max_h`.
fn discarding_system(case: &Case, max_h: f64) -> (System, Rc<RefCell<usize>>) {
    let (mut sys, _) = case.system();
    let discards = Rc::new(RefCell::new(0));
    let train = sys.participants.pop().unwrap();
    sys.participants.push(Box::new(Discarding {
        inner: train,
        max_h,
        discards: discards.clone(),
    }));
    (sys, discards)
}

#[test]
fn coupling_discard_is_retried_or_reported() {
    let case = Case::track(2, 200.0, 2e9);
    // Retry: the implicit scheme rolls back and halves.
    let (mut sys, discards) = discarding_system(&case, 0.6 * H);
    let mut scheme = build_scheme(&CouplingConfig::default()).unwrap();
    scheme.initialize(&mut sys).unwrap();
    let policy = OnNonConvergence::Retry { min_step: H / 4.0 };
    let mut hs = Vec::new();
    for k in 0..5 {
        let report = advance(scheme.as_mut(), &mut sys, k as f64 * H, H, policy).unwrap();
        assert_eq!(report.rejected.len(), 1);
        assert_eq!(
            report.rejected[0].report.discarded_by.as_deref(),
            Some("train")
        );
        hs.extend(report.steps.iter().map(|s| s.h));
    }
    assert_eq!(*discards.borrow(), 5);
    assert_eq!(hs, vec![H / 2.0; 10]);
    let mut u = vec![0.0; 3];
    sys.participants[1]
        .get_real(&[200, 201, 202], &mut u)
        .unwrap();
    let mono = case.monolithic(&hs);
    let last = &mono.last().unwrap()[case.bridge.n()..];
    assert!(relative_error(&[u], &[last.to_vec()]) <= 1e-9);

    // Stop and accept: an error naming the participant.
    for policy in [OnNonConvergence::Stop, OnNonConvergence::Accept] {
        let (mut sys, _) = discarding_system(&case, 0.6 * H);
        let mut scheme = build_scheme(&CouplingConfig::default()).unwrap();
        scheme.initialize(&mut sys).unwrap();
        let err = advance(scheme.as_mut(), &mut sys, 0.0, H, policy)
            .unwrap_err()
            .to_string();
        assert!(err.contains("train discarded the step"), "{err}");
    }

    // Explicit schemes keep no state to retry from.
    let (mut sys, _) = discarding_system(&case, 0.6 * H);
    let mut gs = build_scheme(&toml::from_str("scheme = \"gauss-seidel\"").unwrap()).unwrap();
    gs.initialize(&mut sys).unwrap();
    let err = advance(gs.as_mut(), &mut sys, 0.0, H, policy)
        .unwrap_err()
        .to_string();
    assert!(err.contains("train discarded the step"), "{err}");
    assert!(err.contains("no saved state"), "{err}");
}

#[test]
fn coupling_bad_systems_are_rejected() {
    let case = Case::two_oscillators();
    let (mut sys, _) = case.system();
    sys.connections.push(Connection {
        from: 0,
        from_vr: 100,
        to: 2,
        to_vr: 0,
    });
    let mut scheme = build_scheme(&CouplingConfig::default()).unwrap();
    let err = scheme.initialize(&mut sys).unwrap_err().to_string();
    assert!(err.contains("does not exist"), "{err}");

    let (mut sys, _) = case.system();
    sys.connections.push(Connection {
        from: 1,
        from_vr: 100,
        to: 0,
        to_vr: 0,
    });
    let err = scheme.initialize(&mut sys).unwrap_err().to_string();
    assert!(
        err.contains("input vr 0 of participant 'bridge' is fed by more than one"),
        "{err}"
    );

    let (mut sys, _) = case.system();
    assert!(advance(scheme.as_mut(), &mut sys, 0.0, 0.0, OnNonConvergence::Stop).is_err());

    // Integer and Boolean values are not iterated: the implicit scheme refuses them
    let (mut sys, _) = case.system();
    sys.discrete.push(tbi_coupling::DiscreteConnection {
        kind: tbi_coupling::Discrete::Boolean,
        from: 1,
        from_vr: 7,
        to: 0,
        to_vr: 8,
        name: "train.flag → bridge.flag".into(),
    });
    let err = scheme.initialize(&mut sys).unwrap_err().to_string();
    assert!(
        err.contains("Real connections only") && err.contains("train.flag → bridge.flag (Boolean)"),
        "{err}"
    );
}

#[test]
fn coupling_config_defaults_and_keys() {
    let c: CouplingConfig = toml::from_str("").unwrap();
    assert_eq!(c, CouplingConfig::default());
    assert_eq!(c.scheme, SchemeKind::Implicit);
    assert_eq!(c.acceleration, AccelerationKind::IqnIls);
    assert_eq!(
        (
            c.relaxation,
            c.rtol,
            c.atol,
            c.max_iterations,
            c.reuse_steps
        ),
        (0.5, 1e-10, 1e-12, 50, 8)
    );
    assert_eq!(c.predictor, Predictor::Quadratic);
    assert_eq!(c.on_non_convergence, NonConvergenceAction::Stop);
    assert_eq!(c.policy(H), OnNonConvergence::Stop);

    let c: CouplingConfig = toml::from_str(
        r#"
        scheme = "implicit"
        acceleration = "iqn-ils"
        relaxation = 1
        rtol = 1e-8
        atol = 1e-6
        max_iterations = 20
        predictor = "constant"
        reuse_steps = 3
        on_non_convergence = "retry"
        min_step = 1e-5
        "#,
    )
    .unwrap();
    assert_eq!(c.acceleration, AccelerationKind::IqnIls);
    assert_eq!(
        (c.relaxation, c.rtol, c.atol, c.max_iterations),
        (1.0, 1e-8, 1e-6, 20)
    );
    assert_eq!((c.predictor, c.reuse_steps), (Predictor::Constant, 3));
    assert_eq!(c.policy(H), OnNonConvergence::Retry { min_step: 1e-5 });
    let c: CouplingConfig = toml::from_str("on_non_convergence = \"retry\"").unwrap();
    assert_eq!(c.policy(H), OnNonConvergence::Retry { min_step: H / 16.0 });

    let c: CouplingConfig = serde_json::from_str(r#"{"scheme": "jacobi"}"#).unwrap();
    assert_eq!(c.scheme, SchemeKind::Jacobi);

    for (text, name) in [
        ("", "implicit (iqn-ils)"),
        ("acceleration = \"aitken\"", "implicit (aitken)"),
        ("acceleration = \"constant\"", "implicit (constant)"),
        ("scheme = \"gauss-seidel\"", "gauss-seidel"),
        ("scheme = \"jacobi\"", "jacobi"),
    ] {
        let c: CouplingConfig = toml::from_str(text).unwrap();
        assert_eq!(build_scheme(&c).unwrap().name(), name);
    }
}

#[test]
fn coupling_config_errors_name_key_and_value() {
    for (text, expected) in [
        ("relaxtion = 0.3", "relaxtion"),
        (
            "scheme = \"newton\"",
            "scheme = \"newton\" is not one of \"implicit\", \"gauss-seidel\", \"jacobi\"",
        ),
        ("acceleration = \"anderson\"", "acceleration = \"anderson\""),
        ("predictor = \"cubic\"", "predictor = \"cubic\""),
        (
            "on_non_convergence = \"ignore\"",
            "on_non_convergence = \"ignore\"",
        ),
        ("relaxation = 1.5", "relaxation = 1.5"),
        ("relaxation = 0", "relaxation = 0"),
        ("rtol = -1e-3", "rtol = -0.001"),
        ("atol = 0", "atol = 0"),
        ("max_iterations = 0", "max_iterations = 0"),
        (
            "min_step = 1e-4",
            "min_step = 0.0001: only applies with on_non_convergence = \"retry\"",
        ),
        (
            "on_non_convergence = \"retry\"\nmin_step = -1",
            "min_step = -1",
        ),
        ("max_iterations = \"many\"", "max_iterations"),
    ] {
        let err = toml::from_str::<CouplingConfig>(text)
            .unwrap_err()
            .to_string();
        assert!(err.contains(expected), "{text}: {err}");
    }
}

#[test]
fn coupling_build_scheme_refuses_an_invalid_config_by_name() {
    let c = CouplingConfig {
        relaxation: 2.0,
        ..CouplingConfig::default()
    };
    let err = build_scheme(&c)
        .err()
        .expect("relaxation 2 is out of range");
    assert_eq!(
        err,
        CouplingError::Config {
            key: "relaxation".into(),
            value: "2".into(),
            rule: "must be in (0, 1]".into()
        }
    );
    assert_eq!(err.to_string(), "relaxation = 2: must be in (0, 1]");
}

#[test]
fn coupling_statistics_count_steps_and_iterations() {
    let step = |t: f64, h: f64, iterations: usize, residual: f64, converged: bool| Substep {
        t,
        h,
        report: StepReport {
            iterations,
            residual,
            converged,
            discarded_by: None,
            diagnosis: None,
            jacobian_probes: 0,
        },
    };
    let mut stats = CouplingStatistics::new();
    stats.record(&AdvanceReport {
        steps: vec![step(0.0, 1.0, 3, 0.5, true)],
        rejected: vec![],
    });
    stats.record(&AdvanceReport {
        steps: vec![step(1.0, 0.5, 5, 0.9, true), step(1.5, 0.5, 4, 2.0, false)],
        rejected: vec![step(1.0, 1.0, 7, 9.0, false)],
    });
    assert_eq!(stats.steps, 3);
    assert_eq!(stats.iterations, 12);
    assert_eq!(stats.max_iterations, 5);
    assert_eq!(stats.mean_iterations(), 4.0);
    assert_eq!(stats.max_residual, 2.0);
    assert_eq!((stats.rejected, stats.rejected_iterations), (1, 7));
    assert_eq!(stats.accepted_unconverged, 1);
    assert_eq!(stats.min_step, 0.5);
    let text = stats.to_string();
    assert!(
        text.contains("3 steps, iterations mean 4.00 max 5"),
        "{text}"
    );
    assert!(
        text.contains("1 rejected attempts (7 iterations)"),
        "{text}"
    );
    assert!(
        text.contains("1 steps accepted WITHOUT convergence"),
        "{text}"
    );
    assert_eq!(CouplingStatistics::new().mean_iterations(), 0.0);
}

#[test]
fn coupling_accelerations_on_a_seeded_random_linear_map() {
    // H(x) = A x + b with A = −(S Sᵀ + σ I)·κ for seeded random S: eigenvalues real, negative,
    // spread over more than a decade; values scaled like forces (~1e5).
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut rand = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for n in [1, 3, 8] {
        let s: Vec<Vec<f64>> = (0..n).map(|_| (0..n).map(|_| rand()).collect()).collect();
        let a: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let ss: f64 = (0..n).map(|k| s[i][k] * s[j][k]).sum();
                        -2.0 * (ss + if i == j { 0.1 } else { 0.0 })
                    })
                    .collect()
            })
            .collect();
        let b: Vec<f64> = (0..n).map(|_| 1e5 * rand()).collect();
        let map = |x: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|i| (0..n).map(|j| a[i][j] * x[j]).sum::<f64>() + b[i])
                .collect()
        };
        let measure = WeightedRms::new(1e-10, 1e-12);
        let mut sweeps = Vec::new();
        let accelerations: Vec<Box<dyn tbi_coupling::acceleration::Acceleration>> =
            vec![Box::new(Aitken::new(0.5)), Box::new(IqnIls::new(0.5, 0))];
        for mut acc in accelerations {
            acc.initialize(n);
            acc.begin_step(1.0);
            let scale = vec![1.0; n];
            let mut x = vec![0.0; n];
            let mut k = 0;
            loop {
                let xt = map(&x);
                k += 1;
                if measure.converged(&x, &xt) {
                    break;
                }
                assert!(k < 200, "{} did not converge for n = {n}", acc.name());
                let mut next = vec![0.0; n];
                acc.perform(&x, &xt, &scale, &mut next);
                x = next;
            }
            acc.end_step(true);
            sweeps.push(k);
        }
        eprintln!(
            "n = {n}: sweeps aitken {}, iqn-ils {}",
            sweeps[0], sweeps[1]
        );
        assert!(
            sweeps[1] <= n + 2 + 1,
            "IQN-ILS took {} sweeps for n = {n}",
            sweeps[1]
        );
        if n == 1 {
            // Scalar linear map: Aitken's secant is exact after the first relaxed step.
            assert!(sweeps[0] <= 3);
        }
    }
}
