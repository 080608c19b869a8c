#![allow(dead_code)]
//! Shared helpers for the dynamics tests.
pub mod eq14;

use std::sync::Arc;
use tbi_dynamics::bridge::{ModalBridge, SimplySupported};
use tbi_dynamics::train::{Train, TrainRun, TrainVehicle};
use tbi_dynamics::vehicle::LinearVehicle;

/// Yang & Yau (1997) beam: L = 25 m, E = 2.87e9 Pa, I = 2.9 m⁴, μ = 2303 kg/m.
pub fn yang_yau_beam(modes: usize, damping: f64) -> SimplySupported {
    SimplySupported {
        span_m: 25.0,
        youngs_modulus_pa: 2.87e9,
        inertia_vertical_m4: 2.9,
        inertia_lateral_m4: None,
        shear_modulus_pa: None,
        torsion_constant_m4: None,
        polar_inertia_kg_m: None,
        mass_per_length_kg_m: 2303.0,
        modes,
        damping_ratio: damping,
        damping_ratio_torsional: damping,
        e_m: 0.0,
        h4_m: 0.0,
        x_start_m: 0.0,
    }
}

pub fn train_of(vehicles: Vec<(LinearVehicle, f64)>, speed: f64, x0: f64) -> Train {
    let n: usize = vehicles.iter().map(|v| v.0.wheelsets.len()).sum();
    let vehicles = (vehicles.into_iter())
        .map(|(m, off)| TrainVehicle {
            model: Arc::new(m),
            offset_m: off,
            run: 0,
        })
        .collect();
    let hunting = tbi_track::WheelHunting::new(&tbi_track::HuntingParams::default(), n).unwrap();
    Train::single(
        vehicles,
        TrainRun::steady(speed, x0, Default::default(), hunting),
    )
}

/// Midspan vertical displacement of a modal bridge.
pub fn deck_z(bridge: &ModalBridge, x: f64, q: &[f64]) -> f64 {
    let mut sh = vec![[0.0; 3]; bridge.n_modes()];
    bridge.deck_shapes(x, &mut sh);
    sh.iter().zip(q).map(|(s, q)| s[1] * q).sum()
}

/// Exact response of x'' + 2ζω x' + ω² x = F0 sin(Ω t) for 0 ≤ t ≤ T (from rest), then free
/// vibration. Returns x(t).
pub fn sdof_sine_exact(
    omega: f64,
    zeta: f64,
    f0: f64,
    big_omega: f64,
    t_force: f64,
    t: f64,
) -> f64 {
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    // (x, x') during forcing
    let forced = |t: f64| -> (f64, f64) {
        let d = (omega * omega - big_omega * big_omega).powi(2)
            + (2.0 * zeta * omega * big_omega).powi(2);
        if zeta == 0.0 && d < 1e-18 * omega.powi(4) {
            // resonance: x = F0/(2ω²) (sin ωt − ωt cos ωt)
            let x =
                f0 / (2.0 * omega * omega) * ((omega * t).sin() - omega * t * (omega * t).cos());
            let xd = f0 / (2.0 * omega * omega) * (omega * omega * t * (omega * t).sin());
            return (x, xd);
        }
        let a = f0 * (omega * omega - big_omega * big_omega) / d;
        let b = -f0 * 2.0 * zeta * omega * big_omega / d;
        let c1 = -b;
        let c2 = (zeta * omega * c1 - a * big_omega) / wd;
        let e = (-zeta * omega * t).exp();
        let (s, c) = (wd * t).sin_cos();
        let x = a * (big_omega * t).sin() + b * (big_omega * t).cos() + e * (c1 * c + c2 * s);
        let xd = a * big_omega * (big_omega * t).cos() - b * big_omega * (big_omega * t).sin()
            + e * (-zeta * omega * (c1 * c + c2 * s) + wd * (-c1 * s + c2 * c));
        (x, xd)
    };
    if t <= t_force {
        return forced(t).0;
    }
    let (x0, v0) = forced(t_force);
    let tau = t - t_force;
    let e = (-zeta * omega * tau).exp();
    e * (x0 * (wd * tau).cos() + (v0 + zeta * omega * x0) / wd * (wd * tau).sin())
}

/// A deterministic, smooth irregularity with all three components.
#[derive(Debug)]
pub struct Waves;

impl tbi_dynamics::track::RailProfile for Waves {
    fn at(&self, x: f64) -> tbi_dynamics::track::RailIrregularity {
        let c = |a: f64, l: f64, ph: f64| {
            let k = 2.0 * std::f64::consts::PI / l;
            let (s, co) = (k * x + ph).sin_cos();
            [a * s, a * k * co, -a * k * k * s]
        };
        tbi_dynamics::track::RailIrregularity {
            lateral: c(2e-3, 17.0, 0.3),
            cross_level: c(1e-3, 23.0, 1.1),
            vertical: c(3e-3, 11.0, 2.0),
        }
    }

    fn third_derivative(&self, x: f64) -> nalgebra::Vector3<f64> {
        let c = |a: f64, l: f64, ph: f64| {
            let k = 2.0 * std::f64::consts::PI / l;
            -a * k * k * k * (k * x + ph).cos()
        };
        nalgebra::Vector3::new(c(2e-3, 17.0, 0.3), c(1e-3, 23.0, 1.1), c(3e-3, 11.0, 2.0))
    }
}
