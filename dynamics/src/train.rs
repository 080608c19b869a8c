//! A train: vehicles in a row moving at constant speed in +x (forward) or −x (backward).
//!
//! Positions are measured along the track. Wheelset `w` of the train (numbered front to
//! back over all vehicles) sits at `offset_w` behind the first axle, which is at `x0` at
//! `t = 0`, so `x_w(t) = x0 + d (v t − offset_w)` with `d = +1` forward and `−1` backward.
//!
//! A backward train's vehicles face −x: their own lateral axis points to −y and their roll
//! is the deck's with the opposite sign, so each vehicle is used mirrored
//! ([`crate::vehicle::LinearVehicle::mirrored`]: its rail degrees of freedom Y, θ, Z seen
//! through S = diag(−1, −1, 1)), and its wheel hunting, a lateral motion in the vehicle's
//! frame, enters the deck's frame as −Y_h. The vehicle then moves in its own frame exactly
//! as a forward one does over the deck turned end for end.

mod description;

pub use description::{Crosswind, TrainDescription, TrainSpec};

use crate::vehicle::LinearVehicle;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A train speed, m/s: finite and > 0. [`Speed::from_m_s`] is the one place a speed is
/// checked; the scenario, the command line and the train FMU's `speed` parameter all go
/// through it. In JSON it is a bare number.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Serialize, Deserialize)]
#[serde(try_from = "f64", into = "f64")]
pub struct Speed(f64);

/// Why a number is not a [`Speed`].
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("must be a positive finite number, at most 200 m/s (720 km/h)")]
pub struct SpeedError;

impl Speed {
    /// The highest speed accepted, m/s (above any rail vehicle's).
    pub const MAX_M_S: f64 = 200.0;

    /// A speed of `v` m/s, 0 < v ≤ [`Speed::MAX_M_S`].
    pub fn from_m_s(v: f64) -> Result<Speed, SpeedError> {
        if v > 0.0 && v <= Self::MAX_M_S {
            Ok(Speed(v))
        } else {
            Err(SpeedError)
        }
    }

    /// The speed in m/s.
    pub fn m_s(self) -> f64 {
        self.0
    }
}

impl TryFrom<f64> for Speed {
    type Error = SpeedError;
    fn try_from(v: f64) -> Result<Speed, SpeedError> {
        Speed::from_m_s(v)
    }
}

impl From<Speed> for f64 {
    fn from(s: Speed) -> f64 {
        s.0
    }
}

/// The direction a train runs in along the track.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TravelDirection {
    /// Towards +x.
    #[default]
    Forward,
    /// Towards −x.
    Backward,
}

impl TravelDirection {
    /// Whether it is [`TravelDirection::Forward`].
    pub fn is_forward(&self) -> bool {
        *self == TravelDirection::Forward
    }

    /// `+1` forward, `−1` backward.
    pub fn sign(self) -> f64 {
        match self {
            TravelDirection::Forward => 1.0,
            TravelDirection::Backward => -1.0,
        }
    }
}

/// One vehicle of a train.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainVehicle {
    pub model: Arc<LinearVehicle>,
    /// Distance of this vehicle's first wheelset behind the train's first axle, m.
    pub offset_m: f64,
}

impl TrainVehicle {
    /// Distance of this vehicle's centre (the mean of its wheelsets) behind the train's first
    /// axle, m.
    pub fn centre_offset_m(&self) -> f64 {
        let n = self.model.wheelsets.len().max(1) as f64;
        self.offset_m + self.model.wheelsets.iter().map(|w| w.offset_m).sum::<f64>() / n
    }
}

/// A train (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Train {
    pub vehicles: Vec<TrainVehicle>,
    /// Speed v, m/s (> 0; a standing train, v = 0, is allowed in tests of statics).
    pub speed_m_s: f64,
    /// Position of the first axle at t = 0, m.
    pub x0_m: f64,
    /// The direction of travel (the vehicles of a backward train are mirrored).
    pub direction: TravelDirection,
    /// Wheel hunting of every wheelset.
    pub hunting: tbi_track::WheelHunting,
    /// The wind on the car bodies beyond their static loads (None: still air, or a steady
    /// wind whose loads the static equilibrium holds throughout).
    pub wind: Option<std::sync::Arc<crate::vehicle::aero::TrainWind>>,
}

/// Where a train wheelset lives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelsetRef {
    pub vehicle: usize,
    /// Index within the vehicle.
    pub local: usize,
    /// Distance behind the first axle, m.
    pub offset_m: f64,
}

impl Train {
    /// All wheelsets front to back.
    pub fn wheelsets(&self) -> Vec<WheelsetRef> {
        let mut out = Vec::new();
        for (i, tv) in self.vehicles.iter().enumerate() {
            for (l, ws) in tv.model.wheelsets.iter().enumerate() {
                out.push(WheelsetRef {
                    vehicle: i,
                    local: l,
                    offset_m: tv.offset_m + ws.offset_m,
                });
            }
        }
        out
    }

    /// Per vehicle, the first vehicle with the same model (the same `Arc`, as the coaches of
    /// one train; the vehicle itself when none before it has it). Data derived from a model
    /// alone can be kept once per model and read from there.
    pub fn first_of_same_model(&self) -> Vec<usize> {
        (self.vehicles.iter())
            .map(|tv| {
                (self.vehicles.iter())
                    .position(|first| Arc::ptr_eq(&first.model, &tv.model))
                    .expect("the vehicle itself")
            })
            .collect()
    }

    pub fn n_wheelsets(&self) -> usize {
        self.vehicles.iter().map(|v| v.model.wheelsets.len()).sum()
    }

    /// Distance from the first to the last axle, m.
    pub fn length_m(&self) -> f64 {
        self.wheelsets()
            .iter()
            .map(|w| w.offset_m)
            .fold(0.0, f64::max)
    }

    /// Position of a wheelset at offset `offset_m` at time `t`, m.
    #[inline]
    pub fn x_at(&self, offset_m: f64, t: f64) -> f64 {
        match self.direction {
            TravelDirection::Forward => self.x0_m + self.speed_m_s * t - offset_m,
            TravelDirection::Backward => self.x0_m - self.speed_m_s * t + offset_m,
        }
    }

    /// The velocity along x, m/s: the speed, negative for a backward train.
    #[inline]
    pub fn vx(&self) -> f64 {
        self.direction.sign() * self.speed_m_s
    }

    /// The hunting motion `(Y_h, Ẏ_h, Ÿ_h)` of wheelset `w` at `t` in the deck's frame.
    pub fn hunting_at(&self, w: usize, t: f64) -> [f64; 3] {
        let v = self.speed_m_s;
        let h = crate::track::hunting_motion(&self.hunting, w, v * t, v);
        match self.direction {
            TravelDirection::Forward => h,
            TravelDirection::Backward => h.map(|x| -x),
        }
    }

    /// Distance of vehicle `i`'s centre (the mean of its wheelsets) behind the first axle, m.
    pub fn centre_offset_m(&self, i: usize) -> f64 {
        self.vehicles[i].centre_offset_m()
    }

    /// Position at time `t` of the centre of vehicle `i`'s car body, if the wind loads it, m.
    pub fn wind_body_x(&self, i: usize, t: f64) -> Option<f64> {
        let body = self.wind.as_ref()?.bodies[i].as_ref()?;
        Some(self.x_at(body.1, t))
    }

    /// Add `scale` times the wind force on vehicle `i` beyond its static loads at time `t`
    /// with the along-wind turbulence `u` at its centre ([`crate::vehicle::aero::TrainWind`])
    /// to `f`.
    pub fn add_wind_force(
        &self,
        i: usize,
        t: f64,
        u: f64,
        scale: f64,
        f: &mut nalgebra::DVector<f64>,
    ) {
        if let (Some(w), Some(x)) = (&self.wind, self.wind_body_x(i, t)) {
            w.add_force(i, x, u, scale, f);
        }
    }

    /// The wind force on vehicle `i` beyond its static loads at time `t` in the turbulence
    /// `u` (one per DOF), for an initial acceleration; None in still air.
    pub fn wind_force(&self, i: usize, t: f64, u: f64) -> Option<nalgebra::DVector<f64>> {
        self.wind.as_ref()?;
        let mut f = nalgebra::DVector::zeros(self.vehicles[i].model.ndof());
        self.add_wind_force(i, t, u, 1.0, &mut f);
        Some(f)
    }
}
