//! Prescribed rail geometry seen by the wheelsets: track irregularity and wheel hunting.
//!
//! A profile gives, at distance `x` along the track, the lateral `Y_s`, cross-level `θ_s` and
//! vertical `Z_s` irregularity with their first and second derivatives in x. A wheelset moving
//! at constant speed `v` sees `r = (Y_s, θ_s, Z_s)`, `ṙ = v r′`, `r̈ = v² r″`.
//! Wheel hunting (eq. 7) adds `Y_h = A_h sin(2π s / L_h + φ)` to the lateral DOF, with `s`
//! the distance travelled.

use nalgebra::Vector3;
use std::fmt::Debug;

pub use tbi_track::RailIrregularity;

/// A rail irregularity profile along the track.
pub trait RailProfile: Send + Sync + Debug {
    fn at(&self, x: f64) -> RailIrregularity;

    /// Third derivatives `d³/dx³` of (lateral, roll, vertical) — the rail DOF order — at `x`:
    /// the x-derivative of the rail acceleration `v² r″` a wheelset sees
    /// ([`rail_motion_slope`]).
    fn third_derivative(&self, x: f64) -> Vector3<f64>;

    /// Whether the profile is zero everywhere (the ideal track), so that [`Self::at`] gives
    /// zeros at every `x` and a caller may leave it out. Default: false.
    fn is_flat(&self) -> bool {
        false
    }

    /// A hint that [`Self::at`] at `x` follows soon (the wheelsets' positions of the next
    /// step), so that a profile whose data may not be in the cache can start loading it.
    /// Changes no result. Default: nothing.
    fn prefetch(&self, _x: f64) {}
}

/// A perfectly smooth track.
#[derive(Debug, Clone, Copy, Default)]
pub struct Smooth;

impl RailProfile for Smooth {
    fn at(&self, _x: f64) -> RailIrregularity {
        RailIrregularity::default()
    }

    fn third_derivative(&self, _x: f64) -> Vector3<f64> {
        Vector3::zeros()
    }

    fn is_flat(&self) -> bool {
        true
    }
}

/// Rail DOF motion `(u, u̇, ü)` in the order (lateral, roll, vertical) of an irregularity
/// seen at constant speed `v`.
#[inline]
pub fn rail_motion(r: &RailIrregularity, v: f64) -> [Vector3<f64>; 3] {
    [
        Vector3::new(r.lateral[0], r.cross_level[0], r.vertical[0]),
        Vector3::new(r.lateral[1], r.cross_level[1], r.vertical[1]) * v,
        Vector3::new(r.lateral[2], r.cross_level[2], r.vertical[2]) * (v * v),
    ]
}

/// The partial derivatives of [`rail_motion`] `(u, u̇, ü) = (r, v r′, v² r″)` with respect to
/// the position, `∂/∂x = (r′, v r″, v² r‴)`, and to the speed, `∂/∂v = (0, r′, 2 v r″)`, with
/// `r‴` the profile's [`RailProfile::third_derivative`] at the same point.
pub fn rail_motion_slope(
    r: &RailIrregularity,
    third: Vector3<f64>,
    v: f64,
) -> ([Vector3<f64>; 3], [Vector3<f64>; 3]) {
    let d = |k: usize| Vector3::new(r.lateral[k], r.cross_level[k], r.vertical[k]);
    (
        [d(1), d(2) * v, third * (v * v)],
        [Vector3::zeros(), d(1), d(2) * (2.0 * v)],
    )
}

/// Wheel hunting (eq. 7) as seen in time: `(Y_h, Ẏ_h, Ÿ_h)` of wheelset `w` after travelling
/// `s` at speed `v`.
pub fn hunting_motion(h: &tbi_track::WheelHunting, w: usize, s: f64, v: f64) -> [f64; 3] {
    if !h.is_active() {
        return [0.0; 3];
    }
    let d = h.lateral(w, s);
    [d[0], d[1] * v, d[2] * v * v]
}

impl RailProfile for tbi_track::Irregularity {
    fn at(&self, x: f64) -> RailIrregularity {
        tbi_track::Irregularity::at(self, x)
    }

    fn third_derivative(&self, x: f64) -> Vector3<f64> {
        match self.profile() {
            Some(p) => {
                let [lateral, vertical, cross_level] = p.third_derivative(x);
                Vector3::new(lateral, cross_level, vertical)
            }
            None => Vector3::zeros(),
        }
    }

    fn is_flat(&self) -> bool {
        matches!(self, tbi_track::Irregularity::None)
    }

    fn prefetch(&self, x: f64) {
        tbi_track::Irregularity::prefetch(self, x)
    }
}
