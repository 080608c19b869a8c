//! A train braking on the bridge ([`SpeedChange`]).
//!
//! * **Deck.** One moving force decelerating uniformly across the Yang–Yau beam, its
//!   position `x(t) = v₀ t − a t²/2` written here: the monolithic solver's peak midspan
//!   displacement and acceleration against a separate modal solution (each mode
//!   `q̈ + 2ζω q̇ + ω² q = (2P/μL) sin(jπ x(t)/L)` integrated by fourth-order Runge–Kutta at a
//!   step twenty times finer), within 0.5 %.
//! * **Car body.** A coach braking steadily on rigid track (far from the deck) settles to
//!   the static balance of its inertia: the car-body pitch
//!   `φ = m_c a h1 (2/k2v + 1/k1v) / (4 s²)` (its moment `m_c a h1` on the secondary springs
//!   at ±s, the bogies sinking on their primary springs), and the wheel loads carry the
//!   moment of the whole coach's inertia about the axles, `Σ x_w ΔP_w = −a (m_c H + 2 m_t h3)`
//!   with `H = h1 + h2 + h3`; both to 1e-6.

mod common;
use common::*;
use std::f64::consts::PI;
use std::sync::Arc;
use tbi_dynamics::solver::Monolithic;
use tbi_dynamics::track::Smooth;
use tbi_dynamics::train::SpeedChange;
use tbi_dynamics::vehicle::coach::CoachParams;
use tbi_dynamics::vehicle::simple::moving_force;

const P: f64 = 1.0e5;

/// Midspan (displacement, acceleration) peaks of the independent modal solution of a force
/// `P` at `x(t)` on the beam, `modes` modes, RK4 at step `h` until `t_end`.
fn modal_peaks(modes: usize, zeta: f64, x: impl Fn(f64) -> f64, h: f64, t_end: f64) -> (f64, f64) {
    let beam = yang_yau_beam(modes, zeta);
    let (l, mu) = (beam.span_m, beam.mass_per_length_kg_m);
    let ei = beam.youngs_modulus_pa * beam.inertia_vertical_m4;
    let w1 = (PI / l).powi(2) * (ei / mu).sqrt();
    let force = |j: f64, t: f64| {
        let xt = x(t);
        if (0.0..=l).contains(&xt) {
            2.0 * P / (mu * l) * (j * PI * xt / l).sin()
        } else {
            0.0
        }
    };
    let (mut dmax, mut amax) = (0.0_f64, 0.0_f64);
    let n = (t_end / h).ceil() as usize;
    // every mode's (q, q̇); the midspan sums at each step
    let mut s = vec![[0.0_f64; 2]; modes];
    for k in 0..=n {
        let t = k as f64 * h;
        let (mut d, mut a) = (0.0, 0.0);
        for (j0, q) in s.iter().enumerate() {
            let j = (j0 + 1) as f64;
            let wj = j * j * w1;
            let mid = (j * PI * 0.5).sin();
            let qdd = force(j, t) - 2.0 * zeta * wj * q[1] - wj * wj * q[0];
            d += q[0] * mid;
            a += qdd * mid;
        }
        dmax = dmax.max(d.abs());
        amax = amax.max(a.abs());
        for (j0, q) in s.iter_mut().enumerate() {
            let j = (j0 + 1) as f64;
            let wj = j * j * w1;
            let f =
                |t: f64, y: [f64; 2]| [y[1], force(j, t) - 2.0 * zeta * wj * y[1] - wj * wj * y[0]];
            let k1 = f(t, *q);
            let k2 = f(
                t + h / 2.0,
                [q[0] + h / 2.0 * k1[0], q[1] + h / 2.0 * k1[1]],
            );
            let k3 = f(
                t + h / 2.0,
                [q[0] + h / 2.0 * k2[0], q[1] + h / 2.0 * k2[1]],
            );
            let k4 = f(t + h, [q[0] + h * k3[0], q[1] + h * k3[1]]);
            for c in 0..2 {
                q[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
            }
        }
    }
    (dmax, amax)
}

#[test]
fn a_braking_force_gives_the_modal_solution_of_its_motion() {
    let (modes, zeta) = (5, 0.02);
    let beam = yang_yau_beam(modes, zeta);
    let bridge = beam.modal();
    let l = beam.span_m;
    let f1 = bridge.frequencies_hz[0];
    let v0 = 0.5 * 2.0 * f1 * l;
    // the speed halves over the span: v² = v₀² − 2 a L
    let a = 3.0 * v0 * v0 / (8.0 * l);
    let mut train = train_of(vec![(moving_force(P), 0.0)], v0, 0.0);
    train.runs[0].change = Some(SpeedChange {
        from_x_m: 0.0,
        rate_m_s2: -a,
        to_speed_m_s: 0.3 * v0,
    });
    let dt = 2.0e-4;
    // across the span in v₀/(2a), then a period of free vibration
    let t_end = v0 / (2.0 * a) + 1.0 / f1;
    let mut sol = Monolithic::new(bridge.clone(), train, Arc::new(Smooth), dt);
    let (mut dmax, mut amax) = (0.0_f64, 0.0_f64);
    while sol.t < t_end {
        sol.step();
        dmax = dmax.max(deck_z(&bridge, l / 2.0, sol.q.as_slice()).abs());
        amax = amax.max(deck_z(&bridge, l / 2.0, sol.qdd.as_slice()).abs());
    }
    let x = |t: f64| v0 * t - 0.5 * a * t * t;
    let (d_ref, a_ref) = modal_peaks(modes, zeta, x, dt / 20.0, t_end);
    let (ed, ea) = ((dmax - d_ref).abs() / d_ref, (amax - a_ref).abs() / a_ref);
    assert!(
        ed < 0.005,
        "displacement peak {dmax:e} against {d_ref:e} ({ed:e})"
    );
    assert!(
        ea < 0.005,
        "acceleration peak {amax:e} against {a_ref:e} ({ea:e})"
    );
    // the test tells braking apart: at constant speed the peak differs by twice the tolerance
    let at_constant = modal_peaks(modes, zeta, |t| v0 * t, dt / 20.0, l / v0 + 1.0 / f1).0;
    assert!(
        (at_constant - d_ref).abs() / d_ref > 2.0 * 0.005,
        "{at_constant:e} against {d_ref:e}"
    );
}

#[test]
fn a_braking_coach_settles_to_the_static_balance_of_its_inertia() {
    let p = CoachParams::xia2000();
    let coach = p.build().unwrap();
    let (v0, a, t_brake) = (60.0, 1.0, 1.0);
    let mut train = train_of(vec![(coach.clone(), 0.0)], v0, 0.0);
    train.runs[0].change = Some(SpeedChange {
        from_x_m: v0 * t_brake,
        rate_m_s2: -a,
        to_speed_m_s: 10.0,
    });
    // the deck far beyond where the coach runs: rigid track throughout
    let mut beam = yang_yau_beam(3, 0.02);
    beam.x_start_m = 1.0e5;
    let mut sol = Monolithic::new(beam.modal(), train, Arc::new(Smooth), 2.0e-3);
    let before: Vec<f64> = sol.forces.iter().map(|f| f.z).collect();
    assert_eq!(sol.vehicles[0].v[4], 0.0, "level before braking");
    while sol.t < t_brake + 30.0 {
        sol.step();
    }
    let pitch = sol.vehicles[0].v[4];
    let want =
        p.car_mass_kg * (-a) * p.h1_m * (2.0 / p.k2v_n_m + 1.0 / p.k1v_n_m) / (4.0 * p.s_m * p.s_m);
    assert!(
        (pitch - want).abs() <= 1e-6 * want.abs(),
        "car-body pitch {pitch:e} rad against {want:e} rad"
    );
    assert!(pitch < 0.0, "braking pitches the nose down");
    // Σ x_w ΔP_w about the coach's centre, x forward
    let centre = coach.wheelsets.iter().map(|w| w.offset_m).sum::<f64>() / 4.0;
    let moment: f64 = (coach.wheelsets.iter().zip(&sol.forces).zip(&before))
        .map(|((w, f), f0)| (centre - w.offset_m) * (f.z - f0))
        .sum();
    let h = p.h1_m + p.h2_m + p.h3_m;
    let want = a * (p.car_mass_kg * h + 2.0 * p.bogie_mass_kg * p.h3_m);
    assert!(
        (moment - want).abs() <= 1e-6 * want,
        "wheel-load moment {moment:e} N·m against {want:e} N·m"
    );
}

/// A description whose speed change cannot end where it says (as a train FMU whose `speed`
/// parameter was set past its braking's final speed) does not build, and says why.
#[test]
fn a_speed_change_that_cannot_end_where_it_says_does_not_build() {
    use tbi_dynamics::train::{Speed, TrainDescription, TrainSpec};
    let mut d = TrainDescription {
        spec: TrainSpec::Coaches {
            params: CoachParams::xia2000(),
            count: 1,
        },
        speed_m_s: Speed::from_m_s(20.0).unwrap(),
        x0_m: 0.0,
        direction: Default::default(),
        track: 0,
        change: Some(SpeedChange {
            from_x_m: 5.0,
            rate_m_s2: -1.0,
            to_speed_m_s: 10.0,
        }),
        hunting: Default::default(),
        crosswind: None,
    };
    assert!(d.build(0.0).is_ok());
    d.speed_m_s = Speed::from_m_s(8.0).unwrap();
    let e = d.build(0.0).unwrap_err();
    assert!(e.contains("cannot end at 10 m/s"), "{e}");
}
