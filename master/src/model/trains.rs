//! The scenario's trains as descriptions the solvers build from: where each starts, how it
//! runs, and when the last of them has left the deck (or stopped) — checked once, with the
//! field named.
//!
//! A train enters at the deck start (forward) or end (backward) at t = 0 unless it says
//! otherwise: `start_x_m` places its first axle at t = 0; `enter_time_s` has the first axle
//! at the entry then (the train runs on the approach at its starting speed before, so
//! `x0 = entry − d v₀ t_e`); `meet_at_x_m` has its first axle pass that point at the time
//! the first train's first axle does (`x0 = x_m − d v₀ t_m`; a train meeting another keeps
//! its speed).

use crate::scenario::Scenario;
use crate::text::num;
use tbi_dynamics::bridge::ModalBridge;
use tbi_dynamics::train::{Train, TrainDescription, TrainRun, TravelDirection};
use tbi_dynamics::InputError;

/// The trains of a scenario, described and built.
pub(super) struct Trains {
    pub(super) descriptions: Vec<TrainDescription>,
    /// The trains together (monolithic solver, recorder).
    pub(super) train: Train,
    /// When the last train has left the deck or stopped, s.
    pub(super) last_leaves_s: f64,
}

/// The field of train `k` (0-based) named as the scenario wrote it.
fn field(s: &Scenario, k: usize, name: &str) -> String {
    if s.more_trains.is_empty() {
        format!("train.{name}")
    } else {
        format!("train[{}].{name}", k + 1)
    }
}

/// Describe, build and check every train of `s` on `bridge`.
pub(super) fn trains(s: &Scenario, bridge: &ModalBridge) -> Result<Trains, InputError> {
    let err = |k: usize, name: &str, v: String, why: String| {
        InputError::field(&s.origin, field(s, k, name), v, why)
    };
    if s.wind.is_some() && !s.more_trains.is_empty() {
        return Err(InputError::field(
            &s.origin,
            "wind",
            "(set)",
            "a wind with several trains is not supported; run each train alone in the wind",
        ));
    }
    let mut descriptions: Vec<TrainDescription> = Vec::new();
    let mut built: Vec<Train> = Vec::new();
    for (k, t) in s.trains().into_iter().enumerate() {
        let speed = t.speed.map(|v| v.1).unwrap_or(s.run.speed);
        let forward = t.direction.is_forward();
        let d = t.direction.sign();
        let entry = if forward {
            bridge.x_start_m
        } else {
            bridge.x_end_m
        };
        let v0 = speed.m_s();
        if let (Some(c), Some(_)) = (&t.change, &s.wind) {
            let key = if c.rate_m_s2 < 0.0 {
                "braking"
            } else {
                "accelerating"
            };
            return Err(err(
                k,
                key,
                "(set)".into(),
                "a wind on a train that changes its speed is not supported: the car bodies' wind loads take a constant speed".into(),
            ));
        }
        if let Some(c) = &t.change {
            let (key, wrong) = match c.rate_m_s2 < 0.0 {
                true => ("braking", c.to_speed_m_s >= v0),
                false => ("accelerating", c.to_speed_m_s <= v0),
            };
            if wrong {
                return Err(err(
                    k,
                    &format!("{key}.to_speed_kmh"),
                    num(c.to_speed_m_s * 3.6),
                    format!(
                        "the train starts at {} km/h, so {key} would not reach it",
                        num(v0 * 3.6)
                    ),
                ));
            }
        }
        let start = if k == 0 { s.run.start_x_m } else { t.start_x_m };
        let x0 = match (start, t.enter_time_s, t.meet_at_x_m) {
            (Some(x), _, _) => x,
            (None, Some(te), _) => entry - d * v0 * te,
            (None, None, Some(xm)) => {
                let first = built[0].run();
                if t.change.is_some() {
                    return Err(err(k, "meet_at_x_m", num(xm), "a train that meets another keeps its speed; give braking or accelerating a start_x_m or enter_time_s instead".into()));
                }
                let tm = first.time_to_travel(first.direction.sign() * (xm - first.x0_m));
                let Some(tm) = tm.filter(|&tm| tm >= 0.0) else {
                    return Err(err(
                        k,
                        "meet_at_x_m",
                        num(xm),
                        "the first train's first axle never passes there".into(),
                    ));
                };
                let x0 = xm - d * v0 * tm;
                if (forward && x0 > bridge.x_start_m) || (!forward && x0 < bridge.x_end_m) {
                    return Err(err(k, "meet_at_x_m", num(xm), format!(
                        "this train would have to be on the deck at t = 0 (its first axle at {} m) to meet there; start the first train further back or meet further from this train's entry", num(x0)
                    )));
                }
                x0
            }
            (None, None, None) => entry,
        };
        let crosses = if forward {
            x0 < bridge.x_end_m
        } else {
            x0 > bridge.x_start_m
        };
        if !crosses {
            let name = if k == 0 && s.more_trains.is_empty() {
                "run.start_x_m".to_string()
            } else {
                field(s, k, "start_x_m")
            };
            let (end, which) = if forward {
                (bridge.x_end_m, "beyond the deck end")
            } else {
                (bridge.x_start_m, "before the deck start")
            };
            return Err(InputError::field(
                &s.origin,
                name,
                num(x0),
                format!(
                    "the first axle{} would start {which} at {} m, so the train never crosses the bridge",
                    if forward { "" } else { " of a backward train" },
                    num(end)
                ),
            ));
        }
        let description = TrainDescription {
            spec: t.spec.clone(),
            speed_m_s: speed,
            x0_m: x0,
            direction: t.direction,
            track: t.track,
            change: t.change,
            hunting: t.hunting.clone(),
            crosswind: s.wind.as_ref().map(|w| tbi_dynamics::train::Crosswind {
                mean_speed_m_s: w.mean_speed_m_s,
                air_density_kg_m3: w.air_density_kg_m3,
                aero: w.vehicle.clone(),
                on_deck: w.vehicle_on_deck.clone(),
                deck_m: Some([bridge.x_start_m, bridge.x_end_m]),
                turbulent: w.is_turbulent(),
            }),
        };
        let train = (description.build(0.0))
            .map_err(|e| InputError::field(&s.origin, field(s, k, "kind"), t.kind(), &e))?;
        descriptions.push(description);
        built.push(train);
    }
    let mut last_leaves_s = 0.0_f64;
    for (k, train) in built.iter().enumerate() {
        last_leaves_s = last_leaves_s.max(leaves(s, k, train, bridge)?);
    }
    check_apart(s, &built, last_leaves_s + s.run.free_vibration_s)?;
    let train = match built.len() {
        1 => built.remove(0),
        _ => Train::together(built),
    };
    Ok(Trains {
        descriptions,
        train,
        last_leaves_s,
    })
}

/// When train `k` has left the deck (its last axle past the far end), or stopped: refused
/// when it stops on the deck without its braking saying `to_speed_kmh = 0`.
fn leaves(s: &Scenario, k: usize, train: &Train, bridge: &ModalBridge) -> Result<f64, InputError> {
    let run = train.run();
    let exit = match run.direction {
        TravelDirection::Forward => bridge.x_end_m,
        TravelDirection::Backward => bridge.x_start_m,
    };
    let s_out = (run.direction.sign() * (exit - run.x0_m) + train.length_m(0)).max(0.0);
    if let Some(t) = run.time_to_travel(s_out) {
        return Ok(t.max(0.0));
    }
    let t_stop = run.stop_time().expect("a train that never leaves stops");
    let t = s.trains()[k];
    if !t.to_speed_given {
        let x = run.x_at(0.0, t_stop);
        return Err(InputError::field(
            &s.origin,
            field(s, k, "braking.to_speed_kmh"),
            "(missing)",
            format!(
                "the braking stops the train with its first axle at {} m, before its last axle has left the deck; say to_speed_kmh = 0 to let it stop there",
                num(x)
            ),
        ));
    }
    Ok(t_stop.max(0.0))
}

/// Refuse trains on one track that run towards each other, overlap at t = 0, or run into
/// each other before `t_end` (a train catching up with a slower or braking one ahead).
fn check_apart(s: &Scenario, trains: &[Train], t_end: f64) -> Result<(), InputError> {
    let span = |t: &Train| {
        let r = t.run();
        let (a, b) = (r.x_at(0.0, 0.0), r.x_at(t.length_m(0), 0.0));
        (a.min(b), a.max(b))
    };
    for (i, a) in trains.iter().enumerate() {
        for (j, b) in trains.iter().enumerate().skip(i + 1) {
            let (ra, rb): (&TrainRun, &TrainRun) = (a.run(), b.run());
            if ra.track != rb.track {
                continue;
            }
            let say =
                |why: String| InputError::field(&s.origin, field(s, j, "track"), rb.track + 1, why);
            if ra.direction != rb.direction {
                return Err(say(format!(
                    "train {} and train {} would run towards each other on this track",
                    i + 1,
                    j + 1
                )));
            }
            let ((a0, a1), (b0, b1)) = (span(a), span(b));
            if let Some((t, x)) = (a0 > b1 || b0 > a1)
                .then(|| catches_up(a, b, t_end))
                .flatten()
            {
                return Err(say(format!(
                    "train {} and train {} would run into each other on this track at t = {} s, x = {} m",
                    i + 1,
                    j + 1,
                    num(t),
                    num(x)
                )));
            }
            if a0 <= b1 && b0 <= a1 {
                return Err(say(format!(
                    "train {} ({} to {} m) and train {} ({} to {} m) overlap on this track at t = 0",
                    i + 1,
                    num(a0),
                    num(a1),
                    j + 1,
                    num(b0),
                    num(b1)
                )));
            }
        }
    }
    Ok(())
}

/// The first time in `[0, t_end]` two trains running the same way on one track touch (the
/// front of the one behind reaches the last axle of the one ahead), and where: sampled at
/// 4000 times, then bisected. None when they stay apart.
fn catches_up(a: &Train, b: &Train, t_end: f64) -> Option<(f64, f64)> {
    let (ra, rb) = (a.run(), b.run());
    let d = ra.direction.sign();
    // which is ahead at t = 0 along the direction of travel
    let (lead, lead_len, follow) = match d * (ra.x_at(0.0, 0.0) - rb.x_at(0.0, 0.0)) > 0.0 {
        true => (ra, a.length_m(0), rb),
        false => (rb, b.length_m(0), ra),
    };
    // > 0 while the follower's front is behind the leader's last axle
    let gap = |t: f64| d * (lead.x_at(lead_len, t) - follow.x_at(0.0, t));
    let n = 4000;
    let mut before = 0.0;
    for k in 1..=n {
        let t = t_end * k as f64 / n as f64;
        if gap(t) <= 0.0 {
            let hit = first_time(|t| gap(t) <= 0.0, before, t);
            return Some((hit, follow.x_at(0.0, hit)));
        }
        before = t;
    }
    None
}

/// The first time in `[lo, hi]` at which `reached` holds, `reached` false at `lo`, true at
/// `hi` and staying true once it holds (a gap between two trains closing): bisected to the
/// resolution of f64.
pub(crate) fn first_time(reached: impl Fn(f64) -> bool, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if reached(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}
