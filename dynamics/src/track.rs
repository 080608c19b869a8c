//! Prescribed rail geometry seen by the wheelsets: track irregularity and wheel hunting.
//!
//! A profile gives, at distance `x` along the track, the lateral `Y_s`, cross-level `θ_s` and
//! vertical `Z_s` irregularity with their first and second derivatives in x. A wheelset moving
//! at constant speed `v` sees `r = (Y_s, θ_s, Z_s)`, `ṙ = v r′`, `r̈ = v² r″`.
//! Wheel hunting (eq. 7) adds `Y_h = A_h sin(2π s / L_h + φ)` to the lateral DOF, with `s`
//! the distance travelled.

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::fmt::Debug;

/// Irregularity at a point: each array is (value, d/dx, d²/dx²).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RailIrregularity {
    /// Lateral (alignment) Y_s, m.
    pub lateral: [f64; 3],
    /// Cross-level as an angle θ_s, rad.
    pub cross_level: [f64; 3],
    /// Vertical (profile) Z_s, m (+ down).
    pub vertical: [f64; 3],
}

/// A rail irregularity profile along the track.
pub trait RailProfile: Send + Sync + Debug {
    fn at(&self, x: f64) -> RailIrregularity;
}

/// A perfectly smooth track.
#[derive(Debug, Clone, Copy, Default)]
pub struct Smooth;

impl RailProfile for Smooth {
    fn at(&self, _x: f64) -> RailIrregularity {
        RailIrregularity::default()
    }
}

/// Rail DOF motion `(u, u̇, ü)` in the order (lateral, roll, vertical) of an irregularity
/// seen at constant speed `v`.
pub fn rail_motion(r: &RailIrregularity, v: f64) -> [Vector3<f64>; 3] {
    [
        Vector3::new(r.lateral[0], r.cross_level[0], r.vertical[0]),
        Vector3::new(r.lateral[1], r.cross_level[1], r.vertical[1]) * v,
        Vector3::new(r.lateral[2], r.cross_level[2], r.vertical[2]) * (v * v),
    ]
}

/// Wheel hunting (eq. 7). Amplitude 0 switches it off.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Hunting {
    /// Amplitude A_h, m.
    pub amplitude_m: f64,
    /// Wavelength L_h, m.
    pub wavelength_m: f64,
    /// Phase φ of each wheelset of the train, rad.
    pub phases: Vec<f64>,
}

impl Hunting {
    pub fn off(n_wheelsets: usize) -> Self {
        Hunting {
            amplitude_m: 0.0,
            wavelength_m: 1.0,
            phases: vec![0.0; n_wheelsets],
        }
    }

    /// (Y_h, dY_h/dt, d²Y_h/dt²) of wheelset `w` after travelling `s` at speed `v`.
    pub fn lateral(&self, w: usize, s: f64, v: f64) -> [f64; 3] {
        if self.amplitude_m == 0.0 {
            return [0.0; 3];
        }
        let k = 2.0 * std::f64::consts::PI / self.wavelength_m;
        let arg = k * s + self.phases[w];
        let (sn, cs) = arg.sin_cos();
        let a = self.amplitude_m;
        [a * sn, a * k * v * cs, -a * k * k * v * v * sn]
    }
}
