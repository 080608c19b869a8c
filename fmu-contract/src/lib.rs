//! The contract the project's FMUs share: the channel tables both sides of a connection use,
//! and the block arithmetic that turns channel tables into value references, names and
//! output slots. Each FMU's own contract (identifier, resources, which blocks in which order,
//! with which texts) lives in its crate: `fmu_bridge`, `fmu_train` and `fmu_wind`.
//!
//! Naming pattern (FMI "structured" convention, 1-based indices, SI units): a [`Block`] of
//! `count` × `channels` is named `{prefix}[{i}].{channel}`, e.g. `ws[3].F_z`. Its value
//! references are consecutive, index slowest and channel fastest, and the blocks of an FMU
//! follow each other from value reference 0 ([`Blocks`]). Output blocks also own consecutive
//! slots of the FMU's output buffer in the same order.
//!
//! | channels | what | carried by |
//! |---|---|---|
//! | [`WHEEL_CHANNELS`] | `x` (m), `vx` (m/s), `F_y` (N), `M_x` (N·m), `F_z` (N): position, speed and force of a wheelset on the rail | train output → bridge input |
//! | [`RAIL_CHANNELS`] | `y`, `theta`, `z` (m, rad, m) and their `_d`, `_dd` derivatives: rail motion under a wheelset, deck plus irregularity | bridge output → train input |
//!
//! Signs: forces and moments act on the rail (deck); y right, z down, θ right side down.
//! **Input timing**: inputs set before `fmi2DoStep(t, h)` are the values at `t + h` (what an
//! implicit iteration needs); a plain fixed-step master therefore sees a one-step lag.

pub mod package;

pub use package::Contract;

use nalgebra::Vector3;
use tbi_dynamics::solver::partitioned::WheelInput;

/// Build identifier that goes into the FMUs' GUIDs (with the bytes of their resources).
pub const BUILD_ID: &str = concat!("tbi-", env!("CARGO_PKG_VERSION"));

/// The turbulence at a deck point or a car body, as the wind FMU gives it and the bridge
/// FMU takes it (about the mean wind U, which both sides hold).
pub const WIND_CHANNELS: [Channel; 2] = [
    ch(
        "u",
        "m/s",
        "along-wind turbulence u (towards +y, about the mean U)",
    ),
    ch("w", "m/s", "vertical turbulence w (upward)"),
];

/// The position of a car body's centre (the mean of its wheelsets' positions), from the
/// train FMU to the wind FMU.
pub const BODY_POSITION_CHANNELS: [Channel; 1] = [ch(
    "x",
    "m",
    "position of the car body's centre along the track",
)];

/// One scalar channel of a block: its name (after the `.`), unit and description.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Channel {
    pub name: &'static str,
    /// Unit as written into `modelDescription.xml` (`"1"`: dimensionless, no unit written).
    pub unit: &'static str,
    pub description: &'static str,
}

const fn ch(name: &'static str, unit: &'static str, description: &'static str) -> Channel {
    Channel {
        name,
        unit,
        description,
    }
}

/// Rail-motion channels per wheelset, in value-reference order: channel `k` is
/// `rail[k / 3][k % 3]` of the `(u, u̇, ü) × (y, θ, z)` array both partitions use
/// ([`rail_channel`]).
pub const RAIL_CHANNELS: [Channel; 9] = [
    ch("y", "m", "lateral rail displacement"),
    ch("theta", "rad", "rail roll (cross-level) angle"),
    ch("z", "m", "vertical rail displacement (+ down)"),
    ch("y_d", "m/s", "lateral rail velocity"),
    ch("theta_d", "rad/s", "rail roll rate"),
    ch("z_d", "m/s", "vertical rail velocity"),
    ch("y_dd", "m/s2", "lateral rail acceleration"),
    ch("theta_dd", "rad/s2", "rail roll acceleration"),
    ch("z_dd", "m/s2", "vertical rail acceleration"),
];

/// Wheelset channels the train sends to the bridge, in value-reference order (the fields of
/// [`WheelInput`]: [`wheel_channel`]).
pub const WHEEL_CHANNELS: [Channel; 5] = [
    ch("x", "m", "wheelset position along the track"),
    ch("vx", "m/s", "wheelset speed along the track"),
    ch("F_y", "N", "lateral force of the wheelset on the rail (+y)"),
    ch(
        "M_x",
        "N.m",
        "roll moment of the wheelset on the rail (about +x)",
    ),
    ch(
        "F_z",
        "N",
        "vertical force of the wheelset on the rail (+ down)",
    ),
];

/// Indices into [`WHEEL_CHANNELS`].
pub mod wheel {
    pub const X: usize = 0;
    pub const VX: usize = 1;
    pub const F_Y: usize = 2;
    pub const M_X: usize = 3;
    pub const F_Z: usize = 4;
}

/// Channel `k` of [`WHEEL_CHANNELS`] in a wheelset's input.
#[inline]
pub fn wheel_channel(input: &mut WheelInput, k: usize) -> &mut f64 {
    match k {
        wheel::X => &mut input.x,
        wheel::VX => &mut input.vx,
        _ => &mut input.f[k - wheel::F_Y],
    }
}

/// The wheelset input of the [`WHEEL_CHANNELS`] `v` (5 values in their order; channel `k`
/// is [`wheel_channel`]`(input, k)`).
#[inline]
pub fn wheel_from_values(v: &[f64]) -> WheelInput {
    WheelInput {
        x: v[wheel::X],
        vx: v[wheel::VX],
        f: [v[wheel::F_Y], v[wheel::M_X], v[wheel::F_Z]],
    }
}

/// Channel `k` of [`RAIL_CHANNELS`] in a wheelset's rail motion `(u, u̇, ü)`.
#[inline]
pub fn rail_channel(rail: &mut [Vector3<f64>; 3], k: usize) -> &mut f64 {
    &mut rail[k / 3][k % 3]
}

/// The [`RAIL_CHANNELS`] of a rail motion in their order (channel `k` is
/// [`rail_channel`]`(rail, k)`).
#[inline]
pub fn rail_values(rail: &[Vector3<f64>; 3]) -> [f64; 9] {
    let [u, ud, udd] = rail;
    [u.x, u.y, u.z, ud.x, ud.y, ud.z, udd.x, udd.y, udd.z]
}

/// The rail motion of the [`RAIL_CHANNELS`] `v` (9 values in their order; the inverse of
/// [`rail_values`]).
#[inline]
pub fn rail_from_values(v: &[f64]) -> [Vector3<f64>; 3] {
    let d = |i: usize| Vector3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    [d(0), d(1), d(2)]
}

/// FMI causality of a variable (the modelDescription's; the FMUs declare parameters, inputs
/// and outputs).
pub use model_description::Causality;

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

/// `count` × `channels` scalars named `{prefix}[{i}].{channel}` (1-based `i`) with
/// consecutive value references from `vr0` (index slowest, channel fastest); an output block
/// also owns the output-buffer slots from `slot0` in the same order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Block {
    pub prefix: &'static str,
    pub channels: &'static [Channel],
    pub count: usize,
    pub causality: Causality,
    pub vr0: u32,
    /// First output-buffer slot (outputs only).
    pub slot0: Option<usize>,
}

impl Block {
    /// Channels per index.
    #[inline]
    pub fn width(&self) -> usize {
        self.channels.len()
    }

    /// Number of scalars.
    #[inline]
    pub fn len(&self) -> usize {
        self.count * self.width()
    }

    /// Whether the block holds no scalar.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Value reference of channel `k` of index `i` (0-based).
    #[inline]
    pub fn vr(&self, i: usize, k: usize) -> u32 {
        debug_assert!(i < self.count && k < self.width());
        self.vr0 + (i * self.width() + k) as u32
    }

    /// `(i, k)` of a value reference inside the block.
    #[inline]
    pub fn decode(&self, vr: u32) -> Option<(usize, usize)> {
        let o = vr.checked_sub(self.vr0)? as usize;
        (o < self.len()).then(|| (o / self.width(), o % self.width()))
    }

    /// Offset in the block of `vr[0]` when `vr` is a run of consecutive value references
    /// (`vr[i] = vr[0] + i`) that lies wholly inside the block; `None` otherwise (also empty).
    #[inline]
    pub fn run(&self, vr: &[u32]) -> Option<usize> {
        let first = *vr.first()?;
        let o = first.checked_sub(self.vr0)? as usize;
        if o + vr.len() > self.len() {
            return None;
        }
        // without an early exit, so that the test runs several references per instruction
        // (a run is the usual case, and then every reference is looked at anyway)
        let off = (vr.iter().zip(0u32..)).fold(0, |acc, (&r, i)| acc | (r.wrapping_sub(first) ^ i));
        (off == 0).then_some(o)
    }

    /// `set(i, k, value)` for the values of a run that starts at offset `first` of the block
    /// (from [`Block::run`]), in order.
    pub fn for_run(&self, first: usize, values: &[f64], mut set: impl FnMut(usize, usize, f64)) {
        let width = self.width();
        let (mut i, mut k) = (first / width, first % width);
        for &v in values {
            set(i, k, v);
            k += 1;
            if k == width {
                (i, k) = (i + 1, 0);
            }
        }
    }

    /// Sets `items` (one per index of the block) from the values of a run that starts at
    /// offset `first` (from [`Block::run`]): whole items (the master's case) each from its
    /// `width` values by `whole`, otherwise value by value into `channel(item, k)`.
    pub fn set_run<T>(
        &self,
        first: usize,
        values: &[f64],
        items: &mut [T],
        whole: impl Fn(&[f64]) -> T,
        channel: impl Fn(&mut T, usize) -> &mut f64,
    ) {
        let width = self.width();
        if first.is_multiple_of(width) && values.len().is_multiple_of(width) {
            for (item, v) in items[first / width..]
                .iter_mut()
                .zip(values.chunks_exact(width))
            {
                *item = whole(v);
            }
        } else {
            self.for_run(first, values, |i, k, v| *channel(&mut items[i], k) = v);
        }
    }

    /// The output-buffer slot of `vr[0]` when `vr` is a [`Block::run`] inside one of the
    /// output `blocks` (whose slots follow their value references).
    #[inline]
    pub fn output_run(blocks: &[Block], vr: &[u32]) -> Option<usize> {
        blocks.iter().find_map(|b| Some(b.slot0? + b.run(vr)?))
    }

    /// Output-buffer slot of channel `k` of index `i` (outputs only).
    #[inline]
    pub fn slot(&self, i: usize, k: usize) -> usize {
        self.slot0.expect("an output block") + i * self.width() + k
    }

    /// The output-buffer slots of index `i` (outputs only).
    #[inline]
    pub fn slots(&self, i: usize) -> std::ops::Range<usize> {
        self.slot(i, 0)..self.slot(i, 0) + self.width()
    }

    /// `{prefix}[{i + 1}].{channel k}`.
    pub fn name(&self, i: usize, k: usize) -> String {
        format!("{}[{}].{}", self.prefix, i + 1, self.channels[k].name)
    }

    /// Value references of channels `ks` of every index, index slowest.
    pub fn vrs(&self, ks: &[usize]) -> Vec<u32> {
        (0..self.count)
            .flat_map(|i| ks.iter().map(move |&k| self.vr(i, k)))
            .collect()
    }

    /// A table from value reference to what `decode` makes of it, over the value references
    /// of `blocks` (a layout's decoding as one load on the FMI hot path).
    pub fn table<T: Copy>(blocks: &[Block], decode: impl Fn(u32) -> Option<T>) -> Vec<Option<T>> {
        let end = blocks
            .iter()
            .map(|b| b.vr0 + b.len() as u32)
            .max()
            .unwrap_or(0);
        (0..end).map(decode).collect()
    }

    /// The output-buffer slot of `vr` in the first of the output `blocks` that holds it.
    pub fn slot_of(blocks: &[Block], vr: u32) -> Option<usize> {
        blocks
            .iter()
            .find_map(|b| b.decode(vr).map(|(i, k)| b.slot(i, k)))
    }

    /// Every value reference of the block, in order.
    pub fn all_vrs(&self) -> Vec<u32> {
        (0..self.len() as u32).map(|o| self.vr0 + o).collect()
    }

    /// The block's variables in value-reference order; `describe(i, channel)` gives the
    /// description, `start(i, k)` the start value.
    pub fn variables(
        &self,
        describe: impl Fn(usize, &Channel) -> String,
        start: impl Fn(usize, usize) -> Option<f64>,
    ) -> Vec<Var> {
        let mut v = Vec::with_capacity(self.len());
        for i in 0..self.count {
            for (k, c) in self.channels.iter().enumerate() {
                v.push(Var {
                    vr: self.vr(i, k),
                    name: self.name(i, k),
                    causality: self.causality,
                    unit: c.unit.to_string(),
                    description: describe(i, c),
                    start: start(i, k),
                });
            }
        }
        v
    }
}

/// Lays blocks end to end: value references from 0, output slots from 0.
#[derive(Debug, Default)]
pub struct Blocks {
    next_vr: u32,
    next_slot: usize,
}

impl Blocks {
    /// The next block of inputs.
    pub fn input(
        &mut self,
        prefix: &'static str,
        channels: &'static [Channel],
        count: usize,
    ) -> Block {
        self.block(prefix, channels, count, Causality::Input)
    }

    /// The next block of outputs (with buffer slots).
    pub fn output(
        &mut self,
        prefix: &'static str,
        channels: &'static [Channel],
        count: usize,
    ) -> Block {
        self.block(prefix, channels, count, Causality::Output)
    }

    /// Output-buffer slots handed out so far.
    pub fn n_slots(&self) -> usize {
        self.next_slot
    }

    fn block(
        &mut self,
        prefix: &'static str,
        channels: &'static [Channel],
        count: usize,
        causality: Causality,
    ) -> Block {
        let slot0 = (causality == Causality::Output).then_some(self.next_slot);
        let b = Block {
            prefix,
            channels,
            count,
            causality,
            vr0: self.next_vr,
            slot0,
        };
        self.next_vr += b.len() as u32;
        if slot0.is_some() {
            self.next_slot += b.len();
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rail_values_are_the_rail_channels_in_order() {
        let mut r = [
            Vector3::new(1.0, 2.0, 3.0),
            Vector3::new(4.0, 5.0, 6.0),
            Vector3::new(7.0, 8.0, 9.0),
        ];
        let v = rail_values(&r);
        for (k, &vk) in v.iter().enumerate() {
            assert_eq!(vk, *rail_channel(&mut r, k), "channel {k}");
        }
        assert_eq!(rail_from_values(&v), r);
        let mut w = WheelInput::default();
        for k in 0..WHEEL_CHANNELS.len() {
            *wheel_channel(&mut w, k) = 10.0 + k as f64;
        }
        let v: Vec<f64> = (0..5).map(|k| 10.0 + k as f64).collect();
        assert_eq!(wheel_from_values(&v), w);
    }

    #[test]
    fn set_run_sets_whole_items_and_single_channels_alike() {
        let mut blocks = Blocks::default();
        let b = blocks.input("ws", &WHEEL_CHANNELS, 3);
        let values: Vec<f64> = (0..15).map(|j| 1.0 + f64::from(j)).collect();
        // every offset and length: whole items (fast) and partial ones (value by value)
        for first in 0..15 {
            for len in 0..=15 - first {
                let mut items = vec![WheelInput::default(); 3];
                b.set_run(
                    first,
                    &values[..len],
                    &mut items,
                    wheel_from_values,
                    wheel_channel,
                );
                let mut expected = vec![WheelInput::default(); 3];
                b.for_run(first, &values[..len], |i, k, v| {
                    *wheel_channel(&mut expected[i], k) = v
                });
                assert_eq!(items, expected, "first {first}, len {len}");
            }
        }
    }

    #[test]
    fn for_run_visits_index_and_channel_of_each_value() {
        let mut blocks = Blocks::default();
        let b = blocks.input("ws", &WHEEL_CHANNELS, 3);
        let values: Vec<f64> = (0..9).map(f64::from).collect();
        let mut seen = Vec::new();
        b.for_run(3, &values, |i, k, v| seen.push((i, k, v)));
        let expected: Vec<(usize, usize, f64)> = (3..12)
            .map(|j| (j / b.width(), j % b.width(), (j - 3) as f64))
            .collect();
        assert_eq!(seen, expected);
    }

    #[test]
    fn blocks_follow_each_other_and_decode_inverts_vr() {
        let mut blocks = Blocks::default();
        let a = blocks.input("ws", &WHEEL_CHANNELS, 3);
        let b = blocks.output("ws", &RAIL_CHANNELS, 3);
        let c = blocks.output("x", &WHEEL_CHANNELS[..2], 4);
        assert_eq!((a.vr0, b.vr0, c.vr0), (0, 15, 42));
        assert_eq!((a.slot0, b.slot0, c.slot0), (None, Some(0), Some(27)));
        assert_eq!(blocks.n_slots(), 35);
        for blk in [a, b, c] {
            for i in 0..blk.count {
                for k in 0..blk.width() {
                    assert_eq!(blk.decode(blk.vr(i, k)), Some((i, k)));
                }
            }
            assert_eq!(blk.decode(blk.vr0 + blk.len() as u32), None);
        }
        assert_eq!(b.decode(14), None);
        assert_eq!(b.name(2, 8), "ws[3].z_dd");
        assert_eq!(b.slots(1), 9..18);
        assert_eq!(c.vrs(&[1]), vec![43, 45, 47, 49]);
        // runs of consecutive value references inside a block
        assert_eq!(b.run(&[15, 16, 17]), Some(0));
        assert_eq!(b.run(&(20..42).collect::<Vec<_>>()), Some(5));
        assert_eq!(b.run(&[41]), Some(26));
        assert_eq!(b.run(&[41, 42]), None, "leaves the block");
        assert_eq!(b.run(&[14, 15]), None, "starts before it");
        assert_eq!(b.run(&[15, 17]), None, "not consecutive");
        assert_eq!(b.run(&[16, 15]), None, "not ascending");
        assert_eq!(b.run(&[]), None);
        let mut seen = Vec::new();
        b.for_run(8, &[1.0, 2.0, 3.0], |i, k, v| seen.push((i, k, v)));
        assert_eq!(seen, vec![(0, 8, 1.0), (1, 0, 2.0), (1, 1, 3.0)]);
        assert_eq!(Block::output_run(&[b, c], &[43, 44]), Some(28));
        assert_eq!(
            Block::output_run(&[b, c], &[41, 42]),
            None,
            "across two blocks"
        );
        assert_eq!(
            Block::output_run(&[a], &[0, 1]),
            None,
            "an input block has no slots"
        );
    }

    #[test]
    fn channel_accessors_follow_the_tables() {
        let mut w = WheelInput::default();
        for k in 0..WHEEL_CHANNELS.len() {
            *wheel_channel(&mut w, k) = k as f64 + 1.0;
        }
        assert_eq!((w.x, w.vx, w.f), (1.0, 2.0, [3.0, 4.0, 5.0]));
        let mut r = [Vector3::zeros(); 3];
        for k in 0..RAIL_CHANNELS.len() {
            *rail_channel(&mut r, k) = k as f64;
        }
        assert_eq!(r[1], Vector3::new(3.0, 4.0, 5.0));
        assert_eq!(RAIL_CHANNELS[5].name, "z_d");
    }
}
