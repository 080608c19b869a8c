//! Trains: vehicles in rows, each row (a train) moving in +x (forward) or −x (backward) on
//! its own track, at constant speed or braking or accelerating once ([`TrainRun`]).
//!
//! Positions are measured along the track. Wheelset `w` of a train (numbered front to back
//! over its vehicles) sits at `offset_w` behind the train's first axle, which is at `x0` at
//! `t = t₀` and has travelled `s(t)` since, so `x_w(t) = x0 + d (s(t) − offset_w)` with
//! `d = +1` forward and `−1` backward (`s = v (t − t₀)` at constant speed).
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

    /// `"forward"` or `"backward"`, as the scenario writes it.
    pub fn as_str(self) -> &'static str {
        match self {
            TravelDirection::Forward => "forward",
            TravelDirection::Backward => "backward",
        }
    }

    /// `+1` forward, `−1` backward.
    pub fn sign(self) -> f64 {
        match self {
            TravelDirection::Forward => 1.0,
            TravelDirection::Backward => -1.0,
        }
    }
}

/// A change of speed: from where the first axle passes `from_x_m`, the speed changes at a
/// constant rate until it reaches `to_speed_m_s`, and stays there (0: the train stops and
/// stands).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedChange {
    /// Where the change begins: the first axle's position, m.
    pub from_x_m: f64,
    /// The rate of change of the speed, m/s² (< 0 braking, > 0 accelerating).
    pub rate_m_s2: f64,
    /// The speed it ends at, m/s (≥ 0).
    pub to_speed_m_s: f64,
}

/// How one train runs: where and when it starts, its speed (constant, or changing once), its
/// direction and track, and its wheels' hunting.
///
/// Its first axle has travelled `s(t)` from `x0_m` at time `t` (`s = v₀ (t − t₀)` at
/// constant speed; with a [`SpeedChange`] `s` is piecewise quadratic: `v₀` until the
/// change begins, then `v₀ + a τ`, then the final speed), and wheelset `w` of the train, at
/// `offset_w` behind the first axle, is at `x_w = x0 + d (s − offset_w)`.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainRun {
    /// The speed at the start v₀, m/s (> 0; a standing train, v = 0, is allowed in tests of
    /// statics).
    pub speed_m_s: f64,
    /// Position of the first axle at `t0_s`, m.
    pub x0_m: f64,
    /// The time the first axle is at `x0_m`, s.
    pub t0_s: f64,
    /// The direction of travel (the vehicles of a backward train are mirrored).
    pub direction: TravelDirection,
    /// The track it runs on: 0 the first ([`crate::bridge::ModalBridge::track_place`]).
    pub track: usize,
    /// A change of speed (None: constant speed).
    pub change: Option<SpeedChange>,
    /// Wheel hunting of its wheelsets (numbered within the train).
    pub hunting: tbi_track::WheelHunting,
}

/// The motion of a train's first axle at one time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Travel {
    /// Distance travelled from `x0`, m.
    pub s_m: f64,
    /// Speed, m/s (≥ 0).
    pub v_m_s: f64,
    /// Rate of change of the speed, m/s² (along the direction of travel).
    pub a_m_s2: f64,
}

impl TrainRun {
    /// A train at constant speed `speed_m_s` from `x0_m` at t = 0, on the first track.
    pub fn steady(
        speed_m_s: f64,
        x0_m: f64,
        direction: TravelDirection,
        hunting: tbi_track::WheelHunting,
    ) -> TrainRun {
        TrainRun {
            speed_m_s,
            x0_m,
            t0_s: 0.0,
            direction,
            track: 0,
            change: None,
            hunting,
        }
    }

    /// The first axle's travel at time `t`.
    #[inline]
    pub fn travel(&self, t: f64) -> Travel {
        let v0 = self.speed_m_s;
        let tau = t - self.t0_s;
        let steady = Travel {
            s_m: v0 * tau,
            v_m_s: v0,
            a_m_s2: 0.0,
        };
        let Some(c) = &self.change else {
            return steady;
        };
        let (s1, t1) = self.change_begins(c);
        if tau <= t1 || c.rate_m_s2 == 0.0 {
            return steady;
        }
        let a = c.rate_m_s2;
        let t2 = t1 + (c.to_speed_m_s - v0) / a;
        let s2 = s1 + v0 * (t2 - t1) + 0.5 * a * (t2 - t1) * (t2 - t1);
        if tau < t2 {
            let u = tau - t1;
            return Travel {
                s_m: s1 + v0 * u + 0.5 * a * u * u,
                v_m_s: v0 + a * u,
                a_m_s2: a,
            };
        }
        Travel {
            s_m: s2 + c.to_speed_m_s * (tau - t2),
            v_m_s: c.to_speed_m_s,
            a_m_s2: 0.0,
        }
    }

    /// Position of a wheelset at offset `offset_m` at time `t`, m.
    #[inline]
    pub fn x_at(&self, offset_m: f64, t: f64) -> f64 {
        self.x_after(self.travel(t).s_m, offset_m)
    }

    /// Position of a wheelset at offset `offset_m` once the first axle has travelled `s`, m.
    #[inline]
    pub fn x_after(&self, s: f64, offset_m: f64) -> f64 {
        match self.direction {
            TravelDirection::Forward => self.x0_m + s - offset_m,
            TravelDirection::Backward => self.x0_m - s + offset_m,
        }
    }

    /// The velocity along x at `t`, m/s: the speed, negative for a backward train.
    #[inline]
    pub fn vx(&self, t: f64) -> f64 {
        self.direction.sign() * self.travel(t).v_m_s
    }

    /// The hunting motion `(Y_h, Ẏ_h, Ÿ_h)` of the train's wheelset `w` at `t` in the deck's
    /// frame (with a changing speed, the term `a dY_h/ds` of `Ÿ_h` is left out, as the
    /// `a r′` of the irregularity's: see [`crate::solver::rail_prescribed`]).
    pub fn hunting_at(&self, w: usize, t: f64) -> [f64; 3] {
        let tr = self.travel(t);
        let h = crate::track::hunting_motion(&self.hunting, w, tr.s_m, tr.v_m_s);
        match self.direction {
            TravelDirection::Forward => h,
            TravelDirection::Backward => h.map(|x| -x),
        }
    }

    /// The first time the first axle has travelled `s` (≥ 0) from `x0_m`, or None if it
    /// stops before: the inverse of [`Self::travel`], in closed form.
    pub fn time_to_travel(&self, s: f64) -> Option<f64> {
        let v0 = self.speed_m_s;
        let steady = |s: f64| (v0 > 0.0).then(|| self.t0_s + s / v0);
        let Some(c) = self.change.as_ref().filter(|c| c.rate_m_s2 != 0.0) else {
            return steady(s);
        };
        let (s1, t1) = self.change_begins(c);
        if s <= s1 {
            return steady(s);
        }
        let a = c.rate_m_s2;
        let u2 = (c.to_speed_m_s - v0) / a;
        let s2 = s1 + v0 * u2 + 0.5 * a * u2 * u2;
        if s <= s2 {
            // s1 + v0 u + a u²/2 = s, the root on the way (u ≤ u2)
            let disc = (v0 * v0 + 2.0 * a * (s - s1)).max(0.0);
            let u = 2.0 * (s - s1) / (v0 + disc.sqrt());
            return Some(self.t0_s + t1 + u);
        }
        (c.to_speed_m_s > 0.0).then(|| self.t0_s + t1 + u2 + (s - s2) / c.to_speed_m_s)
    }

    /// The time the speed reaches zero and stays there (None: it never stops), s.
    pub fn stop_time(&self) -> Option<f64> {
        let c = self.change.as_ref()?;
        if c.to_speed_m_s > 0.0 || c.rate_m_s2 >= 0.0 {
            return None;
        }
        let t1 = self.change_begins(c).1;
        Some(self.t0_s + t1 - self.speed_m_s / c.rate_m_s2)
    }

    /// Where the change `c` begins, as the distance the first axle has travelled (at once
    /// when the train starts past `from_x_m`), and when, after `t0_s`.
    #[inline]
    fn change_begins(&self, c: &SpeedChange) -> (f64, f64) {
        let s1 = (self.direction.sign() * (c.from_x_m - self.x0_m)).max(0.0);
        let v0 = self.speed_m_s;
        (s1, if v0 > 0.0 { s1 / v0 } else { 0.0 })
    }
}

/// One vehicle of a train.
#[derive(Debug, Clone, PartialEq)]
pub struct TrainVehicle {
    pub model: Arc<LinearVehicle>,
    /// Distance of this vehicle's first wheelset behind its train's first axle, m.
    pub offset_m: f64,
    /// Its train: an index into [`Train::runs`].
    pub run: usize,
}

impl TrainVehicle {
    /// Distance of this vehicle's centre (the mean of its wheelsets) behind its train's first
    /// axle, m.
    pub fn centre_offset_m(&self) -> f64 {
        let n = self.model.wheelsets.len().max(1) as f64;
        self.offset_m + self.model.wheelsets.iter().map(|w| w.offset_m).sum::<f64>() / n
    }
}

/// The trains on the bridge: their vehicles, one row after the other (train 1's front to
/// back, then train 2's, …), and how each train runs (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Train {
    pub vehicles: Vec<TrainVehicle>,
    /// How each train runs (one per train; `vehicles[i].run` indexes it).
    pub runs: Vec<TrainRun>,
    /// The wind on the car bodies beyond their static loads (None: still air, or a steady
    /// wind whose loads the static equilibrium holds throughout). One train only.
    pub wind: Option<std::sync::Arc<crate::vehicle::aero::TrainWind>>,
}

/// Where a train wheelset lives.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelsetRef {
    pub vehicle: usize,
    /// Index within the vehicle.
    pub local: usize,
    /// Distance behind its train's first axle, m.
    pub offset_m: f64,
    /// Its train: an index into [`Train::runs`].
    pub run: usize,
    /// Index within its train, front to back.
    pub in_run: usize,
}

impl Train {
    /// One train of `vehicles` running as `run`.
    pub fn single(vehicles: Vec<TrainVehicle>, run: TrainRun) -> Train {
        let vehicles = (vehicles.into_iter())
            .map(|v| TrainVehicle { run: 0, ..v })
            .collect();
        Train {
            vehicles,
            runs: vec![run],
            wind: None,
        }
    }

    /// The trains of `trains` (each one train, without wind) on the bridge together.
    pub fn together(trains: Vec<Train>) -> Train {
        let mut all = Train {
            vehicles: Vec::new(),
            runs: Vec::new(),
            wind: None,
        };
        for t in trains {
            let base = all.runs.len();
            (all.vehicles).extend(t.vehicles.into_iter().map(|v| TrainVehicle {
                run: v.run + base,
                ..v
            }));
            all.runs.extend(t.runs);
        }
        all
    }

    /// The first train's run (the only one of a single train).
    pub fn run(&self) -> &TrainRun {
        &self.runs[0]
    }

    /// All wheelsets front to back, train after train.
    pub fn wheelsets(&self) -> Vec<WheelsetRef> {
        let mut out = Vec::new();
        let mut in_run = vec![0; self.runs.len()];
        for (i, tv) in self.vehicles.iter().enumerate() {
            for (l, ws) in tv.model.wheelsets.iter().enumerate() {
                out.push(WheelsetRef {
                    vehicle: i,
                    local: l,
                    offset_m: tv.offset_m + ws.offset_m,
                    run: tv.run,
                    in_run: in_run[tv.run],
                });
                in_run[tv.run] += 1;
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

    /// Distance from the first to the last axle of train `run`, m.
    pub fn length_m(&self, run: usize) -> f64 {
        (self.wheelsets().iter())
            .filter(|w| w.run == run)
            .map(|w| w.offset_m)
            .fold(0.0, f64::max)
    }

    /// Position of wheelset `ws` at time `t`, m.
    #[inline]
    pub fn x_of(&self, ws: &WheelsetRef, t: f64) -> f64 {
        self.runs[ws.run].x_at(ws.offset_m, t)
    }

    /// Whether any wheel hunts.
    pub fn hunts(&self) -> bool {
        self.runs.iter().any(|r| r.hunting.is_active())
    }

    /// Distance of vehicle `i`'s centre (the mean of its wheelsets) behind its train's first
    /// axle, m.
    pub fn centre_offset_m(&self, i: usize) -> f64 {
        self.vehicles[i].centre_offset_m()
    }

    /// Position at time `t` of the centre of vehicle `i`'s car body, if the wind loads it, m.
    pub fn wind_body_x(&self, i: usize, t: f64) -> Option<f64> {
        let body = self.wind.as_ref()?.bodies[i].as_ref()?;
        Some(self.runs[self.vehicles[i].run].x_at(body.1, t))
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

    /// The rate of change of the speed of vehicle `i`'s train at `t`, m/s² (+ speeding up):
    /// its bodies' inertia loads it ([`crate::vehicle::LinearVehicle::inertia`]).
    #[inline]
    pub fn acceleration_of(&self, i: usize, t: f64) -> f64 {
        let run = &self.runs[self.vehicles[i].run];
        match run.change {
            None => 0.0,
            Some(_) => run.travel(t).a_m_s2,
        }
    }

    /// Whether vehicle `i`'s train changes its speed at some time.
    pub fn changes_speed(&self, i: usize) -> bool {
        self.runs[self.vehicles[i].run].change.is_some()
    }

    /// The force on vehicle `i` beyond its static loads at time `t` (one per DOF), for an
    /// initial acceleration: the wind's in the turbulence `u`, and the inertia of a changing
    /// speed; None in still air at constant speed.
    pub fn body_force(&self, i: usize, t: f64, u: f64) -> Option<nalgebra::DVector<f64>> {
        let model = &self.vehicles[i].model;
        let a = self.acceleration_of(i, t);
        if self.wind.is_none() && (a == 0.0 || model.inertia.is_empty()) {
            return None;
        }
        let mut f = nalgebra::DVector::zeros(model.ndof());
        self.add_wind_force(i, t, u, 1.0, &mut f);
        model.add_inertia(a, f.as_mut_slice());
        Some(f)
    }
}
