//! The bridge FMU's variables, described once: value references, names, units,
//! descriptions, start values and output-buffer slots, for the model, the master and the
//! `modelDescription.xml` writer.
//!
//! | block | causality | channels | value references |
//! |---|---|---|---|
//! | `ws[i]` | input | [`WHEEL_CHANNELS`] (position, speed, force of wheelset i on the rail) | from 0 |
//! | `ws[i]` | output | [`RAIL_CHANNELS`] (rail motion under wheelset i, deck plus irregularity) | after the inputs |
//! | `probe[k]` | output | [`PROBE_CHANNELS`] (deck response at probe k) | after the rail motion |
//! | `deck[j]` | input | [`WIND_CHANNELS`] (turbulence at deck point j, from the wind FMU; only with `[wind] turbulence`) | after the probes |
//! | `mode[n].damping_ratio` | parameter (fixed) | the damping ratio of mode n, – | from [`PARAM_BASE`] |

use crate::BridgeResources;
use fmu_contract::{Block, Blocks, Channel, Var, RAIL_CHANNELS, WHEEL_CHANNELS, WIND_CHANNELS};
use tbi_dynamics::solver::partitioned::ProbeValues;

/// `<fmiModelDescription description>` of the bridge FMU.
pub const DESCRIPTION: &str =
    "Bridge with its track (modal model, Xia, Xu & Chan 2000): wheelset forces in, rail motion out";

/// First parameter value reference (`mode[1].damping_ratio`).
pub const PARAM_BASE: u32 = 1_000_000;

/// Start of `ws[i].x`, m: a wheelset that has not arrived is far before the deck.
pub const PARKED_X: f64 = -1.0e6;

/// Deck response channels at a probe, in value-reference order.
pub const PROBE_CHANNELS: [Channel; 5] = [
    Channel {
        name: "y",
        unit: "m",
        description: "deck lateral displacement",
    },
    Channel {
        name: "z",
        unit: "m",
        description: "deck vertical displacement (+ down)",
    },
    Channel {
        name: "theta",
        unit: "rad",
        description: "deck torsion",
    },
    Channel {
        name: "y_dd",
        unit: "m/s2",
        description: "deck lateral acceleration",
    },
    Channel {
        name: "z_dd",
        unit: "m/s2",
        description: "deck vertical acceleration",
    },
];

/// A probe's values in [`PROBE_CHANNELS`] order.
pub fn probe_channels(v: &ProbeValues) -> [f64; 5] {
    [v.y, v.z, v.theta, v.y_dd, v.z_dd]
}

/// A probe's values from [`PROBE_CHANNELS`] order.
pub fn probe_values(c: &[f64]) -> ProbeValues {
    ProbeValues {
        y: c[0],
        z: c[1],
        theta: c[2],
        y_dd: c[3],
        z_dd: c[4],
    }
}

/// A bridge FMU variable, decoded from its value reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BridgeVar {
    /// Channel `k` of [`WHEEL_CHANNELS`] of wheelset `w` (0-based), an input.
    Wheel { w: usize, k: usize },
    /// Channel `k` of [`WIND_CHANNELS`] at deck point `j` (0-based), an input.
    Wind { j: usize, k: usize },
    /// An output, by its slot in the output buffer.
    Output(usize),
    /// The damping ratio of mode `n` (0-based), a parameter.
    Damping(usize),
}

/// The bridge FMU's blocks for a number of wheelsets and probes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BridgeLayout {
    pub wheel_in: Block,
    pub rail_out: Block,
    pub probe_out: Block,
    pub wind_in: Block,
    /// Modes whose damping ratios are parameters (0 for a layout made without resources).
    pub n_modes: usize,
    n_outputs: usize,
    /// `decode` by value reference.
    table: Vec<Option<BridgeVar>>,
}

impl BridgeLayout {
    pub fn new(n_wheelsets: usize, n_probes: usize) -> BridgeLayout {
        Self::with_wind(n_wheelsets, n_probes, 0)
    }

    /// With `n_points` deck points taking the turbulence as inputs.
    pub fn with_wind(n_wheelsets: usize, n_probes: usize, n_points: usize) -> BridgeLayout {
        let mut b = Blocks::default();
        let wheel_in = b.input("ws", &WHEEL_CHANNELS, n_wheelsets);
        let rail_out = b.output("ws", &RAIL_CHANNELS, n_wheelsets);
        let probe_out = b.output("probe", &PROBE_CHANNELS, n_probes);
        let wind_in = b.input("deck", &WIND_CHANNELS, n_points);
        let mut l = BridgeLayout {
            wheel_in,
            rail_out,
            probe_out,
            wind_in,
            n_modes: 0,
            n_outputs: b.n_slots(),
            table: Vec::new(),
        };
        l.table = Block::table(&[l.wheel_in, l.rail_out, l.probe_out, l.wind_in], |vr| {
            l.decode_blocks(vr)
        });
        l
    }

    /// The layout of the FMU with these resources.
    pub fn of(res: &BridgeResources) -> BridgeLayout {
        let points = res.modal.buffeting.as_ref().map_or(0, |b| b.points.max(2));
        let mut l = BridgeLayout::with_wind(res.n_wheelsets, res.probes.len(), points);
        l.n_modes = res.modal.n_modes();
        l
    }

    pub fn n_wheelsets(&self) -> usize {
        self.wheel_in.count
    }

    /// Size of the output buffer.
    pub fn n_outputs(&self) -> usize {
        self.n_outputs
    }

    /// The variable of `vr` (one table load).
    pub fn decode(&self, vr: u32) -> Option<BridgeVar> {
        if vr >= PARAM_BASE {
            let n = (vr - PARAM_BASE) as usize;
            return (n < self.n_modes).then_some(BridgeVar::Damping(n));
        }
        self.table.get(vr as usize).copied().flatten()
    }

    /// The name of parameter `mode[n + 1].damping_ratio`.
    pub fn damping_name(n: usize) -> String {
        format!("mode[{}].damping_ratio", n + 1)
    }

    fn decode_blocks(&self, vr: u32) -> Option<BridgeVar> {
        if let Some((w, k)) = self.wheel_in.decode(vr) {
            return Some(BridgeVar::Wheel { w, k });
        }
        if let Some((j, k)) = self.wind_in.decode(vr) {
            return Some(BridgeVar::Wind { j, k });
        }
        Block::slot_of(&[self.rail_out, self.probe_out], vr).map(BridgeVar::Output)
    }

    /// All variables in value-reference order (what `modelDescription.xml` lists).
    pub fn variables(&self, res: &BridgeResources) -> Vec<Var> {
        let mut v = self.wheel_in.variables(
            |w, c| format!("{}, wheelset {}", c.description, w + 1),
            |_, k| Some(if k == 0 { PARKED_X } else { 0.0 }),
        );
        v.extend(self.rail_out.variables(
            |w, c| {
                format!(
                    "{} under wheelset {} (deck plus irregularity)",
                    c.description,
                    w + 1
                )
            },
            |_, _| None,
        ));
        v.extend(self.probe_out.variables(
            |p, c| {
                let probe = &res.probes[p];
                format!(
                    "{} at probe {} (x = {} m)",
                    c.description, probe.name, probe.x_m
                )
            },
            |_, _| None,
        ));
        if let Some(spec) = &res.modal.buffeting {
            let (x, _) = spec.points_on(res.modal.x_start_m, res.modal.x_end_m);
            v.extend(self.wind_in.variables(
                |j, c| format!("{} at deck point {} (x = {} m)", c.description, j + 1, x[j]),
                |_, _| Some(0.0),
            ));
        }
        let m = &res.modal;
        v.extend((0..self.n_modes).map(|n| Var {
            vr: PARAM_BASE + n as u32,
            name: Self::damping_name(n),
            causality: fmu_contract::Causality::Parameter,
            unit: "1".into(),
            description: format!(
                "damping ratio of mode {} ({}, {} Hz)",
                n + 1,
                m.labels[n],
                m.frequencies_hz[n]
            ),
            start: Some(m.damping[n]),
        }));
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variable_decodes_to_itself_and_outputs_fill_the_buffer() {
        let l = BridgeLayout::with_wind(7, 3, 4);
        assert_eq!(l.n_outputs(), 9 * 7 + 5 * 3);
        let mut slots = Vec::new();
        for (i, b) in [l.wheel_in, l.rail_out, l.probe_out, l.wind_in]
            .iter()
            .enumerate()
        {
            for n in 0..b.count {
                for k in 0..b.width() {
                    match l.decode(b.vr(n, k)) {
                        Some(BridgeVar::Wheel { w, k: kk }) => {
                            assert_eq!((i, w, kk), (0, n, k))
                        }
                        Some(BridgeVar::Wind { j, k: kk }) => assert_eq!((i, j, kk), (3, n, k)),
                        Some(BridgeVar::Output(s)) => slots.push(s),
                        Some(BridgeVar::Damping(m)) => {
                            panic!("{} decodes as mode {m}", b.name(n, k))
                        }
                        None => panic!("{} does not decode", b.name(n, k)),
                    }
                }
            }
        }
        assert_eq!(slots, (0..l.n_outputs()).collect::<Vec<_>>());
        assert_eq!(l.decode((14 * 7 + 5 * 3 + 2 * 4) as u32), None);
        // the damping parameters from PARAM_BASE, as many as there are modes
        assert_eq!(
            l.decode(PARAM_BASE),
            None,
            "a layout without resources has none"
        );
        let mut m = l.clone();
        m.n_modes = 3;
        assert_eq!(m.decode(PARAM_BASE + 2), Some(BridgeVar::Damping(2)));
        assert_eq!(m.decode(PARAM_BASE + 3), None);
        assert_eq!(BridgeLayout::damping_name(0), "mode[1].damping_ratio");
    }
}
