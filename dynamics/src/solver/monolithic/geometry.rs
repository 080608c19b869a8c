//! A step's geometry, which depends on the time alone: where the wheelsets are, the
//! prescribed rail motion under them and their rail shapes `Ψ` in the two layouts the step
//! reads ([`Geometry`], made from the model as [`Placement`] gives it); and where each
//! vehicle's `U` sits in them ([`Blocks`]).
//!
//! The step makes it itself, or takes it from the worker that makes it for the steps to come
//! ([`super::lookahead`]): the same functions, the same values.

use crate::bridge::{LaneScratch, ModalBridge, SHAPE_LANES};
use crate::solver::rail_prescribed;
use crate::track::RailProfile;
use crate::train::{Train, WheelsetRef};
use nalgebra::Vector3;

/// What a step's geometry reads: the model, where each wheelset sits in the train and in
/// the blocks.
pub(super) struct Placement<'a> {
    pub(super) bridge: &'a ModalBridge,
    pub(super) train: &'a Train,
    pub(super) track: &'a dyn RailProfile,
    pub(super) wheelsets: &'a [WheelsetRef],
    pub(super) lane_at: &'a [(usize, usize)],
    /// The step size, s.
    pub(super) h: f64,
}

/// A step's geometry, which depends on the time alone: the wheelsets' positions, their
/// prescribed rail motion and their rail shapes in the two layouts the step reads.
#[derive(Debug, Clone, Default)]
pub(super) struct Geometry {
    /// The time it is made for, s.
    pub(super) t: f64,
    /// Wheelset positions, m.
    pub(super) x: Vec<f64>,
    /// Prescribed rail motion (irregularity and hunting) under each wheelset.
    pub(super) presc: Vec<[Vector3<f64>; 3]>,
    /// Every vehicle's `U` (its wheelsets' rail shapes `Ψ`, zeros off the deck) mode after
    /// mode, vehicle after vehicle from `block_at[i]`: `blocks[block_at[i] + n · 3n_w + 3l + k]
    /// = Ψ_{w_l}[n][k]`, written with the shapes ([`ModalBridge::rail_shapes_lanes`]). Its
    /// products `Ψ q` ([`super::reduced::block_mul`]) are those of the step and of
    /// [`super::reduced::Reduced::apply`].
    pub(super) blocks: Vec<f64>,
    /// The same shapes as three rows of `N_b` per wheelset, component after component
    /// (`psi_t[(3w + k) N_b + n] = Ψ_w[n][k]`): a vehicle's wheelsets' rows, one after the
    /// other, are its `U` rail DOF after rail DOF ([`super::reduced::block_tr_add`]).
    pub(super) psi_t: Vec<f64>,
    /// Per wheelset: on the deck.
    pub(super) on: Vec<bool>,
    /// Scratch of [`ModalBridge::rail_shapes_lanes`].
    lanes: LaneScratch,
}

impl Geometry {
    pub(super) fn new(nw: usize, nb: usize) -> Self {
        Geometry {
            t: 0.0,
            x: vec![0.0; nw],
            presc: vec![[Vector3::zeros(); 3]; nw],
            blocks: vec![0.0; 3 * nw * nb],
            psi_t: vec![0.0; 3 * nw * nb],
            on: vec![false; nw],
            lanes: LaneScratch::default(),
        }
    }

    /// Every wheelset's position at `t`.
    pub(super) fn positions(&mut self, m: &Placement<'_>, t: f64) {
        self.t = t;
        // each train's travel once, for its wheelsets (which follow one another)
        let mut travelled = (usize::MAX, 0.0);
        for (x, ws) in self.x.iter_mut().zip(m.wheelsets) {
            let run = &m.train.runs[ws.run];
            if travelled.0 != ws.run {
                travelled = (ws.run, run.travel(t).s_m);
            }
            *x = run.x_after(travelled.1, ws.offset_m);
        }
    }

    /// The prescribed rail motion (zero when `flat`) under the wheelsets `busy` at their
    /// [`Geometry::positions`] at `t`.
    pub(super) fn rails(&mut self, m: &Placement<'_>, busy: &[usize], t: f64, flat: bool) {
        for &w in busy {
            self.presc[w] = if flat {
                [Vector3::zeros(); 3]
            } else {
                // the track's data a step on is read next step
                let ws = &m.wheelsets[w];
                let run = &m.train.runs[ws.run];
                m.track.prefetch(run.x_at(ws.offset_m, t + m.h));
                rail_prescribed(m.track, run, ws.in_run, self.x[w], t)
            };
        }
    }

    /// The rail shapes of the wheelsets `busy` (ascending) at their positions, in both
    /// layouts, [`SHAPE_LANES`] at a time (each lane's shapes are those of a lane alone).
    pub(super) fn shapes(&mut self, m: &Placement<'_>, busy: &[usize]) {
        let nb = m.bridge.n_modes();
        let mut psi_t = &mut self.psi_t[..];
        let mut base = 0;
        for chunk in busy.chunks(SHAPE_LANES) {
            let mut rows: [&mut [f64]; SHAPE_LANES] = Default::default();
            let mut at = [(0, 0); SHAPE_LANES];
            let mut xs = [0.0; SHAPE_LANES];
            let mut tracks = [0; SHAPE_LANES];
            for ((((r, a), x), tr), &w) in
                (rows.iter_mut().zip(&mut at).zip(&mut xs).zip(&mut tracks)).zip(chunk)
            {
                let tail_t = std::mem::take(&mut psi_t)
                    .split_at_mut((w - base) * 3 * nb)
                    .1;
                let (this_t, tail_t) = tail_t.split_at_mut(3 * nb);
                (*r, psi_t, base) = (this_t, tail_t, w + 1);
                *a = m.lane_at[w];
                *x = self.x[w];
                *tr = m.train.runs[m.wheelsets[w].run].track;
            }
            let mut on = [false; SHAPE_LANES];
            let k = chunk.len();
            m.bridge.rail_shapes_lanes(
                &xs[..k],
                &tracks[..k],
                &mut self.blocks,
                &at[..k],
                &mut rows[..k],
                &mut on[..k],
                &mut self.lanes,
            );
            for (&w, on) in chunk.iter().zip(on) {
                self.on[w] = on;
            }
        }
    }
}

/// Where each vehicle's `U` sits in a [`Geometry`]: vehicle `i`'s block of
/// [`Geometry::blocks`] starts at `block_at[i]`, its wheelsets' rows of [`Geometry::psi_t`]
/// at its first wheelset `first_ws[i]`.
#[derive(Clone, Copy)]
pub(super) struct Blocks<'a> {
    pub(super) geo: &'a Geometry,
    pub(super) train: &'a Train,
    pub(super) block_at: &'a [usize],
    pub(super) first_ws: &'a [usize],
    /// The number of modes `N_b`.
    pub(super) nb: usize,
}

impl<'a> Blocks<'a> {
    /// Vehicle `i`'s `U` mode after mode, in [`Geometry::blocks`].
    pub(super) fn block(&self, i: usize) -> &'a [f64] {
        let r3 = 3 * self.train.vehicles[i].model.wheelsets.len();
        &self.geo.blocks[self.block_at[i]..self.block_at[i] + r3 * self.nb]
    }

    /// Vehicle `i`'s `U` rail DOF after rail DOF: its wheelsets' rows of
    /// [`Geometry::psi_t`].
    pub(super) fn block_t(&self, i: usize) -> &'a [f64] {
        let (nb, f0) = (self.nb, self.first_ws[i]);
        let nwi = self.train.vehicles[i].model.wheelsets.len();
        &self.geo.psi_t[3 * nb * f0..3 * nb * (f0 + nwi)]
    }
}
