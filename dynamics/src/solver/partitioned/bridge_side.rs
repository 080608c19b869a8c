//! The bridge partition with its track ([`BridgeSide`], see [`super`]): the modal equations
//! `q̈ + 2ζω q̇ + ω² q = Σ Ψ(x)ᵀ f` stepped with the wheel forces of the end of the step, and
//! the rail motion under each wheelset, deck plus irregularity. Its sums over the wheelsets go
//! through the shapes' own basis ([`super::basis`]).

use super::basis::{sine_forces, sine_motions, BasisScratch, ShapeCache};
use super::interface::{ProbeValues, WheelInput};
use crate::bridge::ModalBridge;
use crate::newmark::Newmark;
use crate::solver::share;
use crate::track::{rail_motion, RailProfile};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};
use std::sync::{Arc, Mutex};

/// Dynamic state of the modal bridge.
#[derive(Debug, PartialEq, Default, Serialize, Deserialize)]
pub struct ModalState {
    pub q: Vec<f64>,
    pub qd: Vec<f64>,
    pub qdd: Vec<f64>,
    /// Time since initialisation, s (the time of the buffeting forces).
    #[serde(default)]
    pub t: f64,
}

impl Clone for ModalState {
    fn clone(&self) -> Self {
        ModalState {
            q: self.q.clone(),
            qd: self.qd.clone(),
            qdd: self.qdd.clone(),
            t: self.t,
        }
    }

    /// Reuses the vectors' allocations.
    fn clone_from(&mut self, source: &Self) {
        self.q.clone_from(&source.q);
        self.qd.clone_from(&source.qd);
        self.qdd.clone_from(&source.qdd);
        self.t = source.t;
    }
}

/// The bridge with its track (see the module docs).
#[derive(Debug)]
pub struct BridgeSide {
    pub bridge: Arc<ModalBridge>,
    pub track: Arc<dyn RailProfile>,
    /// The track each wheelset slot runs on (0 the first; slots beyond it: 0).
    pub tracks: Arc<Vec<usize>>,
    pub state: ModalState,
    omega: Arc<Vec<f64>>,
    zeta: Arc<Vec<f64>>,
    /// Rail shapes at recent positions, shared by clones (it holds derived data only, keyed
    /// by position, so a restored state may use it too).
    cache: Arc<Mutex<ShapeCache>>,
    /// The deck's buffeting forces (derived from the bridge; shared by clones).
    buffeting: Option<Arc<crate::bridge::buffeting::DeckBuffeting>>,
    /// The turbulence (u, w) at the deck points at the end of the coming step, m/s, when it
    /// comes from outside (the bridge FMU's inputs `deck[j].u`, `deck[j].w`); None: the
    /// bridge generates its field ([`Self::take_wind_from_inputs`]).
    pub deck_wind: Option<Vec<[f64; 2]>>,
    /// Scratch of [`Self::rails`]: `(q, q̇, q̈, 0)` of each mode.
    modal: Vec<[f64; 4]>,
    /// Scratch of [`Self::step`]: the generalised forces.
    force: Vec<f64>,
    /// Scratch of the products through the shapes' basis.
    nodes: BasisScratch,
}

impl Clone for BridgeSide {
    fn clone(&self) -> Self {
        BridgeSide {
            bridge: self.bridge.clone(),
            track: self.track.clone(),
            tracks: self.tracks.clone(),
            state: self.state.clone(),
            omega: self.omega.clone(),
            zeta: self.zeta.clone(),
            cache: self.cache.clone(),
            buffeting: self.buffeting.clone(),
            deck_wind: self.deck_wind.clone(),
            modal: Vec::new(),
            force: Vec::new(),
            nodes: BasisScratch::default(),
        }
    }

    /// Reuses this side's allocations (the rollback of an FMU copies the modal state).
    fn clone_from(&mut self, source: &Self) {
        share(&mut self.bridge, &source.bridge);
        share(&mut self.track, &source.track);
        share(&mut self.tracks, &source.tracks);
        self.state.clone_from(&source.state);
        share(&mut self.omega, &source.omega);
        share(&mut self.zeta, &source.zeta);
        share(&mut self.cache, &source.cache);
        match (&mut self.buffeting, &source.buffeting) {
            (Some(to), Some(from)) => share(to, from),
            (to, from) => to.clone_from(from),
        }
        self.deck_wind.clone_from(&source.deck_wind);
    }
}

impl BridgeSide {
    pub fn new(bridge: Arc<ModalBridge>, track: Arc<dyn RailProfile>) -> Self {
        let nb = bridge.n_modes();
        BridgeSide {
            omega: Arc::new(bridge.omegas()),
            zeta: Arc::new(bridge.damping.clone()),
            state: ModalState {
                q: vec![0.0; nb],
                qd: vec![0.0; nb],
                qdd: vec![0.0; nb],
                t: 0.0,
            },
            cache: Arc::new(Mutex::new(ShapeCache::default())),
            buffeting: bridge.buffeting.as_ref().map(|spec| {
                Arc::new(
                    crate::bridge::buffeting::DeckBuffeting::new(&bridge, spec)
                        .expect("the buffeting spec is checked when the model is built"),
                )
            }),
            deck_wind: None,
            modal: Vec::new(),
            force: Vec::new(),
            nodes: BasisScratch::default(),
            bridge,
            track,
            tracks: Arc::new(Vec::new()),
        }
    }

    /// Take the deck's turbulence from [`Self::deck_wind`] (set before each step) instead of
    /// generating it: the bridge FMU coupled to a wind FMU (nothing without buffeting).
    pub fn take_wind_from_inputs(&mut self) {
        if let Some(spec) = &self.bridge.buffeting {
            let b = crate::bridge::buffeting::DeckBuffeting::without_field(&self.bridge, spec);
            self.deck_wind = Some(vec![[0.0; 2]; b.points().len()]);
            self.buffeting = Some(Arc::new(b));
        }
    }

    /// Add the buffeting forces at time `t` to `fq`.
    fn add_buffeting(&self, t: f64, fq: &mut [f64]) {
        if let Some(b) = &self.buffeting {
            match &self.deck_wind {
                Some(uw) => b.add_modal_force_from(uw, fq),
                None => b.add_modal_force(t, fq),
            }
        }
    }

    /// Generalised forces `Σ Ψ(x_w)ᵀ f_w`.
    fn modal_force(&mut self, inputs: &[WheelInput]) -> Vec<f64> {
        let mut fq = Vec::new();
        self.modal_force_into(inputs, &mut fq);
        fq
    }

    /// [`Self::modal_force`] into `fq` (resized to the modes), through the shapes' own basis
    /// (`R` the rail map [`ModalBridge::rail_of`], so `Ψ(x)ᵀ f = φ(x)ᵀ (Rᵀ f)`):
    ///
    /// * nodal shapes, `φ(x) = Σⱼ wⱼ φⱼ` over the Lagrange stencil at `x`: the wheelsets'
    ///   `Rᵀ f` gathered at the nodes of their stencils, each node in use projected once;
    /// * sine shapes, `φₙ(x) = aₙ sin(kₙ θ)`: `Hₖ = Σ_w sin(k θ_w) Rᵀ f_w` for each
    ///   half-wave number `k`, then `Fₙ = aₙ · H_{kₙ}`.
    ///
    /// Either way a pass over the modes per node or per mode instead of per wheelset, and
    /// no shapes to evaluate.
    fn modal_force_into(&mut self, inputs: &[WheelInput], fq: &mut Vec<f64>) {
        let nb = self.omega.len();
        fq.clear();
        fq.resize(nb, 0.0);
        let mut c = self.cache.lock().expect("shape cache");
        c.fill(&self.bridge, &*self.track, inputs);
        if let Some((half_waves, amplitudes, kmax)) = self.bridge.sine_modes() {
            self.nodes.zeroed(kmax + 1);
            let BasisScratch { force, on_deck, .. } = &mut self.nodes;
            on_deck.clear();
            for (w, wi) in inputs.iter().enumerate() {
                if let Some(at) = c.sines_at(w, wi.x) {
                    let k = track_of(&self.tracks, w);
                    on_deck.push((at, self.bridge.deck_force_of_on(k, wi.f)));
                }
            }
            sine_forces(force, &c.sines, on_deck);
            let h = &self.nodes.force;
            for ((o, &k), a) in fq.iter_mut().zip(half_waves).zip(amplitudes) {
                let hk = h[k as usize];
                *o += a[0] * hk[0] + a[1] * hk[1] + a[2] * hk[2];
            }
            return;
        }
        if let Some((values, n_nodes)) = self.bridge.nodal_values() {
            let ns = &mut self.nodes;
            ns.begin(n_nodes);
            for (w, wi) in inputs.iter().enumerate() {
                if let (Some(st), _) = c.stencil(w, wi.x) {
                    let k = track_of(&self.tracks, w);
                    let g = self.bridge.deck_force_of_on(k, wi.f);
                    for j in 0..st.k {
                        let i = st.start + j;
                        ns.touch(i);
                        for (f, gc) in ns.force[i].iter_mut().zip(g) {
                            *f += st.w[j] * gc;
                        }
                    }
                }
            }
            ns.nodes.sort_unstable();
            for &i in &ns.nodes {
                crate::simd::project_force(fq, &values[i * nb..(i + 1) * nb], ns.force[i]);
            }
        }
    }

    /// Bridge at rest in its static response to the steady deck loads; initial
    /// acceleration from the inputs at t = 0.
    pub fn initialize(&mut self, inputs: &[WheelInput]) {
        let nb = self.omega.len();
        self.state.q = self.bridge.steady_response();
        self.state.qd = vec![0.0; nb];
        self.state.t = 0.0;
        let mut fq = self.modal_force(inputs);
        self.add_buffeting(0.0, &mut fq);
        self.state.qdd = (0..nb)
            .map(|n| fq[n] + self.bridge.steady(n) - self.omega[n].powi(2) * self.state.q[n])
            .collect();
    }

    /// One Newmark step of size `h` with end-of-step inputs.
    ///
    /// Solved for the new acceleration (`(1 + h/2 c + h²/4 k) q̈₁ = f − c q̇ₚ − k qₚ` with the
    /// predictors `qₚ`, `q̇ₚ`), which is the same Newmark step as solving for the new
    /// displacement but keeps the outputs accurate for communication steps far below the
    /// nominal one (the displacement form divides a round-off-sized difference by h²).
    pub fn step(&mut self, h: f64, inputs: &[WheelInput]) {
        let nm = Newmark::new(h);
        let mut fq = std::mem::take(&mut self.force);
        self.modal_force_into(inputs, &mut fq);
        let t1 = self.state.t + h;
        self.add_buffeting(t1, &mut fq);
        let s = &mut self.state;
        s.t = t1;
        for n in 0..fq.len() {
            let c = 2.0 * self.zeta[n] * self.omega[n];
            let k = self.omega[n] * self.omega[n];
            let (qp, qdp) = nm.predict(s.q[n], s.qd[n], s.qdd[n]);
            let f = fq[n] + self.bridge.steady(n);
            let a = (f - c * qdp - k * qp) / (1.0 + 0.5 * h * c + 0.25 * h * h * k);
            (s.q[n], s.qd[n]) = nm.correct((qp, qdp), a);
            s.qdd[n] = a;
        }
        self.force = fq;
        // where the wheelsets will be a step on: the track's data there is read next step
        for wi in inputs {
            self.track.prefetch(wi.x + wi.vx * h);
        }
    }

    /// Rail motion (u, u̇, ü) under wheelset slot `w` at `x`, moving at `vx`: deck plus
    /// irregularity.
    pub fn rail(&mut self, w: usize, x: f64, vx: f64) -> [Vector3<f64>; 3] {
        let input = WheelInput { x, vx, f: [0.0; 3] };
        let mut out = [Vector3::zeros(); 3];
        self.rails_of(std::slice::from_ref(&input), Some(w), |_, r| out = *r);
        out
    }

    /// [`Self::rail`] under every wheelset, wheelset `w` at `inputs[w]`: `f(w, motion)`.
    pub fn rails(&mut self, inputs: &[WheelInput], f: impl FnMut(usize, &[Vector3<f64>; 3])) {
        self.rails_of(inputs, None, f)
    }

    /// [`Self::rails`] through the shapes' own basis: the deck motion `(φ q, φ q̇, φ q̈)` of
    /// each basis function once — at each node in use (nodal shapes), or
    /// `Bₖ = Σ_{kₙ = k} aₙ (qₙ, q̇ₙ, q̈ₙ)` for each half-wave number `k` (sine shapes) — then
    /// at each wheelset its combination (the stencil's weights, or `sin(k θ)`), mapped to the
    /// rail ([`ModalBridge::rail_of`]) and added to the irregularity's. The inputs are those
    /// of wheelset slots `0, 1, …`, or of slot `slot` alone.
    fn rails_of(
        &mut self,
        inputs: &[WheelInput],
        slot: Option<usize>,
        mut f: impl FnMut(usize, &[Vector3<f64>; 3]),
    ) {
        let nb = self.omega.len();
        let s = &self.state;
        self.modal.clear();
        self.modal
            .extend((s.q.iter().zip(&s.qd).zip(&s.qdd)).map(|((&q, &qd), &qdd)| [q, qd, qdd, 0.0]));
        let slot_of = |w: usize| slot.unwrap_or(w);
        let mut c = self.cache.lock().expect("shape cache");
        match slot {
            Some(w) => {
                c.reserve(w + 1);
                if let Some(p) = c.claim(&*self.track, w, inputs[0].x) {
                    c.shapes_of(&self.bridge, &[p]);
                }
            }
            None => c.fill(&self.bridge, &*self.track, inputs),
        }
        if let Some((half_waves, amplitudes, kmax)) = self.bridge.sine_modes() {
            self.nodes.zeroed(kmax + 1);
            let b = &mut self.nodes.motion;
            for ((&k, a), m) in half_waves.iter().zip(amplitudes).zip(&self.modal) {
                let bk = &mut b[k as usize];
                for (bc, ac) in bk.iter_mut().zip(a) {
                    for (v, md) in bc.iter_mut().zip(m) {
                        *v += ac * md;
                    }
                }
            }
            let BasisScratch {
                motion: b,
                starts,
                deck,
                ..
            } = &mut self.nodes;
            starts.clear();
            starts.extend(
                (inputs.iter().enumerate()).filter_map(|(w, wi)| c.sines_at(slot_of(w), wi.x)),
            );
            sine_motions(deck, b, &c.sines, starts);
            let mut deck = deck.iter();
            for (w, wi) in inputs.iter().enumerate() {
                let (sines, irregularity) = c.sines(slot_of(w), wi.x);
                let mut r = rail_motion(irregularity, wi.vx);
                if sines.is_some() {
                    let acc = deck.next().expect("a deck motion per wheelset on the deck");
                    for (d, rd) in r.iter_mut().enumerate() {
                        let k = track_of(&self.tracks, slot_of(w));
                        let acc = [acc[0][d], acc[1][d], acc[2][d]];
                        *rd += Vector3::from(self.bridge.rail_of_on(k, acc));
                    }
                }
                f(slot_of(w), &r);
            }
            return;
        }
        let (values, n_nodes) = self.bridge.nodal_values().expect("nodal shapes");
        let ns = &mut self.nodes;
        ns.begin(n_nodes);
        for (w, wi) in inputs.iter().enumerate() {
            if let (Some(st), _) = c.stencil(slot_of(w), wi.x) {
                for j in 0..st.k {
                    ns.touch(st.start + j);
                }
            }
        }
        ns.node_motions(values, nb, &self.modal);
        for (w, wi) in inputs.iter().enumerate() {
            let (st, irregularity) = c.stencil(slot_of(w), wi.x);
            let mut r = rail_motion(irregularity, wi.vx);
            if let Some(st) = st {
                for (rd, d) in r.iter_mut().zip(ns.deck_motion(st)) {
                    let k = track_of(&self.tracks, slot_of(w));
                    *rd += Vector3::from(self.bridge.rail_of_on(k, d));
                }
            }
            f(slot_of(w), &r);
        }
    }

    /// The rail motion under every wheelset linearised at the current point: the partial
    /// derivatives a bridge FMU gives as its directional derivatives. With the seeds `dx`,
    /// `dv`, `df` of each wheelset's position, speed and force (`seeds[w]`) and `duw` of the
    /// turbulence at the deck points:
    ///
    /// ```text
    /// d(u, u̇, ü)_w = [Ψ′(x_w)(q, q̇, q̈) + (r′, v r″, v² r‴)] dx_w + (0, r′, 2 v r″) dv_w
    /// ```
    ///
    /// (`rail_motion_slope`; Ψ′ = [`ModalBridge::rail_shape_slopes`]). At a communication point
    /// the state is fixed and the forces act only through the next step. While `initializing`
    /// the acceleration follows the loads ([`Self::initialize`]), so also
    ///
    /// ```text
    /// dq̈ = Σ_w [Ψ(x_w)ᵀ df_w + Ψ′(x_w)ᵀ f_w dx_w] + B duw ,   d ü_w += Ψ(x_w) dq̈ ,
    /// ```
    ///
    /// `B` the buffeting forces' linear map. Calls `f(w, d(u, u̇, ü)_w)` and returns `dq̈`
    /// (zeros at a communication point).
    pub fn linearised_rails(
        &self,
        inputs: &[WheelInput],
        seeds: &[WheelInput],
        deck_wind_seed: Option<&[[f64; 2]]>,
        initializing: bool,
        mut f: impl FnMut(usize, &[Vector3<f64>; 3]),
    ) -> Vec<f64> {
        let bridge = &self.bridge;
        let nb = bridge.n_modes();
        let (mut psi, mut dpsi) = (vec![[0.0; 3]; nb], vec![[0.0; 3]; nb]);
        let mut dqdd = vec![0.0; nb];
        if initializing {
            for (w, (wi, si)) in inputs.iter().zip(seeds).enumerate() {
                let k = track_of(&self.tracks, w);
                if bridge.rail_shapes_on(k, wi.x, &mut psi) {
                    bridge.rail_shape_slopes_on(k, wi.x, &mut dpsi);
                    for n in 0..nb {
                        for k in 0..3 {
                            dqdd[n] += psi[n][k] * si.f[k] + dpsi[n][k] * wi.f[k] * si.x;
                        }
                    }
                }
            }
            if let (Some(b), Some(duw)) = (&self.buffeting, deck_wind_seed) {
                b.add_modal_force_from(duw, &mut dqdd);
            }
        }
        let s = &self.state;
        for (w, (wi, si)) in inputs.iter().zip(seeds).enumerate() {
            let (mut by_x, by_v) = crate::track::rail_motion_slope(
                &self.track.at(wi.x),
                self.track.third_derivative(wi.x),
                wi.vx,
            );
            let k = track_of(&self.tracks, w);
            let on = bridge.rail_shapes_on(k, wi.x, &mut psi);
            if on {
                bridge.rail_shape_slopes_on(k, wi.x, &mut dpsi);
                for n in 0..nb {
                    for k in 0..3 {
                        by_x[0][k] += dpsi[n][k] * s.q[n];
                        by_x[1][k] += dpsi[n][k] * s.qd[n];
                        by_x[2][k] += dpsi[n][k] * s.qdd[n];
                    }
                }
            }
            let mut d = [0, 1, 2].map(|i| by_x[i] * si.x + by_v[i] * si.vx);
            if on && initializing {
                for n in 0..nb {
                    for k in 0..3 {
                        d[2][k] += psi[n][k] * dqdd[n];
                    }
                }
            }
            f(w, &d);
        }
        dqdd
    }

    /// Deck response at `x` (the deck shapes there kept for the next call: probes stay put).
    pub fn probe(&mut self, x: f64) -> ProbeValues {
        let mut c = self.cache.lock().expect("shape cache");
        let shapes = c.probe(&self.bridge, self.omega.len(), x);
        ProbeValues::from_shapes(shapes, &self.state.q, &self.state.qdd)
    }
}

/// The track of wheelset slot `w` (0 beyond the list: an empty list is one track).
#[inline]
fn track_of(tracks: &[usize], w: usize) -> usize {
    tracks.get(w).copied().unwrap_or(0)
}
