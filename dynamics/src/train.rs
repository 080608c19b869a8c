//! A train: vehicles in a row moving at constant speed in +x.
//!
//! Positions are measured along the track. Wheelset `w` of the train (numbered front to
//! back over all vehicles) sits at `offset_w` behind the first axle, which is at `x0` at
//! `t = 0`, so `x_w(t) = x0 + v t − offset_w`.

use crate::vehicle::LinearVehicle;
use std::sync::Arc;

/// One vehicle of a train.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainVehicle {
    pub model: Arc<LinearVehicle>,
    /// Distance of this vehicle's first wheelset behind the train's first axle, m.
    pub offset_m: f64,
}

/// A train (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Train {
    pub vehicles: Vec<TrainVehicle>,
    /// Speed v, m/s (> 0).
    pub speed_m_s: f64,
    /// Position of the first axle at t = 0, m.
    pub x0_m: f64,
    /// Wheel hunting of every wheelset.
    pub hunting: tbi_track::WheelHunting,
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
        self.x0_m + self.speed_m_s * t - offset_m
    }
}
