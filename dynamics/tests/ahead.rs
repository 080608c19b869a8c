//! The geometry of the monolithic step made ahead on a second thread
//! (`Monolithic::run_ahead`) gives every step the same values, bit for bit, as made by the
//! stepping thread: for sine and for nodal shapes, with the worker started, stopped and
//! started again (as `tbi run` switches while it measures), and when a step's time is not the
//! worker's.
mod common;
use common::*;
use std::sync::Arc;
use tbi_dynamics::bridge::{ModalBridge, Shapes, SimplySupported};
use tbi_dynamics::solver::Monolithic;
use tbi_dynamics::track::Smooth;
use tbi_dynamics::vehicle::coach::CoachParams;

fn sine_bridge() -> ModalBridge {
    SimplySupported {
        modes: 12,
        ..SimplySupported::example()
    }
    .modal()
}

/// The sine bridge's deck shapes sampled every 2.5 m, interpolated by Lagrange stencils of
/// four nodes (an FE model's shapes are given so).
fn nodal_bridge() -> ModalBridge {
    let mut b = sine_bridge();
    let nb = b.n_modes();
    let x_m: Vec<f64> = (0..=24).map(|i| 2.5 * i as f64).collect();
    let mut values = Vec::new();
    let mut sh = vec![[0.0; 3]; nb];
    for &x in &x_m {
        b.deck_shapes(x.clamp(1e-9, 60.0 - 1e-9), &mut sh);
        values.extend_from_slice(&sh);
    }
    b.shapes = Shapes::Nodal {
        x_m,
        values,
        order: 4,
    };
    b
}

/// Three coaches from 30 m before the span, at 160 km/h: the steps see wheelsets off, onto
/// and on the deck.
fn solver(bridge: &ModalBridge) -> Monolithic {
    let c = CoachParams::xia2000().build().unwrap();
    let l = CoachParams::xia2000().length_m;
    let coaches = (0..3).map(|i| (c.clone(), i as f64 * l)).collect();
    let train = train_of(coaches, 160.0 / 3.6, -30.0);
    Monolithic::new(bridge.clone(), train, Arc::new(Waves), 2e-3)
}

fn assert_same(a: &Monolithic, b: &Monolithic, step: usize) {
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(a.t.to_bits(), b.t.to_bits(), "step {step}: t");
    for (name, x, y) in [
        ("q", &a.q, &b.q),
        ("q̇", &a.qd, &b.qd),
        ("q̈", &a.qdd, &b.qdd),
    ] {
        assert_eq!(
            bits(x.as_slice()),
            bits(y.as_slice()),
            "step {step}: {name}"
        );
    }
    for (i, (va, vb)) in a.vehicles.iter().zip(&b.vehicles).enumerate() {
        for (x, y) in [(&va.v, &vb.v), (&va.vd, &vb.vd), (&va.vdd, &vb.vdd)] {
            assert_eq!(
                bits(x.as_slice()),
                bits(y.as_slice()),
                "step {step}: vehicle {i}"
            );
        }
    }
    for w in 0..a.forces.len() {
        assert_eq!(
            bits(a.forces[w].as_slice()),
            bits(b.forces[w].as_slice()),
            "step {step}: force of wheelset {w}"
        );
        for d in 0..3 {
            assert_eq!(
                bits(a.rail[w][d].as_slice()),
                bits(b.rail[w][d].as_slice()),
                "step {step}: rail motion {d} of wheelset {w}"
            );
        }
    }
}

#[test]
fn the_geometry_made_ahead_gives_the_same_steps_bit_for_bit() {
    for bridge in [sine_bridge(), nodal_bridge()] {
        let (mut here, mut ahead) = (solver(&bridge), solver(&bridge));
        assert!(ahead.ahead_may_pay());
        assert!(ahead.run_ahead(None) && ahead.runs_ahead());
        assert_eq!(here.q.amax(), 0.0, "the train starts off the deck");
        for k in 0..900 {
            match k {
                300 => {
                    ahead.stop_ahead();
                    assert!(!ahead.runs_ahead());
                }
                400 => assert!(ahead.run_ahead(None)),
                _ => {}
            }
            here.step();
            ahead.step();
            assert_same(&here, &ahead, k);
        }
        assert!(ahead.runs_ahead(), "the worker kept up with every step");
        assert!(here.q.amax() > 0.0, "the train reached the deck");
    }
}

/// A step to a time the worker has not made (the time set from outside) makes its own
/// geometry and stops the worker; the steps stay those made without it.
#[test]
fn a_step_out_of_step_with_the_worker_makes_its_own_geometry() {
    let bridge = nodal_bridge();
    let (mut here, mut ahead) = (solver(&bridge), solver(&bridge));
    assert!(ahead.run_ahead(None));
    for k in 0..500 {
        if k == 250 {
            here.t += 1e-3;
            ahead.t += 1e-3;
        }
        here.step();
        ahead.step();
        assert_same(&here, &ahead, k);
        assert_eq!(ahead.runs_ahead(), k < 250, "step {k}");
    }
}

/// On the ideal track without hunting the idle wheelsets depend on the state: no worker.
#[test]
fn no_worker_on_the_ideal_track() {
    let c = CoachParams::xia2000().build().unwrap();
    let train = train_of(vec![(c, 0.0)], 30.0, -10.0);
    let mut sol = Monolithic::new(sine_bridge(), train, Arc::new(Smooth), 2e-3);
    assert!(!sol.ahead_may_pay());
    assert!(!sol.run_ahead(None));
    assert!(!sol.runs_ahead());
}
