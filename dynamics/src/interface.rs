//! The co-simulation interface: what the bridge and train FMUs carry in their resources and
//! which scalar variables they expose, in one place for the FMUs and the master.
//!
//! Naming pattern (FMI "structured" convention, 1-based indices, SI units):
//!
//! | FMU | causality | names |
//! |---|---|---|
//! | bridge | input | `ws[i].x` (m), `ws[i].vx` (m/s), `ws[i].F_y` (N), `ws[i].M_x` (N·m), `ws[i].F_z` (N) — position, speed and the force of wheelset i on the rail |
//! | bridge | output | `ws[i].y`, `ws[i].theta`, `ws[i].z` (m, rad, m), `…_d` (velocities), `…_dd` (accelerations) — rail motion under wheelset i, deck plus irregularity |
//! | bridge | output | `probe[k].y`, `probe[k].z`, `probe[k].theta`, `probe[k].y_dd`, `probe[k].z_dd` — deck response at probe k |
//! | train | input | `ws[i].y` … `ws[i].z_dd` — the rail motion above |
//! | train | output | `ws[i].x`, `ws[i].vx`, `ws[i].F_y`, `ws[i].M_x`, `ws[i].F_z`, `ws[i].P_left`, `ws[i].P_right` (N), `ws[i].derail`, `ws[i].offload` (–) |
//! | train | output | `veh[k].a_y`, `veh[k].a_z` (m/s²) — car-body accelerations |
//! | train | parameter | `speed` (m/s), `x0` (m), `hunting.amplitude` (m), `hunting.wavelength` (m), `hunting.seed`, `coach.<field>` |
//!
//! Signs: forces and moments act on the rail (deck); y right, z down, θ right side down.
//! **Input timing**: inputs set before `fmi2DoStep(t, h)` are the values at `t + h` (what an
//! implicit iteration needs); a plain fixed-step master therefore sees a one-step lag.

use crate::bridge::ModalBridge;
use crate::train::{Train, TrainVehicle};
use crate::vehicle::coach::CoachParams;
use crate::vehicle::simple::{moving_force, sprung_mass, MovingForceAxle, SprungMassAxle};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use tbi_track::{HuntingParams, WheelHunting};

/// Model identifier (and shared-object stem) of the bridge FMU.
pub const BRIDGE_ID: &str = "bridge";
/// Model identifier (and shared-object stem) of the train FMU.
pub const TRAIN_ID: &str = "train";
/// Resource file of the bridge FMU (JSON of [`BridgeResources`]).
pub const BRIDGE_RESOURCE: &str = "bridge.json";
/// Resource file with the track irregularity record (optional).
pub const TRACK_RESOURCE: &str = "track.csv";
/// Resource file of the train FMU (JSON of [`TrainResources`]).
pub const TRAIN_RESOURCE: &str = "train.json";

/// Rail-motion channel names per wheelset, in value-reference order.
pub const RAIL_CHANNELS: [(&str, &str, &str); 9] = [
    ("y", "m", "lateral rail displacement"),
    ("theta", "rad", "rail roll (cross-level) angle"),
    ("z", "m", "vertical rail displacement (+ down)"),
    ("y_d", "m/s", "lateral rail velocity"),
    ("theta_d", "rad/s", "rail roll rate"),
    ("z_d", "m/s", "vertical rail velocity"),
    ("y_dd", "m/s2", "lateral rail acceleration"),
    ("theta_dd", "rad/s2", "rail roll acceleration"),
    ("z_dd", "m/s2", "vertical rail acceleration"),
];

/// Wheelset channels the train sends to the bridge, in value-reference order.
pub const WHEEL_CHANNELS: [(&str, &str, &str); 5] = [
    ("x", "m", "wheelset position along the track"),
    ("vx", "m/s", "wheelset speed along the track"),
    ("F_y", "N", "lateral force of the wheelset on the rail (+y)"),
    (
        "M_x",
        "N.m",
        "roll moment of the wheelset on the rail (about +x)",
    ),
    (
        "F_z",
        "N",
        "vertical force of the wheelset on the rail (+ down)",
    ),
];

/// Extra per-wheelset outputs of the train.
pub const LOAD_CHANNELS: [(&str, &str, &str); 4] = [
    ("P_left", "N", "left (-y) wheel vertical load"),
    ("P_right", "N", "right (+y) wheel vertical load"),
    ("derail", "1", "derail factor Q/P of the wheelset"),
    ("offload", "1", "offload factor (P0 - P)/P0 of the wheelset"),
];

/// Probe channels of the bridge.
pub const PROBE_CHANNELS: [(&str, &str, &str); 5] = [
    ("y", "m", "deck lateral displacement"),
    ("z", "m", "deck vertical displacement (+ down)"),
    ("theta", "rad", "deck torsion"),
    ("y_dd", "m/s2", "deck lateral acceleration"),
    ("z_dd", "m/s2", "deck vertical acceleration"),
];

/// FMI causality of a variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    Input,
    Output,
}

/// One scalar Real variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Var {
    pub vr: u32,
    pub name: String,
    pub causality: Causality,
    pub unit: String,
    pub description: String,
    /// Start value (inputs and parameters).
    pub start: Option<f64>,
}

/// A probe: name (for descriptions) and position, m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProbeSpec {
    pub name: String,
    pub x_m: f64,
}

/// Everything the bridge FMU reads from its resources.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BridgeResources {
    pub modal: ModalBridge,
    pub probes: Vec<ProbeSpec>,
    pub n_wheelsets: usize,
    /// Whether `track.csv` holds an irregularity record (else the track is smooth).
    pub has_track_record: bool,
}

/// A bridge FMU variable, decoded from its value reference (0-based indices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BridgeVar {
    /// `ws[w].<WHEEL_CHANNELS[k]>` (input).
    Wheel { w: usize, k: usize },
    /// `ws[w].<RAIL_CHANNELS[k]>` (output).
    Rail { w: usize, k: usize },
    /// `probe[p].<PROBE_CHANNELS[k]>` (output).
    Probe { p: usize, k: usize },
}

/// Value references of the bridge FMU.
pub mod bridge_vr {
    use super::BridgeVar;

    /// The variable behind `vr` for `nw` wheelsets and `np` probes (inverse of the functions
    /// below).
    pub fn decode(nw: usize, np: usize, vr: u32) -> Option<BridgeVar> {
        let v = vr as usize;
        if v < 5 * nw {
            Some(BridgeVar::Wheel { w: v / 5, k: v % 5 })
        } else if v < 14 * nw {
            let o = v - 5 * nw;
            Some(BridgeVar::Rail { w: o / 9, k: o % 9 })
        } else if v < 14 * nw + 5 * np {
            let o = v - 14 * nw;
            Some(BridgeVar::Probe { p: o / 5, k: o % 5 })
        } else {
            None
        }
    }

    /// `ws[w].<WHEEL_CHANNELS[k]>` (0-based w, k).
    pub fn wheel_input(w: usize, k: usize) -> u32 {
        (5 * w + k) as u32
    }
    /// `ws[w].<RAIL_CHANNELS[k]>`.
    pub fn rail_output(nw: usize, w: usize, k: usize) -> u32 {
        (5 * nw + 9 * w + k) as u32
    }
    /// `probe[p].<PROBE_CHANNELS[k]>`.
    pub fn probe_output(nw: usize, p: usize, k: usize) -> u32 {
        (14 * nw + 5 * p + k) as u32
    }
}

impl BridgeResources {
    /// All variables of the bridge FMU, in value-reference order.
    pub fn variables(&self) -> Vec<Var> {
        let nw = self.n_wheelsets;
        let mut v = Vec::new();
        for w in 0..nw {
            for (k, (ch, unit, desc)) in WHEEL_CHANNELS.iter().enumerate() {
                v.push(Var {
                    vr: bridge_vr::wheel_input(w, k),
                    name: format!("ws[{}].{ch}", w + 1),
                    causality: Causality::Input,
                    unit: unit.to_string(),
                    description: format!("{desc}, wheelset {}", w + 1),
                    start: Some(if k == 0 { -1.0e6 } else { 0.0 }),
                });
            }
        }
        for w in 0..nw {
            for (k, (ch, unit, desc)) in RAIL_CHANNELS.iter().enumerate() {
                v.push(Var {
                    vr: bridge_vr::rail_output(nw, w, k),
                    name: format!("ws[{}].{ch}", w + 1),
                    causality: Causality::Output,
                    unit: unit.to_string(),
                    description: format!(
                        "{desc} under wheelset {} (deck plus irregularity)",
                        w + 1
                    ),
                    start: None,
                });
            }
        }
        for (p, probe) in self.probes.iter().enumerate() {
            for (k, (ch, unit, desc)) in PROBE_CHANNELS.iter().enumerate() {
                v.push(Var {
                    vr: bridge_vr::probe_output(nw, p, k),
                    name: format!("probe[{}].{ch}", p + 1),
                    causality: Causality::Output,
                    unit: unit.to_string(),
                    description: format!("{desc} at probe {} (x = {} m)", probe.name, probe.x_m),
                    start: None,
                });
            }
        }
        v
    }
}

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
                })
                .collect(),
            TrainSpec::SprungMass(list) => list
                .iter()
                .map(|a| {
                    Ok(TrainVehicle {
                        model: Arc::new(sprung_mass(a)?),
                        offset_m: a.offset_m,
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

    /// Build the train.
    pub fn build(
        &self,
        speed_m_s: f64,
        x0_m: f64,
        hunting: &HuntingParams,
    ) -> Result<Train, String> {
        let vehicles = self.vehicles()?;
        let n: usize = vehicles.iter().map(|v| v.model.wheelsets.len()).sum();
        let hunting = WheelHunting::new(hunting, n).map_err(|e| format!("hunting: {e}"))?;
        Ok(Train {
            vehicles,
            speed_m_s,
            x0_m,
            hunting,
        })
    }
}

/// Everything the train FMU reads from its resources (all of it can be changed through
/// parameters before initialisation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrainResources {
    pub spec: TrainSpec,
    /// Speed, m/s.
    pub speed_m_s: f64,
    /// First-axle position at t = 0, m.
    pub x0_m: f64,
    pub hunting: HuntingParams,
}

/// A train FMU variable, decoded from its value reference (0-based indices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrainVar {
    /// `ws[w].<RAIL_CHANNELS[k]>` (input).
    Rail { w: usize, k: usize },
    /// `ws[w].<WHEEL_CHANNELS or LOAD_CHANNELS[k]>` (output, k < 9).
    Wheel { w: usize, k: usize },
    /// `veh[i].a_y` (k = 0) or `veh[i].a_z` (k = 1) (output).
    Vehicle { i: usize, k: usize },
    /// The j-th entry of [`train_parameters`].
    Parameter(usize),
}

/// Value references of the train FMU.
pub mod train_vr {
    use super::TrainVar;

    /// The variable behind `vr` for `nw` wheelsets and `nv` vehicles (inverse of the functions
    /// below; parameter indices are not range-checked here).
    pub fn decode(nw: usize, nv: usize, vr: u32) -> Option<TrainVar> {
        if vr >= PARAM_BASE {
            return Some(TrainVar::Parameter((vr - PARAM_BASE) as usize));
        }
        let v = vr as usize;
        if v < 9 * nw {
            Some(TrainVar::Rail { w: v / 9, k: v % 9 })
        } else if v < 18 * nw {
            let o = v - 9 * nw;
            Some(TrainVar::Wheel { w: o / 9, k: o % 9 })
        } else if v < 18 * nw + 2 * nv {
            let o = v - 18 * nw;
            Some(TrainVar::Vehicle { i: o / 2, k: o % 2 })
        } else {
            None
        }
    }

    /// `ws[w].<RAIL_CHANNELS[k]>` inputs.
    pub fn rail_input(w: usize, k: usize) -> u32 {
        (9 * w + k) as u32
    }
    /// `ws[w].<WHEEL_CHANNELS[k]>` (k < 5) or `<LOAD_CHANNELS[k-5]>` outputs.
    pub fn wheel_output(nw: usize, w: usize, k: usize) -> u32 {
        (9 * nw + 9 * w + k) as u32
    }
    /// `veh[i].a_y` (k = 0) / `veh[i].a_z` (k = 1).
    pub fn vehicle_output(nw: usize, i: usize, k: usize) -> u32 {
        (18 * nw + 2 * i + k) as u32
    }
    /// First parameter value reference.
    pub const PARAM_BASE: u32 = 1_000_000;
}

/// Names of the train FMU's Real parameters in value-reference order from
/// [`train_vr::PARAM_BASE`]: `speed`, `x0`, `hunting.amplitude`, `hunting.wavelength`,
/// `hunting.seed`, then `coach.<field>` for coach trains.
pub fn train_parameters(res: &TrainResources) -> Vec<(String, String, String, f64)> {
    let mut p = vec![
        (
            "speed".to_string(),
            "m/s".to_string(),
            "train speed".to_string(),
            res.speed_m_s,
        ),
        (
            "x0".to_string(),
            "m".to_string(),
            "position of the first axle at the start time".to_string(),
            res.x0_m,
        ),
        (
            "hunting.amplitude".to_string(),
            "m".to_string(),
            "wheel hunting amplitude A_h (0 = off)".to_string(),
            res.hunting.amplitude_m,
        ),
        (
            "hunting.wavelength".to_string(),
            "m".to_string(),
            "wheel hunting wavelength L_h".to_string(),
            res.hunting.wavelength_m,
        ),
        (
            "hunting.seed".to_string(),
            "1".to_string(),
            "seed of the per-wheelset hunting phases (integer value)".to_string(),
            res.hunting.seed as f64,
        ),
    ];
    if let TrainSpec::Coaches { params, .. } = &res.spec {
        for (name, value) in params.fields() {
            let unit = unit_of(name);
            p.push((
                format!("coach.{name}"),
                unit.to_string(),
                format!("coach property {name} (Table 1)"),
                value,
            ));
        }
    }
    p
}

fn unit_of(field: &str) -> &'static str {
    if field.ends_with("_kg_m2") {
        "kg.m2"
    } else if field.ends_with("_kg") {
        "kg"
    } else if field.ends_with("_n_m") {
        "N/m"
    } else if field.ends_with("_ns_m") {
        "N.s/m"
    } else {
        "m"
    }
}

impl TrainResources {
    /// All variables of the train FMU.
    pub fn variables(&self) -> Vec<Var> {
        let nw = self.spec.n_wheelsets();
        let mut v = Vec::new();
        for w in 0..nw {
            for (k, (ch, unit, desc)) in RAIL_CHANNELS.iter().enumerate() {
                v.push(Var {
                    vr: train_vr::rail_input(w, k),
                    name: format!("ws[{}].{ch}", w + 1),
                    causality: Causality::Input,
                    unit: unit.to_string(),
                    description: format!(
                        "{desc} under wheelset {} (deck plus irregularity)",
                        w + 1
                    ),
                    start: Some(0.0),
                });
            }
        }
        for w in 0..nw {
            let chans = WHEEL_CHANNELS.iter().chain(LOAD_CHANNELS.iter());
            for (k, (ch, unit, desc)) in chans.enumerate() {
                v.push(Var {
                    vr: train_vr::wheel_output(nw, w, k),
                    name: format!("ws[{}].{ch}", w + 1),
                    causality: Causality::Output,
                    unit: unit.to_string(),
                    description: format!("{desc}, wheelset {}", w + 1),
                    start: None,
                });
            }
        }
        for i in 0..self.spec.n_vehicles() {
            for (k, (ch, desc)) in [
                ("a_y", "car-body lateral acceleration"),
                ("a_z", "car-body vertical acceleration"),
            ]
            .iter()
            .enumerate()
            {
                v.push(Var {
                    vr: train_vr::vehicle_output(nw, i, k),
                    name: format!("veh[{}].{ch}", i + 1),
                    causality: Causality::Output,
                    unit: "m/s2".into(),
                    description: format!("{desc}, vehicle {} (0 if not modelled)", i + 1),
                    start: None,
                });
            }
        }
        for (j, (name, unit, desc, value)) in train_parameters(self).into_iter().enumerate() {
            v.push(Var {
                vr: train_vr::PARAM_BASE + j as u32,
                name,
                causality: Causality::Parameter,
                unit,
                description: desc,
                start: Some(value),
            });
        }
        v
    }
}

/// Build identifier that goes into the FMUs' GUIDs (with the bytes of their resources).
pub const BUILD_ID: &str = concat!("tbi-", env!("CARGO_PKG_VERSION"));

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decode_inverts_the_layout() {
        let (nw, np, nv) = (7, 3, 2);
        for w in 0..nw {
            for k in 0..5 {
                assert_eq!(
                    bridge_vr::decode(nw, np, bridge_vr::wheel_input(w, k)),
                    Some(BridgeVar::Wheel { w, k })
                );
            }
            for k in 0..9 {
                assert_eq!(
                    bridge_vr::decode(nw, np, bridge_vr::rail_output(nw, w, k)),
                    Some(BridgeVar::Rail { w, k })
                );
                assert_eq!(
                    train_vr::decode(nw, nv, train_vr::rail_input(w, k)),
                    Some(TrainVar::Rail { w, k })
                );
                assert_eq!(
                    train_vr::decode(nw, nv, train_vr::wheel_output(nw, w, k)),
                    Some(TrainVar::Wheel { w, k })
                );
            }
        }
        for p in 0..np {
            for k in 0..5 {
                assert_eq!(
                    bridge_vr::decode(nw, np, bridge_vr::probe_output(nw, p, k)),
                    Some(BridgeVar::Probe { p, k })
                );
            }
        }
        for i in 0..nv {
            for k in 0..2 {
                assert_eq!(
                    train_vr::decode(nw, nv, train_vr::vehicle_output(nw, i, k)),
                    Some(TrainVar::Vehicle { i, k })
                );
            }
        }
        assert_eq!(bridge_vr::decode(nw, np, (14 * nw + 5 * np) as u32), None);
        assert_eq!(train_vr::decode(nw, nv, (18 * nw + 2 * nv) as u32), None);
        assert_eq!(
            train_vr::decode(nw, nv, train_vr::PARAM_BASE + 4),
            Some(TrainVar::Parameter(4))
        );
    }
}
