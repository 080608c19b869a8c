//! Moving constant force on a simply supported beam against the exact modal solution
//! (domain reference §1): each mode is a damped oscillator under a sine force while the
//! load is on the span and in free vibration afterwards, solved in closed form.
mod common;
use common::*;
use std::f64::consts::PI;
use std::sync::Arc;
use tbi_dynamics::solver::Monolithic;
use tbi_dynamics::track::Smooth;
use tbi_dynamics::vehicle::simple::moving_force;

const P: f64 = 1.0e5;

struct Run {
    t: Vec<f64>,
    mid: Vec<f64>,
}

fn simulate(alpha: f64, zeta: f64, modes: usize, dt: f64) -> (Run, f64, f64) {
    let beam = yang_yau_beam(modes, zeta);
    let bridge = beam.modal();
    let f1 = bridge.frequencies_hz[0];
    let l = beam.span_m;
    let v = alpha * 2.0 * f1 * l;
    let train = train_of(vec![(moving_force(P), 0.0)], v, 0.0);
    let mut sol = Monolithic::new(bridge.clone(), train, Arc::new(Smooth), dt);
    let t_end = l / v + 1.0 / f1;
    let mut run = Run {
        t: vec![0.0],
        mid: vec![0.0],
    };
    while sol.t < t_end {
        sol.step();
        run.t.push(sol.t);
        run.mid.push(deck_z(&bridge, l / 2.0, sol.q.as_slice()));
    }
    (run, v, l)
}

/// Exact midspan displacement with `modes` modes.
fn exact_mid(alpha: f64, zeta: f64, modes: usize, t: f64) -> f64 {
    let beam = yang_yau_beam(modes, zeta);
    let l = beam.span_m;
    let mu = beam.mass_per_length_kg_m;
    let ei = beam.youngs_modulus_pa * beam.inertia_vertical_m4;
    let w1 = (PI / l).powi(2) * (ei / mu).sqrt();
    let v = alpha * 2.0 * (w1 / (2.0 * PI)) * l;
    let mut w = 0.0;
    for j in 1..=modes {
        let jf = j as f64;
        let wj = jf * jf * w1;
        // unnormalised modes sin(jπx/L): q̈ + 2ζω q̇ + ω² q = (2P/(μL)) sin(jπvt/L)
        let q = sdof_sine_exact(wj, zeta, 2.0 * P / (mu * l), jf * PI * v / l, l / v, t);
        w += q * (jf * PI * 0.5).sin();
    }
    w
}

#[test]
fn peak_midspan_matches_exact_series() {
    let modes = 10;
    for &zeta in &[0.0, 0.02, 0.05] {
        for &alpha in &[0.1, 0.25, 0.5, 0.75, 1.0] {
            let (run, _, _) = simulate(alpha, zeta, modes, 2.0e-4);
            let sim_peak = run.mid.iter().copied().fold(f64::MIN, f64::max);
            let mut ex_peak = f64::MIN;
            let mut max_err: f64 = 0.0;
            for (t, m) in run.t.iter().zip(&run.mid) {
                let e = exact_mid(alpha, zeta, modes, *t);
                ex_peak = ex_peak.max(e);
                max_err = max_err.max((m - e).abs());
            }
            let rel = (sim_peak - ex_peak).abs() / ex_peak;
            assert!(
                rel < 0.005,
                "alpha {alpha} zeta {zeta}: peak {sim_peak} vs exact {ex_peak} ({rel:e})"
            );
            // whole history close: max deviation below 1 % of the peak
            assert!(
                max_err / ex_peak < 0.01,
                "alpha {alpha} zeta {zeta}: history deviates by {}",
                max_err / ex_peak
            );
        }
    }
}

#[test]
fn one_mode_versus_many_modes() {
    let beam = yang_yau_beam(1, 0.0);
    let l = beam.span_m;
    let ei = beam.youngs_modulus_pa * beam.inertia_vertical_m4;
    let delta_st = P * l.powi(3) / (48.0 * ei);
    // quasi-static crossing: one mode gives 96/π⁴ of the static deflection, many modes the full one
    let (one, _, _) = simulate(0.01, 0.0, 1, 1.0e-3);
    let (many, _, _) = simulate(0.01, 0.0, 15, 1.0e-4);
    let p1 = one.mid.iter().copied().fold(f64::MIN, f64::max);
    let pn = many.mid.iter().copied().fold(f64::MIN, f64::max);
    assert!(
        (p1 / delta_st - 96.0 / PI.powi(4)).abs() < 0.01,
        "one mode: {}",
        p1 / delta_st
    );
    assert!(
        (pn / delta_st - 1.0).abs() < 0.01,
        "many modes: {}",
        pn / delta_st
    );
    // the dynamic amplification of one mode peaks near alpha ≈ 0.5–0.7 at about 1.7
    let mut best = (0.0, 0.0);
    for &a in &[0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 1.0] {
        let (r, _, _) = simulate(a, 0.0, 1, 2.0e-4);
        let daf = r.mid.iter().copied().fold(f64::MIN, f64::max) / delta_st;
        if daf > best.1 {
            best = (a, daf);
        }
    }
    assert!(
        (0.5..=0.7).contains(&best.0),
        "one-mode DAF peaks at alpha {}",
        best.0
    );
    assert!((1.6..1.8).contains(&best.1), "one-mode peak DAF {}", best.1);
}
