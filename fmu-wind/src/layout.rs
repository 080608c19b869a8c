//! The wind FMU's variables, described once: value references, names, units,
//! descriptions, start values and output-buffer slots, for the model, the master and the
//! `modelDescription.xml` writer.
//!
//! | block | causality | channels | value references |
//! |---|---|---|---|
//! | `veh[i]` | input | [`BODY_POSITION_CHANNELS`] (position of car body i's centre) | from 0 |
//! | `deck[j]` | output | [`WIND_CHANNELS`] (turbulence u, w at deck point j) | after the inputs |
//! | `veh[i]` | output | [`WIND_CHANNELS`] (turbulence u, w at car body i) | after the deck points |

use crate::WindResources;
use fmu_contract::{Block, Blocks, Var, BODY_POSITION_CHANNELS, WIND_CHANNELS};

/// `<fmiModelDescription description>` of the wind FMU.
pub const DESCRIPTION: &str = "Turbulent wind along the deck (seeded stationary Gaussian field with Davenport coherence): car-body positions in, turbulence at the deck points and the car bodies out";

/// Start of `veh[i].x`, m: a car body far before the deck (it sees the field's first point).
pub const PARKED_X: f64 = -1.0e6;

/// A wind FMU variable, decoded from its value reference.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WindVar {
    /// The position of car body `i` (0-based), an input.
    Body(usize),
    /// An output, by its slot in the output buffer.
    Output(usize),
}

/// The wind FMU's blocks for a number of deck points and vehicles.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WindLayout {
    pub body_in: Block,
    pub deck_out: Block,
    pub body_out: Block,
    n_outputs: usize,
    /// `decode` by value reference.
    table: Vec<Option<WindVar>>,
}

impl WindLayout {
    pub fn new(n_points: usize, n_vehicles: usize) -> WindLayout {
        let mut b = Blocks::default();
        let body_in = b.input("veh", &BODY_POSITION_CHANNELS, n_vehicles);
        let deck_out = b.output("deck", &WIND_CHANNELS, n_points);
        let body_out = b.output("veh", &WIND_CHANNELS, n_vehicles);
        let mut l = WindLayout {
            body_in,
            deck_out,
            body_out,
            n_outputs: b.n_slots(),
            table: Vec::new(),
        };
        l.table = Block::table(&[l.body_in, l.deck_out, l.body_out], |vr| {
            l.decode_blocks(vr)
        });
        l
    }

    /// The layout of the FMU with these resources.
    pub fn of(res: &WindResources) -> WindLayout {
        WindLayout::new(res.points_m.len(), res.n_vehicles)
    }

    /// Size of the output buffer.
    pub fn n_outputs(&self) -> usize {
        self.n_outputs
    }

    /// The variable of `vr` (one table load).
    pub fn decode(&self, vr: u32) -> Option<WindVar> {
        self.table.get(vr as usize).copied().flatten()
    }

    fn decode_blocks(&self, vr: u32) -> Option<WindVar> {
        if let Some((i, _)) = self.body_in.decode(vr) {
            return Some(WindVar::Body(i));
        }
        Block::slot_of(&[self.deck_out, self.body_out], vr).map(WindVar::Output)
    }

    /// All variables in value-reference order (what `modelDescription.xml` lists).
    pub fn variables(&self, res: &WindResources) -> Vec<Var> {
        let mut v = self.body_in.variables(
            |i, c| format!("{}, vehicle {}", c.description, i + 1),
            |_, _| Some(PARKED_X),
        );
        v.extend(self.deck_out.variables(
            |j, c| {
                format!(
                    "{} at deck point {} (x = {} m)",
                    c.description,
                    j + 1,
                    res.points_m[j]
                )
            },
            |_, _| None,
        ));
        v.extend(self.body_out.variables(
            |i, c| format!("{} at the car body of vehicle {}", c.description, i + 1),
            |_, _| None,
        ));
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_variable_decodes_to_itself_and_outputs_fill_the_buffer() {
        let l = WindLayout::new(5, 3);
        assert_eq!(l.n_outputs(), 2 * 5 + 2 * 3);
        let mut slots = Vec::new();
        for (b, input) in [(l.body_in, true), (l.deck_out, false), (l.body_out, false)] {
            for n in 0..b.count {
                for k in 0..b.width() {
                    match l.decode(b.vr(n, k)) {
                        Some(WindVar::Body(i)) => assert!(input && i == n),
                        Some(WindVar::Output(s)) => slots.push(s),
                        None => panic!("{} does not decode", b.name(n, k)),
                    }
                }
            }
        }
        assert_eq!(slots, (0..l.n_outputs()).collect::<Vec<_>>());
        assert_eq!(l.decode(3 + 16), None);
        assert_eq!(l.body_out.name(1, 0), "veh[2].u");
    }
}
