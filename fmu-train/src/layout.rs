//! The train FMU's variables, described once: value references, names, units,
//! descriptions, start values and output-buffer slots, for the model, the master and the
//! `modelDescription.xml` writer.
//!
//! | block | causality | channels | value references |
//! |---|---|---|---|
//! | `ws[i]` | input | [`RAIL_CHANNELS`] (rail motion under wheelset i) | from 0 |
//! | `ws[i]` | output | [`WHEEL_OUT`]: [`WHEEL_CHANNELS`] then [`LOAD_CHANNELS`] | after the inputs |
//! | `veh[k]` | output | [`VEHICLE_CHANNELS`] (car-body accelerations) | after the wheelsets |
//! | parameters | parameter | [`parameters`]: `speed`, `x0`, `hunting.*`, `coach.*` | from [`PARAM_BASE`] |

use fmu_contract::{
    Block, Blocks, Causality, Channel, Var, BODY_POSITION_CHANNELS, RAIL_CHANNELS, WHEEL_CHANNELS,
    WIND_CHANNELS,
};
use tbi_dynamics::train::{TrainDescription, TrainSpec};

/// The along-wind turbulence at a car body, an input from the wind FMU (the vertical one is
/// not applied to the bodies).
pub const BODY_WIND_CHANNELS: [Channel; 1] = [WIND_CHANNELS[0]];

/// `<fmiModelDescription description>` of the train FMU.
pub const DESCRIPTION: &str = "Train of linear vehicles (moving forces, sprung masses or 27-DOF coaches): rail motion in, wheel forces out";

/// Per-wheelset outputs beyond what the bridge needs.
pub const LOAD_CHANNELS: [Channel; 4] = [
    Channel {
        name: "P_left",
        unit: "N",
        description: "left (-y) wheel vertical load",
    },
    Channel {
        name: "P_right",
        unit: "N",
        description: "right (+y) wheel vertical load",
    },
    Channel {
        name: "derail",
        unit: "1",
        description: "derail factor Q/P of the wheelset",
    },
    Channel {
        name: "offload",
        unit: "1",
        description: "offload factor (P0 - P)/P0 of the wheelset",
    },
];

/// The per-wheelset outputs: the bridge's inputs, then the wheel loads and factors.
pub const WHEEL_OUT: [Channel; 9] = [
    WHEEL_CHANNELS[0],
    WHEEL_CHANNELS[1],
    WHEEL_CHANNELS[2],
    WHEEL_CHANNELS[3],
    WHEEL_CHANNELS[4],
    LOAD_CHANNELS[0],
    LOAD_CHANNELS[1],
    LOAD_CHANNELS[2],
    LOAD_CHANNELS[3],
];

/// Car-body accelerations per vehicle (0 where the vehicle has no such DOF).
pub const VEHICLE_CHANNELS: [Channel; 2] = [
    Channel {
        name: "a_y",
        unit: "m/s2",
        description: "car-body lateral acceleration",
    },
    Channel {
        name: "a_z",
        unit: "m/s2",
        description: "car-body vertical acceleration",
    },
];

/// First parameter value reference.
pub const PARAM_BASE: u32 = 1_000_000;

/// One Real parameter: name, unit, description and its value in the resources.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    pub name: String,
    pub unit: &'static str,
    pub description: String,
    pub value: f64,
}

/// The train FMU's parameters in value-reference order from [`PARAM_BASE`]: `speed`,
/// `x0`, `hunting.amplitude`, `hunting.wavelength`, `hunting.seed`, then `coach.<field>`
/// for coach trains (every Table 1 property).
pub fn parameters(res: &TrainDescription) -> Vec<Parameter> {
    let p = |name: &str, unit, description: &str, value| Parameter {
        name: name.to_owned(),
        unit,
        description: description.to_owned(),
        value,
    };
    let mut list = vec![
        p("speed", "m/s", "train speed", res.speed_m_s.m_s()),
        p(
            "x0",
            "m",
            "position of the first axle at the start time",
            res.x0_m,
        ),
        p(
            "hunting.amplitude",
            "m",
            "wheel hunting amplitude A_h (0 = off)",
            res.hunting.amplitude_m,
        ),
        p(
            "hunting.wavelength",
            "m",
            "wheel hunting wavelength L_h",
            res.hunting.wavelength_m,
        ),
        p(
            "hunting.seed",
            "1",
            "seed of the per-wheelset hunting phases (integer value)",
            res.hunting.seed as f64,
        ),
    ];
    if let TrainSpec::Coaches { params, .. } = &res.spec {
        for (name, value) in params.fields() {
            list.push(Parameter {
                name: format!("coach.{name}"),
                unit: unit_of(name),
                description: format!("coach property {name} (Table 1)"),
                value,
            });
        }
    }
    list
}

/// The unit of a Table 1 field, from its suffix.
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

/// A train FMU variable, decoded from its value reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrainVar {
    /// Channel `k` of [`RAIL_CHANNELS`] of wheelset `w` (0-based), an input.
    Rail { w: usize, k: usize },
    /// The along-wind turbulence at car body `i` (0-based), an input.
    Wind(usize),
    /// An output, by its slot in the output buffer.
    Output(usize),
    /// The j-th entry of [`parameters`] (not range-checked here).
    Parameter(usize),
}

/// The train FMU's blocks for a number of wheelsets and vehicles.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TrainLayout {
    pub rail_in: Block,
    pub wheel_out: Block,
    pub vehicle_out: Block,
    /// Car-body positions (to the wind FMU) and the turbulence there (from it); only in a
    /// turbulent wind.
    pub body_x_out: Block,
    pub wind_in: Block,
    n_outputs: usize,
    /// `decode` by value reference.
    table: Vec<Option<TrainVar>>,
}

impl TrainLayout {
    pub fn new(n_wheelsets: usize, n_vehicles: usize) -> TrainLayout {
        Self::with_wind(n_wheelsets, n_vehicles, false)
    }

    /// With `turbulent`, the car bodies exchange positions and turbulence with a wind FMU.
    pub fn with_wind(n_wheelsets: usize, n_vehicles: usize, turbulent: bool) -> TrainLayout {
        let mut b = Blocks::default();
        let rail_in = b.input("ws", &RAIL_CHANNELS, n_wheelsets);
        let wheel_out = b.output("ws", &WHEEL_OUT, n_wheelsets);
        let vehicle_out = b.output("veh", &VEHICLE_CHANNELS, n_vehicles);
        let n_bodies = if turbulent { n_vehicles } else { 0 };
        let body_x_out = b.output("veh", &BODY_POSITION_CHANNELS, n_bodies);
        let wind_in = b.input("veh", &BODY_WIND_CHANNELS, n_bodies);
        let mut l = TrainLayout {
            rail_in,
            wheel_out,
            vehicle_out,
            body_x_out,
            wind_in,
            n_outputs: b.n_slots(),
            table: Vec::new(),
        };
        l.table = Block::table(
            &[
                l.rail_in,
                l.wheel_out,
                l.vehicle_out,
                l.body_x_out,
                l.wind_in,
            ],
            |vr| l.decode_blocks(vr),
        );
        l
    }

    /// The layout of the FMU with these resources.
    pub fn of(res: &TrainDescription) -> TrainLayout {
        let turbulent = res.crosswind.as_ref().is_some_and(|w| w.turbulent);
        TrainLayout::with_wind(res.spec.n_wheelsets(), res.spec.n_vehicles(), turbulent)
    }

    pub fn n_wheelsets(&self) -> usize {
        self.rail_in.count
    }

    pub fn n_vehicles(&self) -> usize {
        self.vehicle_out.count
    }

    /// Size of the output buffer.
    pub fn n_outputs(&self) -> usize {
        self.n_outputs
    }

    /// The variable of `vr` (one table load).
    pub fn decode(&self, vr: u32) -> Option<TrainVar> {
        if vr >= PARAM_BASE {
            return Some(TrainVar::Parameter((vr - PARAM_BASE) as usize));
        }
        self.table.get(vr as usize).copied().flatten()
    }

    fn decode_blocks(&self, vr: u32) -> Option<TrainVar> {
        if let Some((w, k)) = self.rail_in.decode(vr) {
            return Some(TrainVar::Rail { w, k });
        }
        if let Some((i, _)) = self.wind_in.decode(vr) {
            return Some(TrainVar::Wind(i));
        }
        Block::slot_of(&[self.wheel_out, self.vehicle_out, self.body_x_out], vr)
            .map(TrainVar::Output)
    }

    /// All variables in value-reference order (what `modelDescription.xml` lists).
    pub fn variables(&self, res: &TrainDescription) -> Vec<Var> {
        let mut v = self.rail_in.variables(
            |w, c| {
                format!(
                    "{} under wheelset {} (deck plus irregularity)",
                    c.description,
                    w + 1
                )
            },
            |_, _| Some(0.0),
        );
        v.extend(self.wheel_out.variables(
            |w, c| format!("{}, wheelset {}", c.description, w + 1),
            |_, _| None,
        ));
        v.extend(self.vehicle_out.variables(
            |i, c| format!("{}, vehicle {} (0 if not modelled)", c.description, i + 1),
            |_, _| None,
        ));
        v.extend(self.body_x_out.variables(
            |i, c| format!("{}, vehicle {}", c.description, i + 1),
            |_, _| None,
        ));
        v.extend(self.wind_in.variables(
            |i, c| format!("{} at the car body of vehicle {}", c.description, i + 1),
            |_, _| Some(0.0),
        ));
        for (j, p) in parameters(res).into_iter().enumerate() {
            v.push(Var {
                vr: PARAM_BASE + j as u32,
                name: p.name,
                causality: Causality::Parameter,
                unit: p.unit.to_owned(),
                description: p.description,
                start: Some(p.value),
            });
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variable_decodes_to_itself_and_outputs_fill_the_buffer() {
        let l = TrainLayout::with_wind(7, 2, true);
        assert_eq!(l.n_outputs(), 9 * 7 + 2 * 2 + 2);
        let mut slots = Vec::new();
        let blocks = [
            l.rail_in,
            l.wheel_out,
            l.vehicle_out,
            l.body_x_out,
            l.wind_in,
        ];
        for (i, b) in blocks.iter().enumerate() {
            for n in 0..b.count {
                for k in 0..b.width() {
                    match l.decode(b.vr(n, k)) {
                        Some(TrainVar::Rail { w, k: kk }) => assert_eq!((i, w, kk), (0, n, k)),
                        Some(TrainVar::Wind(j)) => assert_eq!((i, j), (4, n)),
                        Some(TrainVar::Output(s)) => slots.push(s),
                        other => panic!("{} decodes to {other:?}", b.name(n, k)),
                    }
                }
            }
        }
        assert_eq!(slots, (0..l.n_outputs()).collect::<Vec<_>>());
        assert_eq!(l.decode((18 * 7 + 2 * 2 + 2 + 2) as u32), None);
        assert_eq!(l.wind_in.name(1, 0), "veh[2].u");
        assert_eq!(TrainLayout::new(7, 2).n_outputs(), 9 * 7 + 2 * 2);
        assert_eq!(l.decode(PARAM_BASE + 4), Some(TrainVar::Parameter(4)));
        assert_eq!(WHEEL_OUT[5].name, "P_left");
    }
}
