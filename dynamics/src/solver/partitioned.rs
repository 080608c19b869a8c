//! The two partitions of eq. (14), each advanced by its own Newmark step with the coupling
//! quantities of the *end* of the step as inputs.
//!
//! * [`BridgeSide`] (bridge plus track): inputs per wheelset — position `x`, speed `ẋ` and the
//!   force on the rail `f = (F_y, M_x, F_z)`; it integrates `q̈ + 2ζω q̇ + ω² q = Σ Ψ(x)ᵀ f` and
//!   outputs the rail motion under each wheelset, deck plus irregularity:
//!   `u = Ψ(x) q + r(x)`, `u̇ = Ψ q̇ + ẋ r′`, `ü = Ψ q̈ + ẋ² r″`. It forms `Σ Ψᵀ f` and
//!   `Ψ (q, q̇, q̈)` through the shapes' own basis, `Ψ(x) = R Σ_b β_b(x) φ_b` (`R` the rail
//!   map): the nodes of the Lagrange stencil at `x` (nodal shapes, `β` its weights) or the
//!   half-wave numbers (sine shapes, `β_k = sin(kπ(x − x₀)/L)`), each basis function in use
//!   once per sweep instead of every mode under every wheelset.
//! * [`TrainSide`]: inputs per wheelset — that rail motion; it adds wheel hunting, integrates
//!   every vehicle and outputs positions and the wheel forces of eq. (6).
//!
//! When an interface iteration converges, both partitions satisfy their equations at
//! `t + h` with the same interface values, which is exactly the monolithic Newmark step of
//! eq. (14): the co-simulation and the monolithic solution coincide to the iteration
//! tolerance.

use super::{add_hunting, VehicleState, WheelForce};
use crate::bridge::{ModalBridge, SHAPE_LANES};
use crate::newmark::Newmark;
use crate::sparse::{Csr, SparseCholesky};
use crate::track::{rail_motion, RailProfile};
use crate::train::{Train, WheelsetRef};
use crate::vehicle::aero::WindBody;
use crate::vehicle::LinearVehicle;
use nalgebra::{DVector, Vector3};
use serde::{Deserialize, Serialize};
use std::sync::{Arc, Mutex};
use tbi_track::RailIrregularity;

/// The inputs of one wheelset to the bridge.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct WheelInput {
    /// Position along the track, m.
    pub x: f64,
    /// Speed along the track, m/s.
    pub vx: f64,
    /// Force on the rail (F_y N, M_x N·m, F_z N).
    pub f: [f64; 3],
}

/// Deck response at a probe (shear centre).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ProbeValues {
    /// Lateral displacement, m.
    pub y: f64,
    /// Vertical displacement, m (+ down).
    pub z: f64,
    /// Torsion, rad.
    pub theta: f64,
    /// Lateral acceleration, m/s².
    pub y_dd: f64,
    /// Vertical acceleration, m/s².
    pub z_dd: f64,
}

impl ProbeValues {
    /// Deck response from the deck shapes `(φ_h, φ_v, φ_θ)` at the probe and the modal
    /// displacements and accelerations.
    pub fn from_shapes(shapes: &[[f64; 3]], q: &[f64], qdd: &[f64]) -> Self {
        let mut p = ProbeValues::default();
        for (n, sh) in shapes.iter().enumerate() {
            p.y += sh[0] * q[n];
            p.z += sh[1] * q[n];
            p.theta += sh[2] * q[n];
            p.y_dd += sh[0] * qdd[n];
            p.z_dd += sh[1] * qdd[n];
        }
        p
    }
}

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
        super::share(&mut self.bridge, &source.bridge);
        super::share(&mut self.track, &source.track);
        self.state.clone_from(&source.state);
        super::share(&mut self.omega, &source.omega);
        super::share(&mut self.zeta, &source.zeta);
        super::share(&mut self.cache, &source.cache);
        match (&mut self.buffeting, &source.buffeting) {
            (Some(to), Some(from)) => super::share(to, from),
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
                    on_deck.push((at, self.bridge.deck_force_of(wi.f)));
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
                    let g = self.bridge.deck_force_of(wi.f);
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
                        *rd +=
                            Vector3::from(self.bridge.rail_of([acc[0][d], acc[1][d], acc[2][d]]));
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
                    *rd += Vector3::from(self.bridge.rail_of(d));
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
            for (wi, si) in inputs.iter().zip(seeds) {
                if bridge.rail_shapes(wi.x, &mut psi) {
                    bridge.rail_shape_slopes(wi.x, &mut dpsi);
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
            let on = bridge.rail_shapes(wi.x, &mut psi);
            if on {
                bridge.rail_shape_slopes(wi.x, &mut dpsi);
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

/// Newmark factor of one vehicle for one step size, and the response of its new
/// acceleration to the rail motion.
#[derive(Debug, Clone)]
struct Factor {
    h: f64,
    /// `K̂⁻¹ e_d` of each DOF `d` the wind loads (the car body's, [`WindBody::of`]; none
    /// without one): the wind's share of the new acceleration, `a0 K̂⁻¹ F₁ = Σ_d (a0 F₁)_d
    /// K̂⁻¹ e_d`, five products of n values instead of a solve with the factor.
    wind: Vec<(usize, Vec<f64>)>,
    /// `G_l = −a0 K̂⁻¹ [K_vw,l  C_vw,l]` of each wheelset `l`, `n × 6` column-major, wheelset
    /// after wheelset: the new acceleration is `v̈₁ = b + Σ_l G_l (u_l, u̇_l)` with `b` from
    /// the state at the start of the step ([`StepBase`]).
    gain: Vec<f64>,
    /// `E = −a0 K̂⁻¹ [K   C + h K   h/2 C + h²/4 K]`, `n × 3n` column-major: the part of the
    /// new acceleration that follows from the state, `b = E (v, v̇, v̈)` ([`StepBase`]).
    base: Vec<f64>,
}

impl Factor {
    fn of(model: &LinearVehicle, sp: &VehicleSparse, h: f64) -> Factor {
        let nm = Newmark::new(h);
        let n = model.ndof();
        let khat = nm.a0 * &model.m + nm.a1 * &model.c + &model.k;
        let chol = SparseCholesky::of(
            &khat
                .cholesky()
                .expect("a0 M + a1 C + K is positive definite"),
        );
        let mut gain = vec![0.0; 6 * n * model.wheelsets.len()];
        let mut unit = [0.0; 3];
        for (l, g) in gain.chunks_exact_mut(6 * n).enumerate() {
            for (c, col) in g.chunks_exact_mut(n).enumerate() {
                let m = if c < 3 { &sp.kvw[l] } else { &sp.cvw[l] };
                unit.fill(0.0);
                unit[c % 3] = 1.0;
                m.mul_add(-nm.a0, &unit, col);
                chol.solve_mut(col);
            }
        }
        // vₚ = v + h v̇ + h²/4 v̈ and v̇ₚ = v̇ + h/2 v̈ in C v̇ₚ + K vₚ, column by column
        let mut base = vec![0.0; 3 * n * n];
        let mut unit = vec![0.0; n];
        for (j, col) in base.chunks_exact_mut(n).enumerate() {
            let (part, dof) = (j / n, j % n);
            let (ck, cc) = match part {
                0 => (1.0, 0.0),
                1 => (h, 1.0),
                _ => (0.25 * h * h, 0.5 * h),
            };
            unit.fill(0.0);
            unit[dof] = 1.0;
            sp.k.mul_add(-nm.a0 * ck, &unit, col);
            if cc != 0.0 {
                sp.c.mul_add(-nm.a0 * cc, &unit, col);
            }
            chol.solve_mut(col);
        }
        let wind = WindBody::unit_responses(model, |e| chol.solve_mut(e));
        Factor {
            h,
            wind,
            gain,
            base,
        }
    }
}

/// The part of a vehicle's step that does not depend on the rail motion: the predictors
/// `vₚ = v + h v̇ + h²/4 v̈`, `v̇ₚ = v̇ + h/2 v̈` and `b = −a0 K̂⁻¹ (C v̇ₚ + K vₚ)` (as one
/// product `E (v, v̇, v̈)` with the factor's dense [`Factor::base`]), kept for the
/// state (bit for bit) and step size they were made from. An iterating master steps from the
/// same state again and again; each repetition then costs only the rail-motion terms.
#[derive(Debug, Clone, Default)]
struct StepBase {
    h: f64,
    /// `(v, v̇, v̈)` of the state, one after the other.
    key: Vec<f64>,
    vp: Vec<f64>,
    vdp: Vec<f64>,
    b: Vec<f64>,
}

impl StepBase {
    fn matches(&self, h: f64, s: &VehicleState) -> bool {
        let n = s.v.len();
        // the differing bits of all values at once (no early exit: it runs in vector
        // registers, and a repeated step, the usual case, compares every value anyway)
        let differ = |a: &[f64], b: &[f64]| {
            (a.iter().zip(b)).fold(0, |acc, (x, y)| acc | (x.to_bits() ^ y.to_bits()))
        };
        self.h.to_bits() == h.to_bits()
            && self.key.len() == 3 * n
            && [&s.v, &s.vd, &s.vdd]
                .iter()
                .zip(self.key.chunks_exact(n))
                .fold(0, |acc, (a, b)| acc | differ(a.as_slice(), b))
                == 0
    }

    fn make(&mut self, h: f64, s: &VehicleState, factor: &Factor) {
        self.h = h;
        self.key.clear();
        for part in [&s.v, &s.vd, &s.vdd] {
            self.key.extend_from_slice(part.as_slice());
        }
        let (v, vd, vdd) = (s.v.as_slice(), s.vd.as_slice(), s.vdd.as_slice());
        self.vp.clear();
        self.vp
            .extend((v.iter().zip(vd).zip(vdd)).map(|((v, vd), a)| v + h * vd + 0.25 * h * h * a));
        self.vdp.clear();
        self.vdp
            .extend((vd.iter().zip(vdd)).map(|(vd, a)| vd + 0.5 * h * a));
        self.b.clear();
        self.b.resize(s.v.len(), 0.0);
        crate::simd::axpy_columns(&mut self.b, &self.key, &factor.base);
    }
}

/// A vehicle's constant matrices in sparse rows: C, K and each wheelset's K_vw, C_vw.
#[derive(Debug, Clone)]
struct VehicleSparse {
    c: Csr,
    k: Csr,
    kvw: Vec<Csr>,
    cvw: Vec<Csr>,
}

impl VehicleSparse {
    fn of(model: &LinearVehicle) -> Self {
        VehicleSparse {
            c: Csr::of(&model.c),
            k: Csr::of(&model.k),
            kvw: model.wheelsets.iter().map(|w| Csr::of(&w.k_vw)).collect(),
            cvw: model.wheelsets.iter().map(|w| Csr::of(&w.c_vw)).collect(),
        }
    }
}

/// The train (see the module docs).
#[derive(Debug)]
pub struct TrainSide {
    pub train: Arc<Train>,
    pub wheelsets: Arc<Vec<WheelsetRef>>,
    pub states: Vec<VehicleState>,
    /// Total rail motion (with hunting) used for the current state, per wheelset.
    pub rails: Vec<[Vector3<f64>; 3]>,
    /// Current time, s.
    pub t: f64,
    /// Along-wind turbulence u at each car body's centre, m/s, at the end of the coming step
    /// (at `t` before initialisation): the train FMU's inputs `veh[i].u`; zero in a steady
    /// wind ([`crate::vehicle::aero::TrainWind`]).
    pub body_wind: Vec<f64>,
    /// Newmark factors per vehicle (derived from the model and h only; shared by clones,
    /// copied on the rare write). Only the entries `model_of` names are used.
    factors: Arc<Vec<Factor>>,
    /// The vehicles' matrices in sparse rows (derived from the model; shared by clones).
    /// Only the entries `model_of` names are used.
    sparse: Arc<Vec<VehicleSparse>>,
    /// Per vehicle, the first vehicle with the same model ([`Train::first_of_same_model`]):
    /// its factor and sparse rows serve both, so a step reads one copy of them.
    model_of: Arc<Vec<usize>>,
    /// Per wheelset, what its force needs (derived from the model; shared by clones, and by
    /// the wheelsets at the same place of vehicles of one model).
    forces: Arc<Vec<Arc<WheelForce>>>,
    /// The rail-independent part of the last step of each vehicle (derived data keyed by
    /// the state it was made from: kept through a rollback, which restores that state).
    bases: Vec<StepBase>,
    /// Scratch vector of a step per vehicle (the wind's share of the acceleration).
    work: Vec<DVector<f64>>,
    /// Scratch of a step: the rail terms `(u, u̇)` of up to eight wheelsets, one after the
    /// other (written before they are read).
    uv: Vec<f64>,
    /// The hunting motion of every wheelset at the end of the last step asked for (derived
    /// data keyed by the time and the train: an iterating master repeats a step many times).
    hunting: HuntingCache,
}

/// The hunting motion `(Y_h, Ẏ_h, Ÿ_h)` of each wheelset at one time, for one train.
#[derive(Debug, Clone, Default)]
struct HuntingCache {
    /// Bits of the time and address of the train it was made for.
    key: Option<(u64, usize)>,
    values: Vec<[f64; 3]>,
}

impl HuntingCache {
    /// The hunting motion of each of the `n` wheelsets of `train` at time `t`.
    fn at(&mut self, train: &Arc<Train>, n: usize, t: f64) -> &[[f64; 3]] {
        let key = (t.to_bits(), Arc::as_ptr(train) as usize);
        if self.key != Some(key) || self.values.len() != n {
            let v = train.speed_m_s;
            self.values.clear();
            self.values
                .extend((0..n).map(|w| crate::track::hunting_motion(&train.hunting, w, v * t, v)));
            self.key = Some(key);
        }
        &self.values
    }
}

impl Clone for TrainSide {
    fn clone(&self) -> Self {
        TrainSide {
            train: self.train.clone(),
            wheelsets: self.wheelsets.clone(),
            states: self.states.clone(),
            rails: self.rails.clone(),
            t: self.t,
            body_wind: self.body_wind.clone(),
            factors: self.factors.clone(),
            sparse: self.sparse.clone(),
            model_of: self.model_of.clone(),
            forces: self.forces.clone(),
            bases: self.bases.clone(),
            work: self.work.clone(),
            uv: Vec::new(),
            hunting: self.hunting.clone(),
        }
    }

    /// Reuses this side's allocations (the rollback of an FMU copies states, not models;
    /// the step bases stay, as they are keyed by the state they were made from).
    fn clone_from(&mut self, source: &Self) {
        super::share(&mut self.train, &source.train);
        super::share(&mut self.wheelsets, &source.wheelsets);
        self.states.clone_from(&source.states);
        self.rails.clone_from(&source.rails);
        self.t = source.t;
        self.body_wind.clone_from(&source.body_wind);
        super::share(&mut self.factors, &source.factors);
        super::share(&mut self.sparse, &source.sparse);
        super::share(&mut self.model_of, &source.model_of);
        super::share(&mut self.forces, &source.forces);
    }
}

impl TrainSide {
    pub fn new(train: Arc<Train>) -> Self {
        let wheelsets = train.wheelsets();
        let nw = wheelsets.len();
        TrainSide {
            states: train
                .vehicles
                .iter()
                .map(|tv| {
                    VehicleState::initial(
                        &tv.model,
                        &vec![[Vector3::zeros(); 3]; tv.model.wheelsets.len()],
                    )
                })
                .collect(),
            factors: Arc::new(vec![
                Factor {
                    h: f64::NAN,
                    wind: Vec::new(),
                    gain: Vec::new(),
                    base: Vec::new(),
                };
                train.vehicles.len()
            ]),
            rails: vec![[Vector3::zeros(); 3]; nw],
            sparse: Arc::new(
                train
                    .vehicles
                    .iter()
                    .map(|tv| VehicleSparse::of(&tv.model))
                    .collect(),
            ),
            model_of: Arc::new(train.first_of_same_model()),
            forces: Arc::new(WheelForce::of_train(&train, &wheelsets)),
            bases: vec![StepBase::default(); train.vehicles.len()],
            uv: Vec::new(),
            work: train
                .vehicles
                .iter()
                .map(|tv| DVector::zeros(tv.model.ndof()))
                .collect(),
            body_wind: vec![0.0; train.vehicles.len()],
            wheelsets: Arc::new(wheelsets),
            train,
            t: 0.0,
            hunting: HuntingCache::default(),
        }
    }

    /// Position of wheelset `w` at time `t`, m.
    pub fn x(&self, w: usize, t: f64) -> f64 {
        self.train.x_at(self.wheelsets[w].offset_m, t)
    }

    /// Static equilibrium at time `t` on the given rail motion (deck plus irregularity).
    pub fn initialize(&mut self, t: f64, rails: &[[Vector3<f64>; 3]]) {
        self.t = t;
        let hunting = self.hunting.at(&self.train, rails.len(), t);
        self.rails = (rails.iter().zip(hunting))
            .map(|(r, h)| add_hunting(r, h))
            .collect();
        let mut first = 0;
        for (i, tv) in self.train.vehicles.iter().enumerate() {
            let nw = tv.model.wheelsets.len();
            let f = self.train.wind_force(i, t, self.body_wind[i]);
            self.states[i] =
                VehicleState::initial_loaded(&tv.model, &self.rails[first..first + nw], f.as_ref());
            first += nw;
        }
    }

    /// One Newmark step from `self.t` to `self.t + h` with the end-of-step rail motion.
    pub fn step(&mut self, h: f64, rails: &[[Vector3<f64>; 3]]) {
        let t1 = self.t + h;
        let nm = Newmark::new(h);
        let hunting = self.hunting.at(&self.train, rails.len(), t1);
        for ((out, rail), h) in self.rails.iter_mut().zip(rails).zip(hunting) {
            *out = add_hunting(rail, h);
        }
        let mut first = 0;
        for (i, tv) in self.train.vehicles.iter().enumerate() {
            let model: &LinearVehicle = &tv.model;
            let nw = model.wheelsets.len();
            let n = model.ndof();
            if n > 0 {
                let f = self.model_of[i];
                if self.factors[f].h != h {
                    Arc::make_mut(&mut self.factors)[f] = Factor::of(model, &self.sparse[f], h);
                }
                // Solved for the new acceleration (see BridgeSide::step):
                // (M + h/2 C + h²/4 K) v̈₁ = F₁ − C v̇ₚ − K vₚ − Σ_l (K_vw u + C_vw u̇)_l, and
                // M + h/2 C + h²/4 K is h²/4 times the factorised K̂ = a0 M + a1 C + K, so
                // v̈₁ = b + Σ_l G_l (u_l, u̇_l) + a0 K̂⁻¹ F₁ (Factor::gain, StepBase); then
                // v = vₚ + h²/4 v̈₁, v̇ = v̇ₚ + h/2 v̈₁.
                let factor = &self.factors[f];
                let s = &mut self.states[i];
                let base = &mut self.bases[i];
                if !base.matches(h, s) {
                    base.make(h, s, factor);
                }
                let a = s.vdd.as_mut_slice();
                a.copy_from_slice(&base.b);
                // Σ_l G_l (u_l, u̇_l) as one sum over the columns of up to eight wheelsets
                // at a time (column after column, as wheelset after wheelset would add them)
                let uv = &mut self.uv;
                uv.resize(6 * 8, 0.0);
                for (g, rails) in (factor.gain[..6 * n * nw].chunks(6 * n * 8))
                    .zip(self.rails[first..first + nw].chunks(8))
                {
                    for (c, r) in uv.chunks_exact_mut(6).zip(rails) {
                        c.copy_from_slice(&[r[0].x, r[0].y, r[0].z, r[1].x, r[1].y, r[1].z]);
                    }
                    crate::simd::axpy_columns(a, &uv[..6 * rails.len()], g);
                }
                if self.train.wind.is_some() {
                    // the wind on the body beyond its static loads, F₁
                    let w = &mut self.work[i];
                    w.fill(0.0);
                    self.train
                        .add_wind_force(i, t1, self.body_wind[i], nm.a0, w);
                    WindBody::add_responses(&factor.wind, w.as_slice(), a);
                }
                let (v, vd, a) = (s.v.as_mut_slice(), s.vd.as_mut_slice(), s.vdd.as_slice());
                for (((v, vd), a), (vp, vdp)) in
                    (v.iter_mut().zip(vd.iter_mut()).zip(a)).zip(base.vp.iter().zip(&base.vdp))
                {
                    *v = vp + 0.25 * h * h * a;
                    *vd = vdp + 0.5 * h * a;
                }
            }
            first += nw;
        }
        self.t = t1;
    }

    /// Force of wheelset `w` on the rail for the current state: eq. (6) as
    /// [`LinearVehicle::wheel_force`], with `K_wv v + C_wv v̇` from the non-zero entries of
    /// `K_wv`, `C_wv` (a wheelset couples to a few of its vehicle's DOFs).
    pub fn force(&self, w: usize) -> Vector3<f64> {
        self.forces[w].force(&self.states[self.wheelsets[w].vehicle], &self.rails[w])
    }
}

/// `h[k] ← Σ_w sin(k θ_w) g_w` from zero, over the wheelsets `w` in turn (`(at, g)`: the
/// sines of its position for `k = 0 ..` from `sines[at]` on, and its force on the deck): the
/// forces gathered per half-wave number. With AVX2 and at most twelve half-wave numbers the sums stay in registers, the
/// half-wave numbers side by side, instead of being loaded and stored for every wheelset;
/// each `h[k][c]` takes the same products in the same order (bit for bit the same).
fn sine_forces(h: &mut [[f64; 3]], sines: &[f64], wheelsets: &[(usize, [f64; 3])]) {
    #[cfg(target_arch = "x86_64")]
    if h.len() <= 12 && std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above)
        unsafe {
            match h.len().div_ceil(4) {
                0 => {}
                1 => sine_forces_avx2::<1>(h, sines, wheelsets),
                2 => sine_forces_avx2::<2>(h, sines, wheelsets),
                _ => sine_forces_avx2::<3>(h, sines, wheelsets),
            }
        }
        return;
    }
    sine_forces_body(h, sines, wheelsets)
}

fn sine_forces_body(h: &mut [[f64; 3]], sines: &[f64], wheelsets: &[(usize, [f64; 3])]) {
    h.fill([0.0; 3]);
    let n = h.len();
    for &(at, g) in wheelsets {
        for (hk, &sk) in h.iter_mut().zip(&sines[at..at + n]) {
            for (hc, gc) in hk.iter_mut().zip(g) {
                *hc += sk * gc;
            }
        }
    }
}

/// [`sine_forces`] with `h.len() ≤ 4 V` half-wave numbers in `V` vectors per component.
///
/// # Safety
/// AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sine_forces_avx2<const V: usize>(
    h: &mut [[f64; 3]],
    sines: &[f64],
    wheelsets: &[(usize, [f64; 3])],
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_maskload_pd, _mm256_mul_pd, _mm256_set1_pd,
        _mm256_setzero_pd, _mm256_storeu_pd,
    };
    let n = h.len();
    let last = n - 4 * (V - 1); // 1..=4 values in the last vector
                                // SAFETY: AVX2, as this function
    let mask = unsafe { crate::simd::first_lanes(last) };
    let mut acc = [[_mm256_setzero_pd(); V]; 3];
    for &(at, g) in wheelsets {
        let sines = &sines[at..at + n];
        let p = sines.as_ptr();
        let gv = [
            _mm256_set1_pd(g[0]),
            _mm256_set1_pd(g[1]),
            _mm256_set1_pd(g[2]),
        ];
        for v in 0..V {
            // SAFETY: values 4 v .. 4 v + 4 of `sines` (n of them), the last vector's lanes
            // past n masked off
            let sv = unsafe {
                if v + 1 < V || last == 4 {
                    _mm256_loadu_pd(p.add(4 * v))
                } else {
                    _mm256_maskload_pd(p.add(4 * v), mask)
                }
            };
            for (ac, gc) in acc.iter_mut().zip(gv) {
                ac[v] = _mm256_add_pd(ac[v], _mm256_mul_pd(sv, gc));
            }
        }
    }
    let mut out = [[0.0; 12]; 3];
    for (o, ac) in out.iter_mut().zip(acc) {
        for (v, a) in ac.into_iter().enumerate() {
            // SAFETY: 4 values from 4 v < 12 of a 12-value array
            unsafe { _mm256_storeu_pd(o.as_mut_ptr().add(4 * v), a) };
        }
    }
    for (k, hk) in h.iter_mut().enumerate() {
        *hk = [out[0][k], out[1][k], out[2][k]];
    }
}

/// `out[i] ← Σₖ sin(k θᵢ) b[k]` from zero, `k = 0, 1, …` in turn, for the wheelsets `i` on
/// the deck (`starts[i]`: where their sines start in `sines`): the deck motion under
/// each, `b[k]` the deck motion of half-wave number `k` (deck components × `(u, u̇, ü, 0)`).
/// With AVX2 a component's four values are one vector; each value takes the same products
/// in the same order as the scalar loop (bit for bit the same).
fn sine_motions(
    out: &mut Vec<[[f64; 4]; 3]>,
    b: &[[[f64; 4]; 3]],
    sines: &[f64],
    starts: &[usize],
) {
    out.clear();
    out.resize(starts.len(), [[0.0; 4]; 3]);
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above)
        unsafe { sine_motions_avx2(out, b, sines, starts) };
        return;
    }
    sine_motions_body(out, b, sines, starts)
}

fn sine_motions_body(
    out: &mut [[[f64; 4]; 3]],
    b: &[[[f64; 4]; 3]],
    sines: &[f64],
    starts: &[usize],
) {
    for (acc, &at) in out.iter_mut().zip(starts) {
        for (sk, bk) in sines[at..at + b.len()].iter().zip(b) {
            for (ac, bc) in acc.iter_mut().zip(bk) {
                for (v, bv) in ac.iter_mut().zip(bc) {
                    *v += sk * bv;
                }
            }
        }
    }
}

/// [`sine_motions`] with a component's `(u, u̇, ü, 0)` in one vector.
///
/// # Safety
/// AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sine_motions_avx2(
    out: &mut [[[f64; 4]; 3]],
    b: &[[[f64; 4]; 3]],
    sines: &[f64],
    starts: &[usize],
) {
    use std::arch::x86_64::{
        _mm256_add_pd, _mm256_loadu_pd, _mm256_mul_pd, _mm256_set1_pd, _mm256_setzero_pd,
        _mm256_storeu_pd,
    };
    for (o, &at) in out.iter_mut().zip(starts) {
        let mut acc = [_mm256_setzero_pd(); 3];
        for (&sk, bk) in sines[at..at + b.len()].iter().zip(b) {
            let s = _mm256_set1_pd(sk);
            for (ac, bc) in acc.iter_mut().zip(bk) {
                // SAFETY: four values of a four-value array
                let bv = unsafe { _mm256_loadu_pd(bc.as_ptr()) };
                *ac = _mm256_add_pd(*ac, _mm256_mul_pd(s, bv));
            }
        }
        for (oc, ac) in o.iter_mut().zip(acc) {
            // SAFETY: four values of a four-value array
            unsafe { _mm256_storeu_pd(oc.as_mut_ptr(), ac) };
        }
    }
}

/// A Lagrange stencil of nodal shapes: `φ(x) = Σⱼ w[j] φ(node start + j)`, `j < k`.
#[derive(Debug, Clone, Copy, Default)]
struct Stencil {
    start: usize,
    w: [f64; 8],
    k: usize,
}

/// Scratch of [`BridgeSide::modal_force_into`] and [`BridgeSide::rails`]: per basis function
/// (node, or half-wave number) the wheelsets' forces gathered there (deck components) and
/// the deck motion `(φ q, φ q̇, φ q̈)` there, and the nodes in use, ascending once sorted.
#[derive(Debug, Default)]
struct BasisScratch {
    force: Vec<[f64; 3]>,
    motion: Vec<[[f64; 4]; 3]>,
    used: Vec<bool>,
    nodes: Vec<usize>,
    /// Sine shapes: the wheelsets on the deck, as the start of their sines in the shape
    /// cache and their force on the deck ([`sine_forces`]).
    on_deck: Vec<(usize, [f64; 3])>,
    /// Sine shapes: where the sines of each wheelset on the deck start in the shape cache,
    /// and the deck motion under it ([`sine_motions`]).
    starts: Vec<usize>,
    deck: Vec<[[f64; 4]; 3]>,
}

impl BasisScratch {
    /// No node in use, room for `n` nodes.
    fn begin(&mut self, n: usize) {
        for &i in &self.nodes {
            self.used[i] = false;
        }
        self.nodes.clear();
        if self.used.len() < n {
            self.used.resize(n, false);
            self.force.resize(n, [0.0; 3]);
            self.motion.resize(n, [[0.0; 4]; 3]);
        }
    }

    /// Every basis function `0..n` zero (the half-wave numbers of sine shapes, all in use);
    /// the forces.
    fn zeroed(&mut self, n: usize) -> &mut [[f64; 3]] {
        self.force.clear();
        self.force.resize(n, [0.0; 3]);
        self.motion.clear();
        self.motion.resize(n, [[0.0; 4]; 3]);
        self.used.clear();
        self.nodes.clear();
        &mut self.force
    }

    /// Node `i` in use (its force and motion zero when it is new).
    fn touch(&mut self, i: usize) {
        if !self.used[i] {
            self.used[i] = true;
            self.nodes.push(i);
            self.force[i] = [0.0; 3];
            self.motion[i] = [[0.0; 4]; 3];
        }
    }

    /// The deck motion of every node in use from the node values and `modal` (`(q, q̇, q̈, 0)`
    /// of each mode), two nodes at a time; sorts the nodes.
    fn node_motions(&mut self, values: &[[f64; 3]], nb: usize, modal: &[[f64; 4]]) {
        self.nodes.sort_unstable();
        let of = |i: usize| &values[i * nb..(i + 1) * nb];
        for pair in self.nodes.chunks(2) {
            if let [a, b] = *pair {
                let mut acc = [self.motion[a], self.motion[b]];
                crate::simd::rail_accumulate_pair(&mut acc, [of(a), of(b)], modal);
                [self.motion[a], self.motion[b]] = acc;
            } else {
                crate::simd::rail_accumulate(&mut self.motion[pair[0]], of(pair[0]), modal);
            }
        }
    }

    /// The deck motion `(u, u̇, ü)` (deck components) at a stencil from the node motions.
    fn deck_motion(&self, st: &Stencil) -> [[f64; 3]; 3] {
        let mut d = [[0.0; 3]; 3];
        for j in 0..st.k {
            let m = &self.motion[st.start + j];
            for (dd, out) in d.iter_mut().enumerate() {
                for (c, o) in out.iter_mut().enumerate() {
                    *o += st.w[j] * m[c][dd];
                }
            }
        }
        d
    }
}

/// The shapes' basis and the track irregularity at the last two positions of each wheelset
/// slot (the positions at the start and at the end of the current step are what an iterating
/// master asks for): for nodal shapes the Lagrange stencil, for sine shapes `sin(k θ)`.
#[derive(Debug, Default)]
struct ShapeCache {
    /// Per slot: two entries (x bits, on deck); entry `2 w + slot`.
    keys: Vec<[(u64, bool); 2]>,
    /// Per entry, for nodal shapes: the stencil ([`ModalBridge::nodal_stencil`]).
    stencils: Vec<Stencil>,
    /// Per entry, for sine shapes: `sin(k θ)`, `k = 0 ..= kmax` (`stride = kmax + 1` values).
    sines: Vec<f64>,
    stride: usize,
    /// Per slot and entry: the irregularity at that position.
    irregularity: Vec<[RailIrregularity; 2]>,
    next: Vec<usize>,
    /// Deck shapes at the probe positions asked for (x bits, shapes).
    probes: Vec<(u64, Vec<[f64; 3]>)>,
    /// Scratch of [`ModalBridge::sines_lanes`].
    lanes: Vec<[f64; SHAPE_LANES]>,
}

impl ShapeCache {
    /// The deck shapes at probe position `x`.
    fn probe(&mut self, bridge: &ModalBridge, nb: usize, x: f64) -> &[[f64; 3]] {
        let bits = x.to_bits();
        let i = match self.probes.iter().position(|p| p.0 == bits) {
            Some(i) => i,
            None => {
                let mut shapes = vec![[0.0; 3]; nb];
                bridge.deck_shapes(x, &mut shapes);
                self.probes.push((bits, shapes));
                self.probes.len() - 1
            }
        };
        &self.probes[i].1
    }

    /// Room for wheelset slots `0..n`.
    fn reserve(&mut self, n: usize) {
        if self.keys.len() < n {
            self.keys.resize(n, [(f64::NAN.to_bits(), false); 2]);
            self.next.resize(n, 0);
            self.stencils.resize(2 * n, Stencil::default());
            self.irregularity
                .resize(n, [RailIrregularity::default(); 2]);
        }
    }

    /// Makes the entries of every wheelset slot `w` at `inputs[w].x` ([`Self::claim`]), the
    /// basis of the misses [`SHAPE_LANES`] at a time ([`Self::shapes_of`]).
    fn fill(&mut self, bridge: &ModalBridge, track: &dyn RailProfile, inputs: &[WheelInput]) {
        self.reserve(inputs.len());
        let mut pending = [(0usize, 0.0f64); SHAPE_LANES];
        let mut m = 0;
        for (w, wi) in inputs.iter().enumerate() {
            if let Some(p) = self.claim(track, w, wi.x) {
                pending[m] = p;
                m += 1;
                if m == SHAPE_LANES {
                    self.shapes_of(bridge, &pending);
                    m = 0;
                }
            }
        }
        if m > 0 {
            self.shapes_of(bridge, &pending[..m]);
        }
    }

    /// Unless slot `w` has an entry at `x`: takes its older entry for `x` with the
    /// irregularity there, and returns `(2 w + slot, x)`, whose shapes are still to be made
    /// ([`Self::shapes_of`]).
    #[inline]
    fn claim(&mut self, track: &dyn RailProfile, w: usize, x: f64) -> Option<(usize, f64)> {
        let bits = x.to_bits();
        if self.keys[w].iter().any(|k| k.0 == bits) {
            return None;
        }
        let s = self.next[w];
        self.next[w] = 1 - s;
        self.keys[w][s] = (bits, false);
        self.irregularity[w][s] = track.at(x);
        Some((2 * w + s, x))
    }

    /// The basis of entries `(2 w + slot, x)` (ascending entries, at most [`SHAPE_LANES`])
    /// and their on-deck flags into `keys`.
    fn shapes_of(&mut self, bridge: &ModalBridge, pending: &[(usize, f64)]) {
        if let Some((_, _, kmax)) = bridge.sine_modes() {
            let stride = kmax + 1;
            let need = 2 * self.keys.len() * stride;
            if self.stride != stride || self.sines.len() < need {
                self.stride = stride;
                self.sines.resize(need, 0.0);
            }
            let mut outs: [&mut [f64]; SHAPE_LANES] = Default::default();
            let mut xs = [0.0; SHAPE_LANES];
            let mut rest = &mut self.sines[..];
            let mut base = 0;
            for (j, &(entry, x)) in pending.iter().enumerate() {
                let tail = std::mem::take(&mut rest)
                    .split_at_mut((entry - base) * stride)
                    .1;
                let (this, tail) = tail.split_at_mut(stride);
                outs[j] = this;
                rest = tail;
                base = entry + 1;
                xs[j] = x;
            }
            let m = pending.len();
            let mut on = [false; SHAPE_LANES];
            bridge.sines_lanes(&xs[..m], &mut outs[..m], &mut on, &mut self.lanes);
            for (&(entry, _), on) in pending.iter().zip(on) {
                self.keys[entry / 2][entry % 2].1 = on;
            }
            return;
        }
        for &(entry, x) in pending {
            let st = bridge.nodal_stencil(x);
            self.keys[entry / 2][entry % 2].1 = st.is_some();
            self.stencils[entry] =
                st.map_or(Stencil::default(), |(start, w, k)| Stencil { start, w, k });
        }
    }

    /// The slot of wheelset `w`'s entry at `x` (made by [`Self::fill`] or [`Self::claim`]).
    #[inline]
    fn slot(&self, w: usize, x: f64) -> usize {
        let bits = x.to_bits();
        self.keys[w]
            .iter()
            .position(|k| k.0 == bits)
            .expect("the shape cache was filled for these positions")
    }

    /// For nodal shapes, the entry of wheelset slot `w` at `x`: its stencil (None off the
    /// deck) and the irregularity there.
    fn stencil(&self, w: usize, x: f64) -> (Option<&Stencil>, &RailIrregularity) {
        let slot = self.slot(w, x);
        let on = self.keys[w][slot].1;
        (
            on.then(|| &self.stencils[2 * w + slot]),
            &self.irregularity[w][slot],
        )
    }

    /// For sine shapes, where the entry of wheelset slot `w` at `x` starts in `sines` (None
    /// off the deck), and its slot.
    #[inline]
    fn sines_entry(&self, w: usize, x: f64) -> (Option<usize>, usize) {
        let slot = self.slot(w, x);
        let at = self.keys[w][slot].1.then(|| (2 * w + slot) * self.stride);
        (at, slot)
    }

    /// For sine shapes, where the entry of wheelset slot `w` at `x` starts in `sines` (None
    /// off the deck).
    #[inline]
    fn sines_at(&self, w: usize, x: f64) -> Option<usize> {
        self.sines_entry(w, x).0
    }

    /// For sine shapes, the entry of wheelset slot `w` at `x`: `sin(k θ)` (None off the
    /// deck) and the irregularity there.
    #[inline]
    fn sines(&self, w: usize, x: f64) -> (Option<&[f64]>, &RailIrregularity) {
        let (at, slot) = self.sines_entry(w, x);
        (
            at.map(|at| &self.sines[at..at + self.stride]),
            &self.irregularity[w][slot],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The forces gathered per half-wave number in registers equal the loop over the
    /// wheelsets bit for bit, for 1 to 13 half-wave numbers (13: the loop itself).
    #[test]
    fn sine_forces_equal_the_loop_bit_for_bit() {
        let v = |i: usize, c: f64| ((i as f64 + c) * 0.618_033_988_749_895).sin() * 1e3;
        for n in 1..=13 {
            let sines: Vec<Vec<f64>> = (0..7)
                .map(|w| (0..n).map(|k| v(k + 17 * w, 0.3)).collect())
                .collect();
            let g: Vec<[f64; 3]> = (0..7).map(|w| [v(w, 1.1), -v(w, 2.2), v(w, 3.3)]).collect();
            // the sines one after the other, a gap after each (as entries in the cache)
            let storage: Vec<f64> = sines
                .iter()
                .flat_map(|s| s.iter().copied().chain([9.9]))
                .collect();
            let items: Vec<(usize, [f64; 3])> = (0..7).map(|w| (w * (n + 1), g[w])).collect();
            let (mut a, mut b) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
            sine_forces(&mut a, &storage, &items);
            sine_forces_body(&mut b, &storage, &items);
            let bits =
                |h: &[[f64; 3]]| -> Vec<u64> { h.iter().flatten().map(|x| x.to_bits()).collect() };
            assert_eq!(bits(&a), bits(&b), "{n} half-wave numbers");
        }
    }

    /// The deck motions summed over the half-wave numbers a component at a time equal the
    /// scalar loop bit for bit, for 1 to 13 half-wave numbers, and are the sums they stand
    /// for (to round-off, summed in another order).
    #[test]
    fn sine_motions_equal_the_loop_bit_for_bit() {
        let v = |i: usize, c: f64| ((i as f64 + c) * 0.618_033_988_749_895).sin() * 1e3;
        for n in 1..=13 {
            let storage: Vec<f64> = (0..7 * (n + 1)).map(|i| v(i, 0.3)).collect();
            let b: Vec<[[f64; 4]; 3]> = (0..n)
                .map(|k| {
                    let m = |c: usize| [v(k, c as f64), -v(k, 1.5 + c as f64), v(k, 7.0), 0.0];
                    [m(0), m(1), m(2)]
                })
                .collect();
            let starts: Vec<usize> = (0..7).map(|w| w * (n + 1)).collect();
            let mut a = Vec::new();
            sine_motions(&mut a, &b, &storage, &starts);
            let mut s = vec![[[0.0; 4]; 3]; 7];
            sine_motions_body(&mut s, &b, &storage, &starts);
            let bits = |h: &[[[f64; 4]; 3]]| -> Vec<u64> {
                h.iter().flatten().flatten().map(|x| x.to_bits()).collect()
            };
            assert_eq!(bits(&a), bits(&s), "{n} half-wave numbers");
            for (w, aw) in a.iter().enumerate() {
                for c in 0..3 {
                    for d in 0..4 {
                        let sum: f64 = (0..n)
                            .rev()
                            .map(|k| storage[w * (n + 1) + k] * b[k][c][d])
                            .sum();
                        assert!((aw[c][d] - sum).abs() <= 1e-12 * 1e6 * n as f64);
                    }
                }
            }
        }
    }
}
