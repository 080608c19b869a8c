//! The look-ahead plumbing of the monolithic step: a worker thread ([`crate::solver::ahead`])
//! that makes each step's [`Geometry`] up to seven steps ahead, from a copy of the model, while
//! the stepping thread works; the step swaps the worker's geometry in instead of making its
//! own ([`Lookahead::take`]). The same functions make it, so the same values, bit for bit.

use super::geometry::{Geometry, Placement};
use crate::bridge::ModalBridge;
use crate::solver::ahead::Ahead;
use crate::track::RailProfile;
use crate::train::Train;
use std::sync::Arc;
use std::time::Duration;

/// The most bytes of rail shapes (both layouts) a step may take from the worker of
/// [`super::Monolithic::run_ahead`]: 192 KiB. Measured on the Tsing Ma model at 70 km/h, in
/// the placement of the cores where the hand-over is cheap: up to 154 KiB (100 modes under 8
/// coaches, 20 modes under 32) the runs took 36–43 % less time ahead; at 300 KiB (200
/// modes under 8 coaches, 50 under 32) the worker, writing lines the stepping core had
/// read, fell behind, and the runs took up to 20 % longer.
pub const AHEAD_MAX_BYTES: usize = 192 * 1024;

/// The worker making the geometry of the steps to come, if it runs, and what its next start
/// needs.
#[derive(Default)]
pub(super) struct Lookahead {
    /// The worker ([`Lookahead::start`]).
    worker: Option<Ahead<Geometry>>,
    /// The worker stopped on its own (fell behind, or failed) since [`Lookahead::take_lost`]
    /// was last called.
    lost: bool,
    /// The worker's copy of the bridge and the train, kept for its next start.
    model: Option<(Arc<ModalBridge>, Arc<Train>)>,
}

impl Lookahead {
    /// Starts the worker (unless it runs) on the steps after time `t`, each `m.h` on, with
    /// the copy of `m`'s bridge and train made at the first start and with `track`; with
    /// `give_up`, a step waits at most that long for it. Returns whether it runs.
    pub(super) fn start(
        &mut self,
        m: &Placement<'_>,
        track: &Arc<dyn RailProfile>,
        t: f64,
        give_up: Option<Duration>,
    ) -> bool {
        if self.worker.is_some() {
            return true;
        }
        let (bridge, train) = self
            .model
            .get_or_insert_with(|| (Arc::new(m.bridge.clone()), Arc::new(m.train.clone())))
            .clone();
        let track = track.clone();
        let (wheelsets, lane_at, h) = (m.wheelsets.to_vec(), m.lane_at.to_vec(), m.h);
        let busy: Vec<usize> = (0..wheelsets.len()).collect();
        let mut t = t;
        let (nw, nb) = (m.wheelsets.len(), m.bridge.n_modes());
        // the slots' buffers are made by the worker (apart from this thread's)
        let slots = (0..8).map(|_| Geometry::default()).collect();
        let fill = move |_k: u64, g: &mut Geometry| {
            if g.x.len() != nw {
                *g = Geometry::new(nw, nb);
            }
            t += h;
            let model = Placement {
                bridge: &bridge,
                train: &train,
                track: &*track,
                wheelsets: &wheelsets,
                lane_at: &lane_at,
                h,
            };
            g.positions(&model, t);
            g.rails(&model, &busy, t, false);
            g.shapes(&model, &busy);
        };
        self.worker = Ahead::spawn(slots, give_up, fill).ok();
        self.worker.is_some()
    }

    /// The worker's geometry of time `t` swapped into `geo` (which hands the slot it held
    /// back to the worker): whether it was. Out of step with the worker (another time), or
    /// with the worker stopped or fallen behind by its give-up time, the worker is stopped
    /// (each step makes its own geometry from now on) and false returned.
    pub(super) fn take(&mut self, t: f64, geo: &mut Geometry) -> bool {
        let Some(ahead) = &mut self.worker else {
            return false;
        };
        // the held slot gets its own buffers back, this step's come in
        let ok = ahead.next(|held, g| {
            if let Some(h) = held {
                std::mem::swap(h, geo);
            }
            let same = g.t.to_bits() == t.to_bits();
            if same {
                std::mem::swap(g, geo);
            }
            same
        });
        if ok == Some(true) {
            return true;
        }
        // out of step with the worker, or the worker stopped or fell behind by its
        // give-up time: made here from now on
        self.lost |= ok.is_none();
        self.worker = None;
        false
    }

    /// Whether the worker stopped on its own since the last call.
    pub(super) fn take_lost(&mut self) -> bool {
        std::mem::take(&mut self.lost)
    }

    /// Whether the worker runs.
    pub(super) fn runs(&self) -> bool {
        self.worker.is_some()
    }

    /// Stops the worker.
    pub(super) fn stop(&mut self) {
        self.worker = None;
    }
}
