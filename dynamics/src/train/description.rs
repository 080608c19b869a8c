//! A train as data ([`TrainDescription`]): what the scenario reads, the train FMU carries as
//! its resource, and both solvers build their [`Train`] from.

use super::{Speed, SpeedChange, Train, TrainRun, TrainVehicle, TravelDirection};
use crate::vehicle::coach::CoachParams;
use crate::vehicle::simple::{moving_force, sprung_mass, MovingForceAxle, SprungMassAxle};
use crate::vehicle::LinearVehicle;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use tbi_track::{HuntingParams, WheelHunting};

/// The vehicles of a train.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum TrainSpec {
    /// One moving force per axle.
    MovingForce(Vec<MovingForceAxle>),
    /// One sprung mass per axle.
    SprungMass(Vec<SprungMassAxle>),
    /// `count` identical coaches, coupled at their full length.
    Coaches { params: CoachParams, count: usize },
}

impl TrainSpec {
    /// The vehicles with their offsets behind the first axle.
    pub fn vehicles(&self) -> Result<Vec<TrainVehicle>, String> {
        Ok(match self {
            TrainSpec::MovingForce(list) => list
                .iter()
                .map(|a| TrainVehicle {
                    model: Arc::new(moving_force(a.load_n)),
                    offset_m: a.offset_m,
                    run: 0,
                })
                .collect(),
            TrainSpec::SprungMass(list) => list
                .iter()
                .map(|a| {
                    Ok(TrainVehicle {
                        model: Arc::new(sprung_mass(a)?),
                        offset_m: a.offset_m,
                        run: 0,
                    })
                })
                .collect::<Result<_, String>>()?,
            TrainSpec::Coaches { params, count } => {
                params
                    .check()
                    .map_err(|(f, v, why)| format!("coach.{f} = {v}: {why}"))?;
                let coach = Arc::new(params.build()?);
                (0..*count)
                    .map(|k| TrainVehicle {
                        model: coach.clone(),
                        offset_m: k as f64 * params.length_m,
                        run: 0,
                    })
                    .collect()
            }
        })
    }

    /// Number of wheelsets.
    pub fn n_wheelsets(&self) -> usize {
        match self {
            TrainSpec::MovingForce(l) => l.len(),
            TrainSpec::SprungMass(l) => l.len(),
            TrainSpec::Coaches { count, .. } => 4 * count,
        }
    }

    /// Number of vehicles.
    pub fn n_vehicles(&self) -> usize {
        match self {
            TrainSpec::MovingForce(l) => l.len(),
            TrainSpec::SprungMass(l) => l.len(),
            TrainSpec::Coaches { count, .. } => *count,
        }
    }
}

/// A train as data: its vehicles, speed, start position, hunting and crosswind. It builds the
/// [`Train`] of both solvers ([`TrainDescription::build`]); the train FMU carries it as its
/// resource (and lets parameters change it before initialisation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainDescription {
    pub spec: TrainSpec,
    /// Speed, m/s.
    pub speed_m_s: Speed,
    /// First-axle position at the start time, m.
    pub x0_m: f64,
    /// The direction of travel. Default forward (not written then, so a forward train's
    /// description, and the train FMU's GUID made from it, read as before).
    #[serde(default, skip_serializing_if = "TravelDirection::is_forward")]
    pub direction: TravelDirection,
    /// The track it runs on, 0 the first (not written when 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub track: usize,
    /// A change of speed, braking or accelerating (None: constant speed; not written then).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub change: Option<SpeedChange>,
    pub hunting: HuntingParams,
    /// A steady crosswind on the car bodies (None: still air).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crosswind: Option<Crosswind>,
}

fn is_zero(k: &usize) -> bool {
    *k == 0
}

/// A steady mean wind normal to the track (towards +y) on the car bodies
/// ([`crate::vehicle::aero`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Crosswind {
    /// Mean wind speed U, m/s.
    pub mean_speed_m_s: f64,
    /// Air density ρ, kg/m³.
    pub air_density_kg_m3: f64,
    /// The car bodies' coefficients (off the deck, and on it unless `on_deck` is given).
    pub aero: crate::vehicle::aero::VehicleAero,
    /// The car bodies' coefficients on the deck (its shielding or exposure); None: `aero`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub on_deck: Option<crate::vehicle::aero::VehicleAero>,
    /// The deck's extent `[start, end]`, m, where `on_deck` applies (None: all ground).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub deck_m: Option<[f64; 2]>,
    /// The wind is turbulent: the along-wind turbulence at each car body comes from the wind
    /// field (in the monolithic solver) or the train FMU's inputs `veh[i].u` (from the wind
    /// FMU).
    #[serde(default)]
    pub turbulent: bool,
}

impl TrainDescription {
    /// The train, with its first axle at `x0_m` at `start_time` (s): the one place a
    /// [`Train`] is built from its description, for the monolithic solver and in the train
    /// FMU.
    pub fn build(&self, start_time: f64) -> Result<Train, String> {
        if let Some(c) = &self.change {
            let v0 = self.speed_m_s.m_s();
            let reaches = match c.rate_m_s2 {
                a if a < 0.0 => c.to_speed_m_s < v0,
                a if a > 0.0 => c.to_speed_m_s > v0,
                _ => false,
            };
            if !reaches
                || !c.from_x_m.is_finite()
                || c.to_speed_m_s.is_nan()
                || c.to_speed_m_s < 0.0
            {
                return Err(format!(
                    "the speed change from {v0} m/s at {} m/s² cannot end at {} m/s",
                    c.rate_m_s2, c.to_speed_m_s
                ));
            }
        }
        if self.crosswind.is_some() && self.change.is_some() {
            return Err("a crosswind on a train that changes its speed is not supported".into());
        }
        let mut vehicles = self.spec.vehicles()?;
        if self.direction == TravelDirection::Backward {
            if self.crosswind.is_some() {
                return Err("a crosswind on a backward train is not supported".into());
            }
            // each model mirrored once, shared as before by the vehicles that share it
            let mut done: Vec<(*const LinearVehicle, Arc<LinearVehicle>)> = Vec::new();
            for v in &mut vehicles {
                let key = Arc::as_ptr(&v.model);
                v.model = match done.iter().find(|(k, _)| *k == key) {
                    Some((_, m)) => m.clone(),
                    None => {
                        let m = Arc::new(v.model.mirrored());
                        done.push((key, m.clone()));
                        m
                    }
                };
            }
        }
        let n: usize = vehicles.iter().map(|v| v.model.wheelsets.len()).sum();
        let hunting = WheelHunting::new(&self.hunting, n).map_err(|e| format!("hunting: {e}"))?;
        let speed_m_s = self.speed_m_s.m_s();
        let mut wind = None;
        if let Some(w) = &self.crosswind {
            use crate::vehicle::aero::{TrainWind, WindBody};
            let mut tw = TrainWind {
                mean_speed_m_s: w.mean_speed_m_s,
                air_density_kg_m3: w.air_density_kg_m3,
                speed_m_s,
                ground: w.aero.clone(),
                deck: w.on_deck.clone().unwrap_or_else(|| w.aero.clone()),
                deck_m: w.deck_m,
                bodies: Vec::new(),
            };
            // vehicles sharing a model and starting on the same kind of ground (the coaches
            // of a train) share its windy model
            let mut done: Vec<(*const LinearVehicle, bool, Arc<LinearVehicle>)> = Vec::new();
            for v in &mut vehicles {
                let offset = v.centre_offset_m();
                // the body's centre at the start time
                let x = self.x0_m - offset;
                let loads = tw.loads_at(x, 0.0);
                let key = (Arc::as_ptr(&v.model), tw.on_deck(x));
                tw.bodies
                    .push(WindBody::of(&v.model).map(|b| (b, offset, loads)));
                v.model = match done.iter().find(|(k, d, _)| (*k, *d) == key) {
                    Some((_, _, m)) => m.clone(),
                    None => {
                        let m = Arc::new(v.model.in_crosswind(&loads)?);
                        done.push((key.0, key.1, m.clone()));
                        m
                    }
                };
            }
            if tw.bodies.iter().any(Option::is_some) {
                wind = Some(Arc::new(tw));
            }
        }
        let run = TrainRun {
            speed_m_s,
            x0_m: self.x0_m,
            t0_s: start_time,
            direction: self.direction,
            track: self.track,
            change: self.change,
            hunting,
        };
        Ok(Train {
            wind,
            ..Train::single(vehicles, run)
        })
    }
}
