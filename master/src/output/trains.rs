//! The part of `summary.json` a run of several trains adds: each train's run and results
//! (`trains[]`), and where and when trains running towards each other meet (`meetings[]`).
//! A run of one train has neither (its results are the summary's own).

use crate::model::Model;
use serde::{Deserialize, Serialize};
use tbi_dynamics::response::{Recorder, SafetyMax};
use tbi_dynamics::train::{SpeedChange, TrainRun, TravelDirection};

/// One train of several: how it ran and its results.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainResult {
    /// Its number, 1-based, as in the scenario and the history's `train<k>.` columns.
    pub train: usize,
    /// The track it ran on, 1-based.
    pub track: usize,
    /// `"forward"` (+x) or `"backward"` (−x).
    pub direction: TravelDirection,
    /// Its speed at the start, km/h.
    pub speed_kmh: f64,
    /// Its braking or accelerating (rate m/s², signed; final speed m/s), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_change: Option<SpeedChange>,
    pub vehicles: usize,
    pub wheelsets: usize,
    /// First to last axle, m.
    pub length_m: f64,
    /// When its first axle reaches the deck, s (None: never, or before the start).
    pub enters_deck_s: Option<f64>,
    /// When its last axle has left the deck, s (None: it stops before).
    pub leaves_deck_s: Option<f64>,
    /// Car-body maxima, m/s², and the largest Sperling indices (None: moving forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub car_bodies: Option<CarBodies>,
    /// Wheel–rail safety maxima (None: moving forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub safety: Option<SafetyMax>,
}

/// A train's car-body maxima.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CarBodies {
    pub vertical_acceleration_max_m_s2: f64,
    pub lateral_acceleration_max_m_s2: f64,
    /// The largest Sperling index of its car bodies, vertical and lateral.
    pub sperling_vertical_max: Option<f64>,
    pub sperling_lateral_max: Option<f64>,
}

/// Two trains running towards each other: when and where their first axles pass.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Meeting {
    /// The two trains, 1-based.
    pub trains: [usize; 2],
    pub time_s: f64,
    pub x_m: f64,
}

/// The time `run`'s first axle has travelled `s` (None: before the start or never).
fn time_at(run: &TrainRun, s: f64) -> Option<f64> {
    if s < 0.0 {
        return None;
    }
    run.time_to_travel(s).filter(|&t| t >= 0.0)
}

/// Each train's run and results (empty for one train).
pub fn results<W: std::io::Write>(model: &Model, rec: &Recorder<W>) -> Vec<TrainResult> {
    if model.trains.len() < 2 {
        return Vec::new();
    }
    let layout = &rec.layout;
    let of_vehicle = layout.numbered(0);
    let (b, train) = (&model.bridge, &model.train);
    let max_of = |k: usize, v: &[Option<f64>]| {
        (of_vehicle.iter().zip(v))
            .filter(|(a, _)| a.0 == k)
            .filter_map(|(_, s)| *s)
            .reduce(f64::max)
    };
    (train.runs.iter().enumerate())
        .map(|(k, run)| {
            let d = &model.trains[k];
            let length = train.length_m(k);
            let (entry, exit) = match run.direction {
                TravelDirection::Forward => (b.x_start_m, b.x_end_m),
                TravelDirection::Backward => (b.x_end_m, b.x_start_m),
            };
            let sign = run.direction.sign();
            let has_bodies = (of_vehicle.iter().zip(&layout.vehicles))
                .any(|(a, has)| a.0 == k && (has[0] || has[1]));
            let m = rec.by_train.get(k);
            let moving_forces = matches!(d.spec, tbi_dynamics::train::TrainSpec::MovingForce(_));
            TrainResult {
                train: k + 1,
                track: run.track + 1,
                direction: run.direction,
                speed_kmh: run.speed_m_s * 3.6,
                speed_change: run.change,
                vehicles: d.spec.n_vehicles(),
                wheelsets: d.spec.n_wheelsets(),
                length_m: length,
                enters_deck_s: time_at(run, sign * (entry - run.x0_m)),
                leaves_deck_s: time_at(run, sign * (exit - run.x0_m) + length),
                car_bodies: (has_bodies).then(|| CarBodies {
                    vertical_acceleration_max_m_s2: m
                        .map_or(0.0, |m| m.vertical_acceleration_max_m_s2),
                    lateral_acceleration_max_m_s2: m
                        .map_or(0.0, |m| m.lateral_acceleration_max_m_s2),
                    sperling_vertical_max: max_of(k, &rec.vehicles.sperling_vertical),
                    sperling_lateral_max: max_of(k, &rec.vehicles.sperling_lateral),
                }),
                safety: (!moving_forces).then(|| m.map(|m| m.safety.clone()).unwrap_or_default()),
            }
        })
        .collect()
}

/// Where and when the first axles of trains running towards each other pass, on the deck
/// within the run (by bisection of the gap between them, which closes monotonically).
pub fn meetings(model: &Model) -> Vec<Meeting> {
    let runs = &model.train.runs;
    let t_end = model.t_end();
    let mut out = Vec::new();
    for (i, a) in runs.iter().enumerate() {
        for (j, b) in runs.iter().enumerate().skip(i + 1) {
            if a.direction == b.direction {
                continue;
            }
            // the forward train's first axle ahead of the backward one's: gap > 0
            let gap = |t: f64| a.direction.sign() * (a.x_at(0.0, t) - b.x_at(0.0, t));
            if gap(0.0) > 0.0 || gap(t_end) < 0.0 {
                continue;
            }
            let hi = crate::model::first_time(|t| gap(t) >= 0.0, 0.0, t_end);
            let x = a.x_at(0.0, hi);
            if model.bridge.on_deck(x) {
                out.push(Meeting {
                    trains: [i + 1, j + 1],
                    time_s: hi,
                    x_m: x,
                });
            }
        }
    }
    out
}
