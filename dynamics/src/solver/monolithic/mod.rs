//! The monolithic solver of eq. (14): bridge modes and all vehicles in one Newmark step.
//!
//! Unknowns: modal coordinates `q` (N_b) and the free DOFs `vᵢ` of every vehicle. Rail motion
//! under wheelset w: `u_w = Ψ_w q + r_w`, `u̇_w = Ψ_w q̇ + ṙ_w`, `ü_w = Ψ_w q̈ + r̈_w` (eq. 13;
//! `Ψ_w = Ψ(x_w(t))`, `r_w` irregularity plus hunting; as in the paper the convective terms
//! of the moving contact point, `v Ψ′ q`, are not included). Substituting into the vehicle
//! equations and into `q̈ + 2ζω q̇ + ω² q = Σ_w Ψ_wᵀ f_w` with the wheel force of eq. (6)
//! gives eq. (14):
//!
//! ```text
//! M_vv v̈ + C_vv v̇ + K_vv v + Σ_w (C_vw Ψ_w q̇ + K_vw Ψ_w q) = −Σ_w (K_vw r_w + C_vw ṙ_w)
//! (I + Σ ΨᵀM_wΨ) q̈ + (2ζω + Σ ΨᵀC_wwΨ) q̇ + (ω² + Σ ΨᵀK_wwΨ) q + Σ Ψᵀ(C_wv v̇ + K_wv v)
//!     = Σ Ψᵀ (P0 − M_w r̈ − C_ww ṙ − K_ww r)
//! ```
//!
//! a symmetric system whose bridge block and coupling blocks change with the wheelset
//! positions while the vehicle blocks stay constant.
//!
//! **Solution per step.** Newmark turns it into `K̂ x = b`. With the constant per-vehicle
//! matrices `K̂_v = a0 M + a1 C + K` (Cholesky, once), `Ĝ = [K_vw,w + a1 C_vw,w]_w`
//! (n × 3n_w) and `Ŵ = blockdiag(a0 M_w + a1 C_ww + K_ww)`, the vehicle unknowns are eliminated
//! exactly (Schur complement) through the constant rail-space matrix
//! `S = Ŵ − Ĝᵀ K̂_v⁻¹ Ĝ` (3n_w × 3n_w) and `H = Ĝᵀ K̂_v⁻¹`:
//!
//! ```text
//! (D̂ + Σᵢ Uᵢᵀ Sᵢ Uᵢ) q_{n+1} = b_q − Σᵢ Uᵢᵀ Hᵢ b_vᵢ ,      vᵢ,_{n+1} = K̂_vᵢ⁻¹ b_vᵢ − Hᵢᵀ Uᵢ q_{n+1}
//! ```
//!
//! where `Uᵢ` stacks the `Ψ_w` of vehicle i's wheelsets and `D̂ = diag(a0 + a1 2ζω + ω²)`. The
//! cost per step is `O(n_wheelsets · N_b²)` for the reduced matrix plus one `N_b × N_b`
//! Cholesky solve — independent of how many vehicle DOFs there are beyond the constant
//! per-vehicle back-substitutions. The reduced system is solved by conjugate gradients
//! preconditioned by the inverse of its own matrix at an earlier step (renewed as the
//! wheelsets move on), started from the preconditioned right-hand side plus the correction
//! extrapolated from the last steps', to round-off. A vehicle's `K̂_v⁻¹ b_v` is two dense products made once
//! with the factor, `K̂_v⁻¹ [a0 M + a1 C  a2 M + C  M]` times its state `(v, v̇, v̈)` (the
//! Newmark predictors folded in) and `−K̂_v⁻¹ [K_vw  C_vw]` times its wheelsets' rail terms,
//! so a step solves nothing per vehicle. The tests check that this gives the same solution as
//! a dense solve of the explicitly assembled matrices of eq. (14).
//!
//! **Where the parts sit.** This file holds the state and the step of eq. (14); the speed-ups
//! behind it sit in files of their own: the step's geometry (positions, prescribed rail
//! motion, rail shapes in the two layouts the step reads) in `geometry`, the constant
//! per-vehicle blocks in `vehicle_cache`, the reduced system's products and assembly in
//! `reduced`, its conjugate-gradient solve in `iterative` with the lagged preconditioner in
//! `lagged`, the worker that makes the geometry ahead in `lookahead`, the wheelsets a step
//! may leave out in `visits`, and the step's preallocated buffers in `work`.

mod geometry;
mod iterative;
mod lagged;
mod lookahead;
mod reduced;
mod vehicle_cache;
mod visits;
mod work;

pub use lookahead::AHEAD_MAX_BYTES;

use super::{VehicleState, WheelForce};
use crate::bridge::ModalBridge;
use crate::newmark::Newmark;
use crate::track::RailProfile;
use crate::train::{Train, WheelsetRef};
use crate::vehicle::aero::WindBody;
use geometry::{Blocks, Geometry, Placement};
use lookahead::Lookahead;
use nalgebra::{DMatrix, DVector, Vector3};
use reduced::{block_mul, block_tr_add, psi_mul3, psi_tr_add, Reduced};
use std::sync::Arc;
use vehicle_cache::VehicleCache;
use work::Work;

/// Monolithic Newmark integration of eq. (14) (see the module docs).
pub struct Monolithic {
    pub bridge: ModalBridge,
    pub train: Train,
    pub track: Arc<dyn RailProfile>,
    nm: Newmark,
    /// Current time, s.
    pub t: f64,
    pub q: DVector<f64>,
    pub qd: DVector<f64>,
    pub qdd: DVector<f64>,
    /// Vehicle states (free DOFs from static equilibrium).
    pub vehicles: Vec<VehicleState>,
    /// Train wheelsets front to back.
    pub wheelsets: Vec<WheelsetRef>,
    /// Total rail motion (u, u̇, ü) of each wheelset at `t`.
    pub rail: Vec<[Vector3<f64>; 3]>,
    /// Force of each wheelset on the rail at `t` (F_y, M_x, F_z).
    pub forces: Vec<Vector3<f64>>,
    omega: Vec<f64>,
    zeta: Vec<f64>,
    /// Where each vehicle's `U` starts in [`Geometry::blocks`].
    block_at: Vec<usize>,
    /// Each wheelset's lane in [`Geometry::blocks`], `(start, stride)`: its vehicle's
    /// `block_at + 3l` and `3n_w`.
    lane_at: Vec<(usize, usize)>,
    /// The geometry at `t` ([`Monolithic::update_geometry`]).
    geo: Geometry,
    /// The worker making the geometry of the steps to come ([`Monolithic::run_ahead`]).
    ahead: Lookahead,
    /// Per vehicle, its constant blocks (shared by the vehicles of one model).
    cache: Vec<Arc<VehicleCache>>,
    /// The deck's buffeting forces, when the bridge has a turbulent wind.
    buffeting: Option<Arc<crate::bridge::buffeting::DeckBuffeting>>,
    first_ws: Vec<usize>,
    /// Per wheelset, what its force on the rail needs (for the outputs).
    wheel_forces: Vec<Arc<WheelForce>>,
    /// Per wheelset: a moving force (its vehicle has no DOFs, its force is constant), which
    /// off the deck of an ideal track changes nothing from step to step.
    inert: Vec<bool>,
    /// The wheelsets that are not [`Monolithic::inert`], ascending.
    varying: Vec<usize>,
    /// The vehicles without wheelsets (stepped though no wheelset makes them busy).
    loose: Vec<usize>,
    work: Work,
}

impl Monolithic {
    /// Set up at `t = 0`: bridge at rest in its static response to the steady deck loads,
    /// vehicles in static equilibrium on the rail under them, consistent initial
    /// accelerations.
    pub fn new(bridge: ModalBridge, train: Train, track: Arc<dyn RailProfile>, dt: f64) -> Self {
        let nb = bridge.n_modes();
        let wheelsets = train.wheelsets();
        let nw = wheelsets.len();
        let nm = Newmark::new(dt);
        let (mut first_ws, mut block_at, mut lane_at) = (Vec::new(), Vec::new(), Vec::new());
        let (mut k, mut at) = (0, 0);
        for tv in &train.vehicles {
            let r3 = 3 * tv.model.wheelsets.len();
            first_ws.push(k);
            block_at.push(at);
            lane_at.extend((0..r3).step_by(3).map(|l3| (at + l3, r3)));
            k += tv.model.wheelsets.len();
            at += r3 * nb;
        }
        let cache = vehicle_cache::of_train(&train, &nm);
        let q0 = bridge.steady_response();
        let buffeting = bridge.buffeting.as_ref().map(|spec| {
            Arc::new(
                crate::bridge::buffeting::DeckBuffeting::new(&bridge, spec)
                    .expect("the buffeting spec is checked when the model is built"),
            )
        });
        let wheel_forces = WheelForce::of_train(&train, &wheelsets);
        let inert = wheelsets
            .iter()
            .zip(&wheel_forces)
            .map(|(ws, f): (&WheelsetRef, &Arc<WheelForce>)| {
                train.vehicles[ws.vehicle].model.ndof() == 0 && f.constant
            })
            .collect::<Vec<bool>>();
        let varying = (0..nw).filter(|&w| !inert[w]).collect();
        let loose = (train.vehicles.iter().enumerate())
            .filter(|(_, tv)| tv.model.wheelsets.is_empty())
            .map(|(i, _)| i)
            .collect();
        let mut s = Monolithic {
            inert,
            varying,
            loose,
            buffeting,
            omega: bridge.omegas(),
            zeta: bridge.damping.clone(),
            bridge,
            vehicles: Vec::new(),
            train,
            track,
            nm,
            t: 0.0,
            q: DVector::from_vec(q0),
            qd: DVector::zeros(nb),
            qdd: DVector::zeros(nb),
            wheelsets,
            rail: vec![[Vector3::zeros(); 3]; nw],
            forces: vec![Vector3::zeros(); nw],
            block_at,
            lane_at,
            geo: Geometry::new(nw, nb),
            ahead: Lookahead::default(),
            cache,
            first_ws,
            wheel_forces,
            work: Work::default(),
        };
        s.work = Work::new(nb, &s.train);
        // D̂ = diag(a0 + a1 2ζω + ω²), fixed by the step size and the modes
        for n in 0..nb {
            let c = 2.0 * s.zeta[n] * s.omega[n];
            s.work.dhat[n] = nm.a0 + nm.a1 * c + s.omega[n] * s.omega[n];
        }
        s.update_geometry(0.0);
        for w in 0..nw {
            s.rail[w] = s.geo.presc[w];
        }
        s.vehicles = s
            .train
            .vehicles
            .iter()
            .enumerate()
            .map(|(i, tv)| {
                let f = s.first_ws[i];
                let u = body_turbulence(&s.buffeting, &s.train, i, 0.0);
                let wind = s.train.body_force(i, 0.0, u);
                VehicleState::initial_loaded(
                    &tv.model,
                    &s.rail[f..f + tv.model.wheelsets.len()],
                    wind.as_ref(),
                )
            })
            .collect();
        s.initial_bridge_acceleration();
        let mut deck = Vec::new();
        s.deck_motion_into(&mut deck);
        s.finish_outputs(&deck);
        s
    }

    pub fn dt(&self) -> f64 {
        self.nm.h
    }

    /// Wheelset positions at [`Monolithic::t`], m.
    pub fn x(&self) -> &[f64] {
        &self.geo.x
    }

    /// The reduced bridge matrix `A = D̂ + Σ Uᵀ S U` (`N_b × N_b`, symmetric) at the
    /// wheelsets' positions at the current time: what a step to this time solves for `q`
    /// (see the module docs), with the vehicles eliminated. For inspection and tests.
    pub fn reduced_matrix(&self) -> DMatrix<f64> {
        let w = &self.work;
        let mut live = vec![false; self.train.vehicles.len()];
        self.live_vehicles(&w.busy_vehicles, &mut live);
        self.reduced(&w.dhat, &w.busy_vehicles, &live).assemble()
    }

    /// How the reduced system is preconditioned: None by `D̂`, else by an earlier step's
    /// inverse carried forward to this order (`Lagged`: 0 before the second assembly, 1
    /// before the third, 2 after). For inspection and tests.
    pub fn preconditioner_order(&self) -> Option<usize> {
        self.work.solver.order()
    }

    /// The wheelsets whose force can change (all but the moving forces), into `out`.
    pub(crate) fn forces_varying_into(&self, out: &mut Option<Vec<usize>>) {
        out.get_or_insert_with(Vec::new).clone_from(&self.varying);
    }

    /// Wheelset `w`'s rail shapes `Ψ_w[n]`, from its rows of [`Geometry::psi_t`].
    fn shapes_w(&self, w: usize) -> Vec<[f64; 3]> {
        let nb = self.q.len();
        let r = &self.geo.psi_t[3 * nb * w..3 * nb * (w + 1)];
        (0..nb).map(|n| [r[n], r[nb + n], r[2 * nb + n]]).collect()
    }

    /// Where each vehicle's `U` sits in the geometry at `t`.
    fn blocks(&self) -> Blocks<'_> {
        Blocks {
            geo: &self.geo,
            train: &self.train,
            block_at: &self.block_at,
            first_ws: &self.first_ws,
            nb: self.q.len(),
        }
    }

    /// The reduced matrix `A = D̂ + Σ Uᵀ S U` over `vehicles` (those `live`, with a wheelset
    /// on the deck) at the geometry at `t`, unassembled.
    fn reduced<'a>(
        &'a self,
        dhat: &'a DVector<f64>,
        vehicles: &'a [usize],
        live: &'a [bool],
    ) -> Reduced<'a> {
        Reduced {
            blocks: self.blocks(),
            cache: &self.cache,
            dhat,
            vehicles,
            live,
        }
    }

    /// Positions, Ψ and prescribed rail motion at time `t`, and the wheelsets and vehicles
    /// the step has to visit (`work.busy`, `work.busy_vehicles`): on the ideal track, at this
    /// step and the one before, not the idle ones ([`visits::busy_wheelsets`]).
    ///
    /// With [`Monolithic::run_ahead`] (never on the ideal track, where the idle wheelsets
    /// depend on the state) every wheelset is busy, and the geometry was made by the worker:
    /// the same [`Geometry::positions`], [`Geometry::rails`] and [`Geometry::shapes`], the
    /// same values.
    fn update_geometry(&mut self, t: f64) {
        let flat = self.flat();
        let idle_allowed = flat && self.work.flat_before;
        self.work.flat_before = flat;
        if self.ahead.take(t, &mut self.geo) {
            let busy = &mut self.work.busy;
            busy.clear();
            busy.extend(0..self.wheelsets.len());
            self.busy_vehicles();
            return;
        }
        let model = Placement {
            bridge: &self.bridge,
            train: &self.train,
            track: &*self.track,
            wheelsets: &self.wheelsets,
            lane_at: &self.lane_at,
            h: self.nm.h,
        };
        let geo = &mut self.geo;
        geo.positions(&model, t);
        let w = &mut self.work;
        let (rest, busy) = (&mut w.resting, &mut w.busy);
        visits::busy_wheelsets(
            &model,
            geo,
            &self.first_ws,
            &self.inert,
            idle_allowed,
            rest,
            busy,
        );
        geo.rails(&model, busy, t, flat);
        geo.shapes(&model, busy);
        self.busy_vehicles();
    }

    /// The vehicles of the busy wheelsets and those without wheelsets, ascending, into
    /// `work.busy_vehicles`.
    fn busy_vehicles(&mut self) {
        let w = &mut self.work;
        visits::busy_vehicles(&w.busy, &self.wheelsets, &self.loose, &mut w.busy_vehicles);
    }

    /// Make each step's geometry (`Geometry`) on a worker thread up to seven steps ahead
    /// (`solver::ahead`), while this thread steps: the same values as made here, bit for
    /// bit, the step's other work alone on this thread. Returns whether the worker runs; it
    /// does only where it may pay ([`Monolithic::ahead_may_pay`]). The worker works from a
    /// copy of the bridge and the train as they were at the first call (changes to
    /// [`Monolithic::bridge`] or [`Monolithic::train`] after it are not seen by it).
    /// A step whose time is not the worker's (`t` set from outside) makes its own geometry,
    /// and the worker is stopped. The worker spins while it is ahead, so it takes a core of
    /// its own: for runs alone on a machine with cores to spare. With `give_up`, a step
    /// waits at most that long for the worker; one that waits longer makes its own
    /// geometry, the worker is stopped and [`Monolithic::take_ahead_lost`] says so
    /// ([`super::MAX_LAG`] is the measured choice; None waits as long as the worker lives).
    pub fn run_ahead(&mut self, give_up: Option<std::time::Duration>) -> bool {
        if !self.ahead_may_pay() {
            return false;
        }
        let model = Placement {
            bridge: &self.bridge,
            train: &self.train,
            track: &*self.track,
            wheelsets: &self.wheelsets,
            lane_at: &self.lane_at,
            h: self.nm.h,
        };
        self.ahead.start(&model, &self.track, self.t, give_up)
    }

    /// Whether [`Monolithic::run_ahead`] may make the run faster: the geometry does not
    /// depend on the state (it does on the ideal track without hunting, whose idle
    /// wheelsets are left out), and a step's shapes keep within [`AHEAD_MAX_BYTES`]. Whether
    /// it does depends on the machine: on two cores of a virtual machine, the Tsing Ma case
    /// (nodal shapes, each value a Lagrange combination over its stencil; 20 modes, 8
    /// coaches) ran in 0.61 s ahead against 0.95 s when the host had placed the two cores
    /// so that a cache line crossed between them cheaply, and in 1.02–1.07 s when it had
    /// not; the bench case (sine shapes, a cheap recurrence) in 0.198 s against 0.260 s, or
    /// in 0.265–0.29 s. So a caller measures ([`Monolithic::stop_ahead`]).
    pub fn ahead_may_pay(&self) -> bool {
        let bytes = 2 * self.geo.blocks.len() * std::mem::size_of::<f64>();
        !self.flat() && bytes <= AHEAD_MAX_BYTES
    }

    /// The ideal track without hunting: the prescribed motion is zero everywhere.
    fn flat(&self) -> bool {
        self.track.is_flat() && !self.train.hunts()
    }

    /// Whether the worker of [`Monolithic::run_ahead`] stopped on its own since the last call:
    /// it fell behind by its give-up time (it lacks a core) or failed, and each step makes
    /// its own geometry since.
    pub fn take_ahead_lost(&mut self) -> bool {
        self.ahead.take_lost()
    }

    /// Whether the geometry is made ahead ([`Monolithic::run_ahead`]).
    pub fn runs_ahead(&self) -> bool {
        self.ahead.runs()
    }

    /// Stop making the geometry ahead: each step makes its own from now on, the same values.
    pub fn stop_ahead(&mut self) {
        self.ahead.stop();
    }

    fn initial_bridge_acceleration(&mut self) {
        let nb = self.q.len();
        let mut a = DMatrix::<f64>::identity(nb, nb);
        let mut rhs = DVector::zeros(nb);
        for n in 0..nb {
            rhs[n] = self.bridge.steady(n)
                - 2.0 * self.zeta[n] * self.omega[n] * self.qd[n]
                - self.omega[n].powi(2) * self.q[n];
        }
        if let Some(b) = &self.buffeting {
            b.add_modal_force(self.t, rhs.as_mut_slice());
        }
        for (w, ws) in self.wheelsets.iter().enumerate() {
            let model = &self.train.vehicles[ws.vehicle].model;
            let c = &model.wheelsets[ws.local];
            let psi = &self.shapes_w(w);
            // force without the deck-acceleration part of the wheel inertia
            let [u, ud, udd] = self.rail[w];
            let vs = &self.vehicles[ws.vehicle];
            let f = model.wheel_force(ws.local, &vs.v, &vs.vd, &u, &ud, &udd);
            psi_tr_add(psi, &f, rhs.as_mut_slice());
            for i in 0..nb {
                let mp = c.m_w * Vector3::from(psi[i]);
                for j in 0..nb {
                    a[(j, i)] += psi[j][0] * mp.x + psi[j][1] * mp.y + psi[j][2] * mp.z;
                }
            }
        }
        self.qdd = a
            .cholesky()
            .expect("I + ΣΨᵀM_wΨ is positive definite")
            .solve(&rhs);
    }

    /// Rail motion and wheel forces from the current state.
    /// The deck's part `(Ψ q, Ψ q̇, Ψ q̈)` of the rail motion under every wheelset (zero off
    /// the deck) at the current modal state, into `out`.
    fn deck_motion_into(&self, out: &mut Vec<[Vector3<f64>; 3]>) {
        let (q, qd, qdd) = (self.q.as_slice(), self.qd.as_slice(), self.qdd.as_slice());
        out.clear();
        out.extend((0..self.wheelsets.len()).map(|w| {
            if self.geo.on[w] {
                psi_mul3(&self.shapes_w(w), q, qd, qdd)
            } else {
                [Vector3::zeros(); 3]
            }
        }));
    }

    /// [`Self::deck_motion_into`] of the wheelsets `busy` at the end of a step from `Ψ q₁`
    /// alone: Newmark's `q̇₁ = a1 q₁ − q_c` and `q̈₁ = a0 q₁ − q_m` give
    /// `Ψ q̇₁ = a1 Ψ q₁ − Ψ q_c` and `Ψ q̈₁ = a0 Ψ q₁ − Ψ q_m`, with the step's
    /// `pred[w] = (Ψ q_c, Ψ q_m)` under the same shapes: one pass over the shapes instead of
    /// three (the other entries of `out` are left as they are; `out` gets one entry per
    /// wheelset).
    fn deck_motion_at_end(&self, w: &mut Work) {
        let (a0, a1) = (self.nm.a0, self.nm.a1);
        let out = &mut w.deck;
        out.resize(self.wheelsets.len(), [Vector3::zeros(); 3]);
        // off the deck: none; on it (only in a vehicle with a block): from the block's Ψ q₁
        for &ws in &w.busy {
            out[ws] = [Vector3::zeros(); 3];
        }
        for &i in &w.busy_vehicles {
            if !w.live[i] {
                continue;
            }
            let u = self.blocks().block(i);
            let (f0, r3) = (self.first_ws[i], u.len() / self.q.len());
            let uq = &mut w.ux[..r3];
            block_mul(u, self.q.as_slice(), uq);
            for (l, v) in uq.chunks_exact(3).enumerate() {
                let ws = f0 + l;
                if self.geo.on[ws] {
                    let u = Vector3::new(v[0], v[1], v[2]);
                    let [pv, pm] = w.pred[ws];
                    out[ws] = [u, a1 * u - pv, a0 * u - pm];
                }
            }
        }
    }

    /// Rail motion and wheel forces at the current state, the deck's part of the rail motion
    /// given ([`Self::deck_motion_into`]).
    fn finish_outputs(&mut self, deck: &[[Vector3<f64>; 3]]) {
        let all: Vec<usize> = (0..self.wheelsets.len()).collect();
        self.finish_outputs_of(&all, deck, None);
    }

    /// [`Self::finish_outputs`] of the wheelsets `busy` (the others keep theirs). With
    /// `stepped`, the forces of the wheelsets of vehicles with DOFs are taken from it (the
    /// step's `g − z − S U q₁`) instead of being evaluated from eq. (6) again.
    fn finish_outputs_of(
        &mut self,
        busy: &[usize],
        deck: &[[Vector3<f64>; 3]],
        stepped: Option<&[f64]>,
    ) {
        for &w in busy {
            let p = self.geo.presc[w];
            let [u, ud, udd] = if self.geo.on[w] {
                let [a, b, c] = deck[w];
                [a + p[0], b + p[1], c + p[2]]
            } else {
                p
            };
            self.rail[w] = [u, ud, udd];
            let v = self.wheelsets[w].vehicle;
            self.forces[w] = match stepped {
                Some(f) if self.train.vehicles[v].model.ndof() > 0 => {
                    Vector3::new(f[3 * w], f[3 * w + 1], f[3 * w + 2])
                }
                _ => self.wheel_forces[w].force(&self.vehicles[v], &self.rail[w]),
            };
        }
    }

    /// Advance one step of size `dt`: the bridge's predictors and the steady and buffeting
    /// forces, the vehicles eliminated one by one into the bridge's right-hand side, the
    /// reduced system solved for `q₁`, the bridge's Newmark update, then the vehicles
    /// back-substituted and the outputs at the new state.
    pub fn step(&mut self) {
        let nm = self.nm;
        let nb = self.q.len();
        let t1 = self.t + nm.h;
        self.update_geometry(t1);
        let mut w = std::mem::take(&mut self.work);
        self.live_vehicles(&w.busy_vehicles, &mut w.live);
        self.bridge_predictors(&mut w, t1);
        // y = K̂⁻¹ b_v, the state's part first (two vehicles' side by side), the rails'
        // after the wheelset loop
        vehicle_cache::state_parts(
            &w.busy_vehicles,
            &self.train,
            &self.vehicles,
            &self.cache,
            &mut w.bv,
            [&mut w.state, &mut w.state2],
        );
        for k in 0..w.busy_vehicles.len() {
            let i = w.busy_vehicles[k];
            self.eliminate_vehicle(&mut w, i, t1);
        }
        let a = self.reduced(&w.dhat, &w.busy_vehicles, &w.live);
        if !w.solver.solve(&a, &w.bq, &mut w.ux, &mut w.sx) {
            let q1 = a.solve_direct(&w.bq);
            w.solver.cg_x.copy_from(&q1);
        }
        let q1 = &w.solver.cg_x;
        for n in 0..nb {
            let (qd1, qdd1) = nm.update(q1[n], self.q[n], self.qd[n], self.qdd[n]);
            self.qd[n] = qd1;
            self.qdd[n] = qdd1;
        }
        self.q.copy_from(q1);
        // The deck's rail motion at the new state, once: its Ψ q₁ serves the back-substitution.
        self.deck_motion_at_end(&mut w);
        self.back_substitute(&mut w);
        self.t = t1;
        self.finish_outputs_of(&w.busy, &w.deck, Some(&w.gz));
        self.work = w;
    }

    /// The bridge's Newmark predictors `q_m`, `q_c` of the step to `t1` and the diagonal
    /// part of its right-hand side, `b_q = q_m + 2ζω q_c + S` with the buffeting forces at
    /// `t1`.
    fn bridge_predictors(&self, w: &mut Work, t1: f64) {
        let nm = self.nm;
        let nb = self.q.len();
        for n in 0..nb {
            let c = 2.0 * self.zeta[n] * self.omega[n];
            w.qm[n] = nm.mass_pred(self.q[n], self.qd[n], self.qdd[n]);
            w.qc[n] = nm.damp_pred(self.q[n], self.qd[n]);
            w.bq[n] = w.qm[n] + c * w.qc[n] + self.bridge.steady(n);
        }
        if let Some(b) = &self.buffeting {
            b.add_modal_force(t1, w.bq.as_mut_slice());
        }
    }

    /// Vehicle `i` eliminated from the step to `t1` (see the module docs): its
    /// `y = K̂⁻¹ b_v` completed with the wind's and the rails' parts, and the coupling of its
    /// wheelsets to the bridge, `Uᵀ (g − H b_v)` (or `Ψᵀ g` of a wheelset without vehicle
    /// DOFs), added to the bridge's right-hand side.
    fn eliminate_vehicle(&self, w: &mut Work, i: usize, t1: f64) {
        let nm = self.nm;
        let nb = self.q.len();
        let model = &self.train.vehicles[i].model;
        let cache = &self.cache[i];
        let vs = &self.vehicles[i];
        let f0 = self.first_ws[i];
        let n = model.ndof();
        let y = &mut w.bv[i];
        let vc = &mut w.vc[i];
        if n > 0 {
            for k in 0..n {
                vc[k] = nm.damp_pred(vs.v[k], vs.vd[k]);
            }
            // the wind on the body beyond its static loads, F₁
            if self.train.wind.is_some() {
                let f = &mut w.vm[i];
                f.fill(0.0);
                let u = body_turbulence(&self.buffeting, &self.train, i, t1);
                self.train.add_wind_force(i, t1, u, 1.0, f);
                WindBody::add_responses(&cache.wind, f.as_slice(), y.as_mut_slice());
            }
            // the inertia of a changing speed, g a
            let a = self.train.acceleration_of(i, t1);
            if a != 0.0 && !cache.inertia.is_empty() {
                crate::simd::axpy(y.as_mut_slice(), a, &cache.inertia);
            }
        }
        let rails = &mut w.rails;
        rails.clear();
        // Ψ q_c, Ψ q_m of the vehicle's wheelsets (zeros off the deck)
        let r3 = 3 * model.wheelsets.len();
        let (uqc, uqm) = (&mut w.ux[..r3], &mut w.sx[..r3]);
        if w.live[i] {
            let u = self.blocks().block(i);
            crate::simd::mul_columns_pair(uqc, w.qc.as_slice(), u, uqm, w.qm.as_slice(), u);
        } else {
            uqc.fill(0.0);
            uqm.fill(0.0);
        }
        for (l, c) in model.wheelsets.iter().enumerate() {
            let ws = f0 + l;
            let [r, rd, rdd] = self.geo.presc[ws];
            let on = self.geo.on[ws];
            let (pv, pm) = if on {
                let at = |u: &[f64]| Vector3::new(u[3 * l], u[3 * l + 1], u[3 * l + 2]);
                (at(uqc), at(uqm))
            } else {
                (Vector3::zeros(), Vector3::zeros())
            };
            w.pred[ws] = [pv, pm];
            if n > 0 {
                rails.extend_from_slice(r.as_slice());
                rails.extend_from_slice((rd - pv).as_slice());
            }
            if n > 0 || on {
                let g = c.p0 - c.m_w * (rdd - pm) - c.k_ww * r - c.c_ww * (rd - pv);
                if n > 0 {
                    // + C_vwᵀ v_c after the loop; Ψᵀ g goes in with the coupling
                    // correction below (of a wheelset off the deck, g is its force's
                    // part without the vehicle's unknowns)
                    w.gv[3 * l..3 * l + 3].copy_from_slice(g.as_slice());
                } else {
                    let rows = &self.geo.psi_t[3 * nb * ws..3 * nb * (ws + 1)];
                    crate::simd::project_rows(w.bq.as_mut_slice(), rows, [g.x, g.y, g.z]);
                }
            }
        }
        if n > 0 {
            // g_l + C_vw,lᵀ v_c of every wheelset at once
            let gv = &mut w.gv[..r3];
            crate::simd::axpy_columns(gv, vc.as_slice(), &cache.cvw_t);
            crate::simd::axpy_columns(y.as_mut_slice(), rails, &cache.e_rail);
            // g − z of every wheelset, z = H b_v = Ĝᵀ y: its force but for − S U q₁
            // (taken off in the back-substitution); Uᵀ (g − z) into the bridge's
            // right-hand side (the zero rows of wheelsets off the deck add nothing)
            let z = &mut w.z[i];
            crate::simd::mul_columns(z.as_mut_slice(), y.as_slice(), &cache.g_tr);
            let gz = &mut w.gz[3 * f0..3 * f0 + r3];
            for ((d, g), z) in gz.iter_mut().zip(gv.iter()).zip(z.iter()) {
                *d = g - z;
            }
            if w.live[i] {
                block_tr_add(self.blocks().block_t(i), gz, w.bq.as_mut_slice());
            }
        }
    }

    /// The vehicles with DOFs back-substituted at the new `q₁` (see the module docs),
    /// `v₁ = K̂⁻¹ b_v − Hᵀ U q₁`, and their wheelsets' forces on the rail; a vehicle that
    /// this left as it was, off the deck of an ideal track without wind, is at rest.
    fn back_substitute(&mut self, w: &mut Work) {
        let nm = self.nm;
        // Back-substitute the vehicles: v1 = K̂⁻¹ b_v − Hᵀ U q1 (a vehicle with DOFs is busy).
        for &i in &w.busy_vehicles {
            let tv = &self.train.vehicles[i];
            let n = tv.model.ndof();
            if n == 0 {
                continue;
            }
            let cache = &self.cache[i];
            let f0 = self.first_ws[i];
            let nwi = tv.model.wheelsets.len();
            let uq = &mut w.z[i];
            for l in 0..nwi {
                uq.fixed_rows_mut::<3>(3 * l).copy_from(&w.deck[f0 + l][0]);
            }
            // the scratch of the wind's share takes v1 = K̂⁻¹ b_v − Hᵀ U q₁
            let v1 = &mut w.vm[i];
            v1.copy_from(&w.bv[i]);
            crate::simd::axpy_columns(v1.as_mut_slice(), uq.as_slice(), &cache.h_neg_t);
            // the wheelsets' forces on the rail, f = g − z − S U q₁ (eq. 6 at the new state,
            // the vehicle eliminated as in the reduced system)
            if !cache.s_dense.is_empty() {
                let su = &mut w.sx[..3 * nwi];
                crate::simd::mul_columns(su, uq.as_slice(), &cache.s_dense);
                for (f, s) in w.gz[3 * f0..3 * (f0 + nwi)].iter_mut().zip(su.iter()) {
                    *f -= s;
                }
            }
            let changed = self.vehicles[i].newmark_update(&nm, v1);
            // at rest: the same inputs (no deck, no prescribed motion, no wind, no change
            // of speed) next step
            w.resting[i] = !changed
                && w.flat_before
                && self.train.wind.is_none()
                && !self.train.changes_speed(i)
                && (f0..f0 + nwi).all(|ws| !self.geo.on[ws]);
        }
    }

    /// Whether each of `vehicles` has a wheelset on the deck (`live[i]`): the vehicles whose
    /// `U` ([`Blocks::block`]) is not zero.
    fn live_vehicles(&self, vehicles: &[usize], live: &mut [bool]) {
        for &i in vehicles {
            let f0 = self.first_ws[i];
            let nwi = self.train.vehicles[i].model.wheelsets.len();
            live[i] = self.geo.on[f0..f0 + nwi].iter().any(|&on| on);
        }
    }
}

/// The along-wind turbulence at vehicle `i`'s car body at time `t`: the deck's wind field
/// there (its end values beyond the deck), or 0 in a steady wind or for a vehicle the wind
/// does not load.
fn body_turbulence(
    buffeting: &Option<Arc<crate::bridge::buffeting::DeckBuffeting>>,
    train: &Train,
    i: usize,
    t: f64,
) -> f64 {
    match (
        buffeting.as_ref().and_then(|b| b.field()),
        train.wind_body_x(i, t),
    ) {
        (Some(f), Some(x)) => f.at(x, t)[0],
        _ => 0.0,
    }
}
