//! The coupled bridge–train system: the structured (Schur) solver against a dense solve of
//! the explicitly assembled eq. (14); conservation of energy; symmetry of the response.
#![allow(clippy::needless_range_loop)]
mod common;
use common::*;
use nalgebra::DVector;
use std::sync::Arc;
use tbi_dynamics::bridge::{ModalBridge, SimplySupported};
use tbi_dynamics::solver::monolithic::dense_reference_step;
use tbi_dynamics::solver::Monolithic;
use tbi_dynamics::track::Smooth;
use tbi_dynamics::vehicle::coach::CoachParams;

fn bridge_3d(e: f64, h4: f64, damping: f64) -> ModalBridge {
    SimplySupported {
        span_m: 60.0,
        youngs_modulus_pa: 3.0e10,
        inertia_vertical_m4: 8.0,
        inertia_lateral_m4: Some(40.0),
        shear_modulus_pa: Some(1.2e10),
        torsion_constant_m4: Some(12.0),
        polar_inertia_kg_m: Some(3.0e5),
        mass_per_length_kg_m: 2.0e4,
        modes: 12,
        damping_ratio: damping,
        damping_ratio_torsional: damping / 2.0,
        e_m: e,
        h4_m: h4,
        x_start_m: 0.0,
    }
    .modal()
}

fn two_coaches(speed: f64, x0: f64, undamped: bool) -> tbi_dynamics::train::Train {
    let mut p = CoachParams::xia2000();
    if undamped {
        p.c1h_ns_m = 0.0;
        p.c1v_ns_m = 0.0;
        p.c2h_ns_m = 0.0;
        p.c2v_ns_m = 0.0;
    }
    let c = p.build().unwrap();
    train_of(vec![(c.clone(), 0.0), (c, p.length_m)], speed, x0)
}

#[test]
fn structured_solver_equals_dense_eq14() {
    let bridge = bridge_3d(2.05, 1.25, 0.02);
    let train = two_coaches(160.0 / 3.6, 5.0, false);
    let mut sol = Monolithic::new(bridge, train, Arc::new(Waves), 2e-3);
    for _ in 0..400 {
        sol.step();
    }
    for _ in 0..5 {
        let mut probe = Monolithic::new(
            sol.bridge.clone(),
            sol.train.clone(),
            sol.track.clone(),
            sol.dt(),
        );
        copy_state(&sol, &mut probe);
        let dense = dense_reference_step(&mut probe);
        sol.step();
        let (x, _, _) = sol.stacked_state();
        let scale = dense.amax();
        let diff = (&x - &dense).amax();
        assert!(
            diff <= 1e-9 * scale,
            "structured vs dense: {diff:e} (scale {scale:e})"
        );
        assert!(sol.q.amax() > 0.0);
    }
}

fn copy_state(from: &Monolithic, to: &mut Monolithic) {
    to.t = from.t;
    to.q = from.q.clone();
    to.qd = from.qd.clone();
    to.qdd = from.qdd.clone();
    to.vehicles = from.vehicles.clone();
}

/// Total mechanical energy of a parked train on the bridge (positions fixed).
fn energy(sol: &Monolithic) -> f64 {
    let w: Vec<f64> = sol.bridge.omegas();
    let mut e = 0.0;
    for n in 0..sol.q.len() {
        e += 0.5 * sol.qd[n].powi(2) + 0.5 * (w[n] * sol.q[n]).powi(2);
    }
    for (w, ws) in sol.wheelsets.iter().enumerate() {
        let model = &sol.train.vehicles[ws.vehicle].model;
        let c = &model.wheelsets[ws.local];
        let [u, ud, _] = sol.rail[w];
        let v = &sol.vehicles[ws.vehicle].v;
        e += 0.5 * ud.dot(&(c.m_w * ud)) + 0.5 * u.dot(&(c.k_ww * u)) - c.p0.dot(&u);
        e += v.dot(&(&c.k_vw * DVector::from_column_slice(u.as_slice())));
    }
    for (tv, s) in sol.train.vehicles.iter().zip(&sol.vehicles) {
        e += 0.5 * s.vd.dot(&(&tv.model.m * &s.vd)) + 0.5 * s.v.dot(&(&tv.model.k * &s.v));
    }
    e
}

#[test]
fn undamped_parked_train_conserves_energy() {
    let bridge = bridge_3d(2.05, 1.25, 0.0);
    // Parked (speed 0) with its first axle at 40 m: released from rest on the undeformed deck.
    let train = two_coaches(0.0, 40.0, true);
    let mut sol = Monolithic::new(bridge, train, Arc::new(Smooth), 2e-3);
    let e0 = energy(&sol);
    let mut emax: f64 = 0.0;
    let mut swing: f64 = 0.0;
    for _ in 0..3000 {
        sol.step();
        let e = energy(&sol);
        emax = emax.max((e - e0).abs());
        swing = swing.max(sol.q.amax());
    }
    // the work of the static loads is of order P0·u: compare the drift with it
    let scale: f64 = sol.forces.iter().map(|f| f.z).sum::<f64>() * 0.01;
    assert!(swing > 0.0);
    assert!(
        emax < 1e-9 * scale,
        "energy drift {emax:e} J (scale {scale:e} J)"
    );
}

#[test]
fn train_leaving_undamped_bridge_leaves_constant_energy() {
    let bridge = bridge_3d(2.05, 1.25, 0.0);
    let train = two_coaches(120.0 / 3.6, 0.0, false);
    let mut sol = Monolithic::new(bridge, train, Arc::new(Waves), 2e-3);
    let t_off = (60.0 + sol.train.length_m()) / sol.train.speed_m_s;
    while sol.t < t_off + 0.01 {
        sol.step();
    }
    let bridge_energy = |s: &Monolithic| -> f64 {
        let w = s.bridge.omegas();
        (0..s.q.len())
            .map(|n| 0.5 * s.qd[n].powi(2) + 0.5 * (w[n] * s.q[n]).powi(2))
            .sum()
    };
    let e0 = bridge_energy(&sol);
    assert!(e0 > 0.0);
    for _ in 0..2000 {
        sol.step();
    }
    let e1 = bridge_energy(&sol);
    assert!(
        ((e1 - e0) / e0).abs() < 1e-10,
        "free vibration energy {e0} -> {e1}"
    );
}

#[test]
fn symmetric_loading_gives_no_lateral_or_torsional_response() {
    let bridge = bridge_3d(0.0, 0.0, 0.01);
    let labels = bridge.labels.clone();
    let train = two_coaches(160.0 / 3.6, 0.0, false);
    let mut sol = Monolithic::new(bridge, train, Arc::new(Smooth), 2e-3);
    let mut vert: f64 = 0.0;
    for _ in 0..1500 {
        sol.step();
        for (n, l) in labels.iter().enumerate() {
            if l.starts_with('V') {
                vert = vert.max(sol.q[n].abs());
            } else {
                assert_eq!(sol.q[n], 0.0, "mode {l} excited by symmetric loading");
            }
        }
        for s in &sol.vehicles {
            assert_eq!(s.vdd[0], 0.0, "car-body lateral acceleration");
        }
    }
    assert!(vert > 0.0);
    // with the track off the shear centre the same run twists the deck
    let mut sol = Monolithic::new(
        bridge_3d(2.05, 1.25, 0.01),
        two_coaches(160.0 / 3.6, 0.0, false),
        Arc::new(Smooth),
        2e-3,
    );
    for _ in 0..1500 {
        sol.step();
    }
    let tors: f64 = sol
        .bridge
        .labels
        .iter()
        .zip(sol.q.iter())
        .filter(|(l, _)| l.starts_with('T'))
        .map(|(_, q)| q.abs())
        .fold(0.0, f64::max);
    assert!(tors > 0.0);
}
