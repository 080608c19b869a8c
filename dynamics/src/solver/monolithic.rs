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

use super::{rail_prescribed, VehicleState, WheelForce};
use crate::bridge::{LaneScratch, ModalBridge, SHAPE_LANES};
use crate::newmark::Newmark;
use crate::track::RailProfile;
use crate::train::{Train, WheelsetRef};
use crate::vehicle::aero::WindBody;
use crate::vehicle::LinearVehicle;
use nalgebra::{DMatrix, DVector, Vector3};
use std::sync::Arc;

struct VehicleCache {
    /// `K̂⁻¹ e_d` of each DOF `d` the wind loads (the car body's, [`WindBody::of`]; none for
    /// vehicles without DOFs or body): the wind's share of `K̂⁻¹ b_v` is `Σ_d F_d K̂⁻¹ e_d`,
    /// five products of n values instead of a solve with the factor.
    wind: Vec<(usize, Vec<f64>)>,
    /// `[C_vw,0 … C_vw,l …]ᵀ` (3n_w × n, column after column; the structural zeros exact):
    /// `C_vw,lᵀ v_c` of every wheelset in the bridge's right-hand side as one product.
    cvw_t: Vec<f64>,
    /// S = Ŵ − Ĝᵀ K̂⁻¹ Ĝ (3n_w × 3n_w), column after column, its structural zeros exact
    /// ([`structural`]; empty when S = 0).
    s_dense: Vec<f64>,
    /// `−Hᵀ = −K̂⁻¹ Ĝ` (n × 3n_w, column after column): the back-substitution
    /// `v₁ = K̂⁻¹ b_v − Hᵀ U q₁` adds this times `U q₁`.
    h_neg_t: Vec<f64>,
    /// `K̂⁻¹ [a0 M + a1 C   a2 M + C   M]` (n × 3n, column after column): `K̂⁻¹ (M v_m + C v_c)`
    /// of the Newmark predictors `v_m = a0 v + a2 v̇ + v̈`, `v_c = a1 v + v̇` is this times
    /// `(v, v̇, v̈)`.
    e_state: Vec<f64>,
    /// `−K̂⁻¹ [K_vw,l  C_vw,l]` of each wheelset `l` (n × 6n_w, column after column): the rail
    /// terms of `K̂⁻¹ b_v` are this times `(r_l, ṙ_l − Ψ_l q_c)` of each wheelset.
    e_rail: Vec<f64>,
    /// `Ĝᵀ` (3n_w × n, column after column): `H b_v = Ĝᵀ (K̂⁻¹ b_v)`.
    g_tr: Vec<f64>,
}

/// What a step's geometry reads: the model, where each wheelset sits in the train and in
/// the blocks.
struct Placement<'a> {
    bridge: &'a ModalBridge,
    train: &'a Train,
    track: &'a dyn RailProfile,
    wheelsets: &'a [WheelsetRef],
    lane_at: &'a [(usize, usize)],
    /// The step size, s.
    h: f64,
}

/// A step's geometry, which depends on the time alone: the wheelsets' positions, their
/// prescribed rail motion and their rail shapes in the two layouts the step reads.
#[derive(Debug, Clone, Default)]
struct Geometry {
    /// The time it is made for, s.
    t: f64,
    /// Wheelset positions, m.
    x: Vec<f64>,
    /// Prescribed rail motion (irregularity and hunting) under each wheelset.
    presc: Vec<[Vector3<f64>; 3]>,
    /// Every vehicle's `U` (its wheelsets' rail shapes `Ψ`, zeros off the deck) mode after
    /// mode, vehicle after vehicle from `block_at[i]`: `blocks[block_at[i] + n · 3n_w + 3l + k]
    /// = Ψ_{w_l}[n][k]`, written with the shapes ([`ModalBridge::rail_shapes_lanes`]). Its
    /// products `Ψ q` ([`block_mul`]) are those of the step and of
    /// [`Monolithic::apply_reduced_with`].
    blocks: Vec<f64>,
    /// The same shapes as three rows of `N_b` per wheelset, component after component
    /// (`psi_t[(3w + k) N_b + n] = Ψ_w[n][k]`): a vehicle's wheelsets' rows, one after the
    /// other, are its `U` rail DOF after rail DOF ([`block_tr_add`]).
    psi_t: Vec<f64>,
    /// Per wheelset: on the deck.
    on: Vec<bool>,
    /// Scratch of [`ModalBridge::rail_shapes_lanes`].
    lanes: LaneScratch,
}

impl Geometry {
    fn new(nw: usize, nb: usize) -> Self {
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
    fn positions(&mut self, m: &Placement<'_>, t: f64) {
        self.t = t;
        for (x, ws) in self.x.iter_mut().zip(m.wheelsets) {
            *x = m.train.x_at(ws.offset_m, t);
        }
    }

    /// The prescribed rail motion (zero when `flat`) under the wheelsets `busy` at their
    /// [`Geometry::positions`] at `t`.
    fn rails(&mut self, m: &Placement<'_>, busy: &[usize], t: f64, flat: bool) {
        for &w in busy {
            self.presc[w] = if flat {
                [Vector3::zeros(); 3]
            } else {
                // the track's data a step on is read next step
                let ws = &m.wheelsets[w];
                m.track.prefetch(m.train.x_at(ws.offset_m, t + m.h));
                rail_prescribed(m.track, m.train, w, self.x[w], t)
            };
        }
    }

    /// The rail shapes of the wheelsets `busy` (ascending) at their positions, in both
    /// layouts, [`SHAPE_LANES`] at a time (each lane's shapes are those of a lane alone).
    fn shapes(&mut self, m: &Placement<'_>, busy: &[usize]) {
        let nb = m.bridge.n_modes();
        let mut psi_t = &mut self.psi_t[..];
        let mut base = 0;
        for chunk in busy.chunks(SHAPE_LANES) {
            let mut rows: [&mut [f64]; SHAPE_LANES] = Default::default();
            let mut at = [(0, 0); SHAPE_LANES];
            let mut xs = [0.0; SHAPE_LANES];
            for (((r, a), x), &w) in rows.iter_mut().zip(&mut at).zip(&mut xs).zip(chunk) {
                let tail_t = std::mem::take(&mut psi_t)
                    .split_at_mut((w - base) * 3 * nb)
                    .1;
                let (this_t, tail_t) = tail_t.split_at_mut(3 * nb);
                (*r, psi_t, base) = (this_t, tail_t, w + 1);
                *a = m.lane_at[w];
                *x = self.x[w];
            }
            let mut on = [false; SHAPE_LANES];
            let k = chunk.len();
            m.bridge.rail_shapes_lanes(
                &xs[..k],
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

/// The most bytes of rail shapes (both layouts) a step may take from the worker of
/// [`Monolithic::run_ahead`]: 192 KiB. Measured on the Tsing Ma model at 70 km/h, in the
/// placement of the cores where the hand-over is cheap: up to 154 KiB (100 modes under 8
/// coaches, 20 modes under 32) the runs took 36–43 % less time ahead; at 300 KiB (200
/// modes under 8 coaches, 50 under 32) the worker, writing lines the stepping core had
/// read, fell behind, and the runs took up to 20 % longer.
pub const AHEAD_MAX_BYTES: usize = 192 * 1024;

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
    ahead: Option<super::ahead::Ahead<Geometry>>,
    /// The worker stopped on its own (fell behind, or failed) since
    /// [`Monolithic::take_ahead_lost`] was last called.
    ahead_lost: bool,
    /// The worker's copy of the bridge and the train, kept for its next start.
    ahead_model: Option<(Arc<ModalBridge>, Arc<Train>)>,
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
        // Vehicles of one model (the same `Arc`, as the coaches of one train) share their
        // constant blocks, so a step reads one copy of them.
        let mut cache: Vec<Arc<VehicleCache>> = Vec::with_capacity(train.vehicles.len());
        for (tv, j) in train.vehicles.iter().zip(train.first_of_same_model()) {
            let c = match cache.get(j) {
                Some(first) => first.clone(),
                None => Arc::new(vehicle_cache(&tv.model, &nm)),
            };
            cache.push(c);
        }
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
            ahead: None,
            ahead_model: None,
            ahead_lost: false,
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
                let wind = s.train.wind_force(i, 0.0, u);
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
        self.assemble_reduced(&w.dhat, &w.busy_vehicles, &live)
    }

    /// How the reduced system is preconditioned: None by `D̂`, else by an earlier step's
    /// inverse carried forward to this order (`Lagged`: 0 before the second assembly, 1
    /// before the third, 2 after). For inspection and tests.
    pub fn preconditioner_order(&self) -> Option<usize> {
        if !self.work.costs.lagged() {
            return None;
        }
        let p = self.work.pre.as_ref()?;
        Some(usize::from(p.slope.is_some()) + usize::from(p.curvature.is_some()))
    }

    /// The wheelsets whose force can change (all but the moving forces), into `out`.
    pub(crate) fn forces_varying_into(&self, out: &mut Option<Vec<usize>>) {
        out.get_or_insert_with(Vec::new).clone_from(&self.varying);
    }

    /// Wheelset `w`'s rail shapes `Ψ_w[n]`, from its rows of [`Monolithic::psi_t`].
    fn shapes_w(&self, w: usize) -> Vec<[f64; 3]> {
        let nb = self.q.len();
        let r = &self.geo.psi_t[3 * nb * w..3 * nb * (w + 1)];
        (0..nb).map(|n| [r[n], r[nb + n], r[2 * nb + n]]).collect()
    }

    /// Vehicle `i`'s `U` mode after mode, in [`Monolithic::blocks`].
    fn block(&self, i: usize) -> &[f64] {
        let r3 = 3 * self.train.vehicles[i].model.wheelsets.len();
        &self.geo.blocks[self.block_at[i]..self.block_at[i] + r3 * self.q.len()]
    }

    /// Positions, Ψ and prescribed rail motion at time `t`, and the wheelsets and vehicles
    /// the step has to visit (`work.busy`, `work.busy_vehicles`).
    ///
    /// On the deck of an ideal track (no irregularity, no hunting), a wheelset that is off
    /// the deck at `t` and was so at the step before is left out (idle) when it is a moving
    /// force ([`Monolithic::inert`]: zero shapes, zero rail motion and its constant force
    /// already) or when its vehicle is at rest there: the vehicle's last step, off the deck
    /// and without wind on the train, left its state bit for bit as it was, so this step,
    /// with the same inputs, would too (the vehicles of a train that has not reached the
    /// bridge yet). An HSLM train on a short span has most of its axles off the deck. Every
    /// other wheelset is busy.
    ///
    /// With [`Monolithic::run_ahead`] (never on the ideal track, where the idle wheelsets
    /// depend on the state) every wheelset is busy, and the geometry was made by the worker:
    /// the same [`Geometry::positions`], [`Geometry::rails`] and [`Geometry::shapes`], the
    /// same values.
    fn update_geometry(&mut self, t: f64) {
        let flat = self.flat();
        let idle_allowed = flat && self.work.flat_before;
        self.work.flat_before = flat;
        if let Some(ahead) = &mut self.ahead {
            let geo = &mut self.geo;
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
                let busy = &mut self.work.busy;
                busy.clear();
                busy.extend(0..self.wheelsets.len());
                self.busy_vehicles();
                return;
            }
            // out of step with the worker, or the worker stopped or fell behind by its
            // give-up time: made here from now on
            self.ahead_lost |= ok.is_none();
            self.ahead = None;
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
        // the vehicles at rest stay so while they stay off the deck (one that does not is
        // stepped, which tells anew)
        let rest = &mut self.work.resting;
        for (i, tv) in self.train.vehicles.iter().enumerate() {
            let f0 = self.first_ws[i];
            rest[i] = rest[i]
                && idle_allowed
                && (f0..f0 + tv.model.wheelsets.len())
                    .all(|w| !geo.on[w] && !self.bridge.on_deck(geo.x[w]));
        }
        let busy = &mut self.work.busy;
        busy.clear();
        for (w, ws) in self.wheelsets.iter().enumerate() {
            let x = geo.x[w];
            if idle_allowed
                && !geo.on[w]
                && !self.bridge.on_deck(x)
                && (self.inert[w] || rest[ws.vehicle])
            {
                continue;
            }
            busy.push(w);
        }
        geo.rails(&model, busy, t, flat);
        geo.shapes(&model, busy);
        self.busy_vehicles();
    }

    /// The vehicles of the busy wheelsets and those without wheelsets, ascending, into
    /// `work.busy_vehicles`.
    fn busy_vehicles(&mut self) {
        let w = &mut self.work;
        let vehicles = &mut w.busy_vehicles;
        vehicles.clear();
        let mut loose = self.loose.iter().copied().peekable();
        for &ws in w.busy.iter() {
            let v = self.wheelsets[ws].vehicle;
            vehicles.extend(std::iter::from_fn(|| loose.next_if(|&l| l < v)));
            if vehicles.last() != Some(&v) {
                vehicles.push(v);
            }
        }
        vehicles.extend(loose);
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
        if self.ahead.is_some() {
            return true;
        }
        let (bridge, train) = self
            .ahead_model
            .get_or_insert_with(|| (Arc::new(self.bridge.clone()), Arc::new(self.train.clone())))
            .clone();
        let track = self.track.clone();
        let (wheelsets, lane_at, h) = (self.wheelsets.clone(), self.lane_at.clone(), self.nm.h);
        let busy: Vec<usize> = (0..wheelsets.len()).collect();
        let mut t = self.t;
        let (nw, nb) = (self.wheelsets.len(), self.bridge.n_modes());
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
        self.ahead = super::ahead::Ahead::spawn(slots, give_up, fill).ok();
        self.ahead.is_some()
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
        self.track.is_flat() && !self.train.hunting.is_active()
    }

    /// Whether the worker of [`Monolithic::run_ahead`] stopped on its own since the last call:
    /// it fell behind by its give-up time (it lacks a core) or failed, and each step makes
    /// its own geometry since.
    pub fn take_ahead_lost(&mut self) -> bool {
        std::mem::take(&mut self.ahead_lost)
    }

    /// Whether the geometry is made ahead ([`Monolithic::run_ahead`]).
    pub fn runs_ahead(&self) -> bool {
        self.ahead.is_some()
    }

    /// Stop making the geometry ahead: each step makes its own from now on, the same values.
    pub fn stop_ahead(&mut self) {
        self.ahead = None;
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
            let u = self.block(i);
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

    /// Advance one step of size `dt`.
    pub fn step(&mut self) {
        let nm = self.nm;
        let nb = self.q.len();
        let t1 = self.t + nm.h;
        self.update_geometry(t1);
        let mut w = std::mem::take(&mut self.work);
        self.live_vehicles(&w.busy_vehicles, &mut w.live);
        // Bridge predictors and the diagonal part.
        for n in 0..nb {
            let c = 2.0 * self.zeta[n] * self.omega[n];
            w.qm[n] = nm.mass_pred(self.q[n], self.qd[n], self.qdd[n]);
            w.qc[n] = nm.damp_pred(self.q[n], self.qd[n]);
            w.bq[n] = w.qm[n] + c * w.qc[n] + self.bridge.steady(n);
        }
        if let Some(b) = &self.buffeting {
            b.add_modal_force(t1, w.bq.as_mut_slice());
        }
        // y = K̂⁻¹ b_v, the state's part first (two vehicles' side by side), the rails'
        // after the wheelset loop
        self.state_parts(&mut w);
        for &i in &w.busy_vehicles {
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
            }
            let rails = &mut w.rails;
            rails.clear();
            // Ψ q_c, Ψ q_m of the vehicle's wheelsets (zeros off the deck)
            let r3 = 3 * model.wheelsets.len();
            let (uqc, uqm) = (&mut w.ux[..r3], &mut w.sx[..r3]);
            if w.live[i] {
                let u = self.block(i);
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
                    block_tr_add(self.block_t(i), gz, w.bq.as_mut_slice());
                }
            }
        }
        if !self.solve_iterative(&mut w) {
            let q1 = self.solve_direct(&w);
            w.cg_x.copy_from(&q1);
        }
        let q1 = &w.cg_x;
        for n in 0..nb {
            let (qd1, qdd1) = nm.update(q1[n], self.q[n], self.qd[n], self.qdd[n]);
            self.qd[n] = qd1;
            self.qdd[n] = qdd1;
        }
        self.q.copy_from(q1);
        // The deck's rail motion at the new state, once: its Ψ q₁ serves the back-substitution.
        self.deck_motion_at_end(&mut w);
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
            // at rest: the same inputs (no deck, no prescribed motion, no wind) next step
            w.resting[i] = !changed
                && w.flat_before
                && self.train.wind.is_none()
                && (f0..f0 + nwi).all(|ws| !self.geo.on[ws]);
        }
        self.t = t1;
        self.finish_outputs_of(&w.busy, &w.deck, Some(&w.gz));
        self.work = w;
    }

    /// `y = K̂⁻¹ (M v_m + C v_c)` of each busy vehicle with DOFs into `w.bv`, as the product
    /// of [`VehicleCache::e_state`] with its `(v, v̇, v̈)`, two vehicles at a time
    /// ([`crate::simd::mul_columns_pair`], the same values bit for bit as one by one).
    fn state_parts(&self, w: &mut Work) {
        let Work {
            busy_vehicles,
            bv,
            state,
            state2,
            ..
        } = w;
        let mut with_dofs = busy_vehicles
            .iter()
            .copied()
            .filter(|&i| self.train.vehicles[i].model.ndof() > 0);
        let fill = |s: &mut Vec<f64>, i: usize| {
            let vs = &self.vehicles[i];
            s.clear();
            for part in [&vs.v, &vs.vd, &vs.vdd] {
                s.extend_from_slice(part.as_slice());
            }
        };
        while let Some(i) = with_dofs.next() {
            fill(state, i);
            let Some(k) = with_dofs.next() else {
                crate::simd::mul_columns(bv[i].as_mut_slice(), state, &self.cache[i].e_state);
                break;
            };
            fill(state2, k);
            // i < k: the vehicles ascend
            let (head, tail) = bv.split_at_mut(k);
            crate::simd::mul_columns_pair(
                head[i].as_mut_slice(),
                state,
                &self.cache[i].e_state,
                tail[0].as_mut_slice(),
                state2,
                &self.cache[k].e_state,
            );
        }
    }

    /// Whether each of `vehicles` has a wheelset on the deck (`live[i]`): the vehicles whose
    /// `U` ([`Monolithic::block`]) is not zero.
    fn live_vehicles(&self, vehicles: &[usize], live: &mut [bool]) {
        for &i in vehicles {
            let f0 = self.first_ws[i];
            let nwi = self.train.vehicles[i].model.wheelsets.len();
            live[i] = self.geo.on[f0..f0 + nwi].iter().any(|&on| on);
        }
    }

    /// Vehicle `i`'s `U` rail DOF after rail DOF: its wheelsets' rows of
    /// [`Monolithic::psi_t`].
    fn block_t(&self, i: usize) -> &[f64] {
        let (nb, f0) = (self.q.len(), self.first_ws[i]);
        let nwi = self.train.vehicles[i].model.wheelsets.len();
        &self.geo.psi_t[3 * nb * f0..3 * nb * (f0 + nwi)]
    }

    /// Whether vehicle `i` adds `Uᵀ S U` to the reduced matrix: it has DOFs (a rail-space
    /// `S`) and a wheelset on the deck (`live`, [`Monolithic::live_vehicles`]).
    fn couples(&self, i: usize, live: &[bool]) -> bool {
        live[i] && !self.cache[i].s_dense.is_empty()
    }

    /// `y = A x` with `A = D̂ + Σ Uᵀ S U` (rail-space form, never assembled): per vehicle
    /// `U x` as one sum over the modes of its mode-major `U` ([`Monolithic::block`]; each
    /// rail value summed over the modes in order, as one wheelset's `Ψ q` sums them),
    /// `S (U x)` with the dense `S` (column order), and `Uᵀ` of that as one product over the
    /// vehicle's rows of [`Monolithic::psi_t`] ([`block_tr_add`]). Two vehicles' `U x` and
    /// `S (U x)` go side by side ([`crate::simd::mul_columns_pair`]: each of these short sums
    /// is a chain of dependent additions, which the other's fills), the same values bit for
    /// bit; their `Uᵀ` into `y` one vehicle after the other, in order.
    #[allow(clippy::too_many_arguments)]
    fn apply_reduced_with(
        &self,
        vehicles: &[usize],
        live: &[bool],
        dhat: &DVector<f64>,
        x: &[f64],
        y: &mut [f64],
        ux: &mut [f64],
        sx: &mut [f64],
    ) {
        let nb = x.len();
        for n in 0..nb {
            y[n] = dhat[n] * x[n];
        }
        // two vehicles at a time: their U x and S (U x) side by side, then Uᵀ of each in
        // order (the sums into y as one vehicle after the other)
        let mut coupled = vehicles.iter().copied().filter(|&i| self.couples(i, live));
        let rows = |i: usize| 3 * self.train.vehicles[i].model.wheelsets.len();
        while let Some(i) = coupled.next() {
            let ri = rows(i);
            let Some(k) = coupled.next() else {
                let (ux, sx) = (&mut ux[..ri], &mut sx[..ri]);
                block_mul(self.block(i), x, ux);
                crate::simd::mul_columns(sx, ux, &self.cache[i].s_dense);
                block_tr_add(self.block_t(i), sx, y);
                break;
            };
            let rk = rows(k);
            let (ux_i, ux_k) = ux[..ri + rk].split_at_mut(ri);
            let (sx_i, sx_k) = sx[..ri + rk].split_at_mut(ri);
            let (ci, ck) = (&self.cache[i].s_dense, &self.cache[k].s_dense);
            crate::simd::mul_columns_pair(ux_i, x, self.block(i), ux_k, x, self.block(k));
            crate::simd::mul_columns_pair(sx_i, ux_i, ci, sx_k, ux_k, ck);
            block_tr_add(self.block_t(i), sx_i, y);
            block_tr_add(self.block_t(k), sx_k, y);
        }
    }

    /// Preconditioned conjugate gradients on the reduced bridge system, to round-off.
    ///
    /// Two preconditioners, chosen once by the sizes ([`Costs`]): where a product with an
    /// `N_b × N_b` matrix is cheap against an application of `A` (few modes under many
    /// wheelsets), the inverse of the reduced matrix of an earlier step, `A_k = D̂ + Σ Uᵀ S U` at
    /// the wheelset positions of step k, carried forward in time to second order
    /// ([`Lagged`]: the matrix changes only as the wheelsets move, smoothly, so a few
    /// iterations suffice); otherwise `D̂`. Either preconditioner `M⁻¹` starts the iteration
    /// from `M⁻¹ b` plus the extrapolated correction ([`Corrections`]): the corrections
    /// `q − M⁻¹ b` of the last solves vary smoothly, as `q` and the matrices do, so a cubic
    /// through the last four predicts the next one. From such a start (a non-zero
    /// correction added) at least one iteration is made: the start may already pass the
    /// test below, within 10⁻¹⁴ of its terms, and the step's accelerations, `4/h²` times its
    /// displacements, would keep that error (on the default case the deck's vertical
    /// acceleration then moved by 2.8·10⁻⁷ of its largest value); one iteration takes it far
    /// below, as the iterations from `M⁻¹ b` do (2.9·10⁻⁸ from the co-simulation there,
    /// against 7.1·10⁻⁸ before).
    ///
    /// Where no vehicle on the deck is coupled to the modes (moving forces, or no vehicle
    /// there), `A = D̂` and `q = D̂⁻¹ b` is taken at once: no iteration, nothing assembled.
    ///
    /// The lagged inverse is renewed (assembled at the next step) when a solve's
    /// iterations, at the cost `c` of one each, pass the average cost per solve since its
    /// assembly, the assembly's cost `C` included: after the `k`-th solve with `iₖ`
    /// iterations, when `iₖ c > (C + c Σⱼ≤ₖ iⱼ) / k`. The iterations grow as the
    /// preconditioner ages, and renewing where the running cost reaches the average is what
    /// keeps the average least (the rule for replacing an item whose running cost grows with
    /// age). The step of the assembly itself needs none and does not count.
    ///
    /// Measured on the bench case (20 modes under 32 wheelsets, 22 378 steps): 2.11
    /// iterations per solve and 584 assemblies from `M⁻¹ b` alone with the earlier rule
    /// (renew when the iterations beyond the fewest since the assembly have cost an
    /// assembly), 1.15 and 163 with the extrapolation, 1.02 and 220 with both (and at least
    /// one iteration from an extrapolated start): 2.02 applications of `A` a step against
    /// 3.11. On the default case (65 059 steps) 1.28 iterations per solve and 1000
    /// assemblies, 0.81 and 1505, and with both 338 assemblies and 1.85 applications a step
    /// against 2.28.
    ///
    /// The solution is left in `w.cg_x`; returns false when it has not reached round-off
    /// level within [`MAX_CG_ITERATIONS`] (or the carried-forward preconditioner has stopped
    /// being positive definite), so that the direct solver takes over.
    fn solve_iterative(&self, w: &mut Work) -> bool {
        let nb = w.bq.len();
        let lagged = w.costs.lagged();
        // the preconditioner made at this step's own positions (its iterations count for
        // nothing: the steps after it are what a lagged one is judged by)
        let fresh = lagged && w.pre.is_none();
        if lagged {
            w.solves += 1;
        }
        // No vehicle on the deck is coupled to the modes (moving forces, or none there):
        // `A = D̂`, solved exactly, with no iteration and nothing to assemble.
        if !w.busy_vehicles.iter().any(|&i| self.couples(i, &w.live)) {
            for n in 0..nb {
                w.cg_x[n] = w.bq[n] / w.dhat[n];
            }
            w.corrections.clear();
            return true;
        }
        if fresh {
            let a = self.assemble_reduced(&w.dhat, &w.busy_vehicles, &w.live);
            // None (not positive definite) leaves the step to the direct solver
            let Some(lagged) = Lagged::new(&a, w.solves, &w.assembled) else {
                return false;
            };
            w.pre = Some(lagged);
            if w.assembled.len() == 2 {
                w.assembled.remove(0);
            }
            w.assembled.push((a, w.solves));
            w.pre_solves = 0;
            w.pre_iterations = 0;
        }
        if let Some(p) = w.pre.as_ref().filter(|_| lagged) {
            p.at(w.solves, &mut w.pre_now);
        }
        if fresh {
            // a new preconditioner: the corrections of the old one do not continue
            w.corrections.clear();
        }
        let Work {
            pre_now,
            bq,
            dhat,
            corrections,
            cg_base: base,
            cg_x: x,
            cg_r: r,
            cg_z: z,
            cg_p: p,
            cg_ap: ap,
            cg_t: tmp,
            ux,
            sx,
            busy_vehicles,
            live,
            ..
        } = w;
        let inverse = Some(&*pre_now).filter(|_| lagged);
        let dhat: &DVector<f64> = dhat;
        let mut precondition = |v: &mut DVector<f64>| match inverse {
            Some(a) => {
                dense_mul(a, v.as_slice(), tmp.as_mut_slice());
                v.copy_from(tmp);
            }
            None => v.component_div_assign(dhat),
        };
        if bq.amax() == 0.0 {
            x.fill(0.0);
            corrections.push(x, x);
            return true;
        }
        // x₀ = M⁻¹ b + the extrapolated correction
        base.copy_from(bq);
        precondition(base);
        x.copy_from(base);
        let extrapolated = corrections.extrapolate_into(x);
        self.apply_reduced_with(
            busy_vehicles,
            live,
            dhat,
            x.as_slice(),
            ap.as_mut_slice(),
            ux,
            sx,
        );
        r.copy_from(bq);
        *r -= &*ap;
        z.copy_from(r);
        precondition(z);
        p.copy_from(z);
        let mut rz = r.dot(z);
        if rz < 0.0 {
            // a carried-forward preconditioner no longer positive definite
            w.pre = None;
            corrections.clear();
            return false;
        }
        let b = bq.as_slice();
        for it in 0..MAX_CG_ITERATIONS {
            // Converged when every mode's residual is at round-off level relative to its own
            // terms, so that small (e.g. lateral) modal coordinates are as exact as large ones.
            let converged = (it > 0 || !extrapolated)
                && (0..nb)
                    .all(|n| r[n].abs() <= CG_TOLERANCE * (b[n].abs() + dhat[n] * x[n].abs()));
            if converged {
                corrections.push(x, base);
                if lagged && !fresh {
                    w.pre_solves += 1;
                    w.pre_iterations += it;
                    let c = w.costs.iteration();
                    let (k, total) = (w.pre_solves as f64, w.pre_iterations as f64);
                    if it as f64 * c * k > w.costs.assembly + total * c {
                        w.pre = None;
                    }
                }
                return true;
            }
            self.apply_reduced_with(
                busy_vehicles,
                live,
                dhat,
                p.as_slice(),
                ap.as_mut_slice(),
                ux,
                sx,
            );
            let pap = p.dot(ap);
            if pap <= 0.0 {
                w.pre = None;
                corrections.clear();
                return false;
            }
            let alpha = rz / pap;
            x.axpy(alpha, p, 1.0);
            r.axpy(-alpha, ap, 1.0);
            z.copy_from(r);
            precondition(z);
            let rz1 = r.dot(z);
            if rz1 < 0.0 {
                w.pre = None;
                corrections.clear();
                return false;
            }
            let beta = rz1 / rz;
            rz = rz1;
            p.axpy(1.0, z, beta);
        }
        w.pre = None;
        corrections.clear();
        false
    }

    /// Assemble `A = D̂ + Σ Uᵀ S U` and solve by Cholesky.
    fn solve_direct(&self, w: &Work) -> DVector<f64> {
        self.assemble_reduced(&w.dhat, &w.busy_vehicles, &w.live)
            .cholesky()
            .expect("reduced bridge matrix is positive definite")
            .solve(&w.bq)
    }

    /// `A = D̂ + Σ Uᵀ S U` at the current wheelset positions, from each busy vehicle's `U`
    /// in its two layouts ([`Monolithic::block`] and [`Monolithic::block_t`]): column `n` of
    /// `S U` is `S` times column `n` of `U` (the mode-major block's `n`-th run), and the upper
    /// part (rows `0..=n`) of column `n` of
    /// `Uᵀ (S U)` is the rail-major rows' first `n + 1` values taken with those, each a
    /// product over whole columns; the upper triangle is then mirrored below, so that `A` is
    /// symmetric bit for bit (off-deck wheelsets have zero shapes and add exact zeros).
    fn assemble_reduced(
        &self,
        dhat: &DVector<f64>,
        vehicles: &[usize],
        live: &[bool],
    ) -> DMatrix<f64> {
        let nb = dhat.len();
        let mut a = vec![0.0; nb * nb];
        for n in 0..nb {
            a[n * nb + n] = dhat[n];
        }
        let mut su = Vec::new();
        for &i in vehicles {
            if !self.couples(i, live) {
                continue;
            }
            let s = &self.cache[i].s_dense;
            let u = self.block(i);
            let m = u.len() / nb;
            su.resize(m, 0.0);
            let ut = self.block_t(i);
            for (n, (col, un)) in a.chunks_exact_mut(nb).zip(u.chunks_exact(m)).enumerate() {
                crate::simd::mul_columns(&mut su, un, s);
                crate::simd::axpy_columns_strided(&mut col[..=n], &su, ut, nb);
            }
        }
        for j in 0..nb {
            for i in 0..j {
                a[i * nb + j] = a[j * nb + i];
            }
        }
        DMatrix::from_vec(nb, nb, a)
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

/// Iterations of the conjugate-gradient path before the direct solver takes over.
const MAX_CG_ITERATIONS: usize = 12;
/// Operation counts (multiply-adds) of the pieces of the iterative solve, from the sizes.
#[derive(Debug, Clone, Copy, Default)]
struct Costs {
    /// One application of `A`: `Ψ x`, `S`, `Ψᵀ` for every wheelset.
    apply: f64,
    /// One product with the `N_b × N_b` inverse of the preconditioner (counted as the two
    /// triangular solves with its factor, `2 N_b²`).
    inverse_product: f64,
    /// Assembling and inverting `A`, and carrying the inverse forward ([`Lagged`]).
    assembly: f64,
}

impl Costs {
    fn of(nb: usize, train: &Train) -> Costs {
        let nb = nb as f64;
        // the inverse (N_b³) and the five products of Lagged's terms
        let (mut apply, mut assembly) = (0.0, 6.0 * nb * nb * nb);
        for tv in &train.vehicles {
            let r = 3.0 * tv.model.wheelsets.len() as f64;
            apply += 2.0 * r * nb + r * r;
            assembly += r * r * nb + r * nb * nb;
        }
        Costs {
            apply,
            inverse_product: 2.0 * nb * nb,
            assembly,
        }
    }

    /// Whether the inverse of an earlier step's matrix is the preconditioner: when a product
    /// with it costs at most a quarter of an application of `A` (measured: 20 modes under 32
    /// wheelsets, the bench case, 2.1 iterations per solve and an assembly every 38 steps;
    /// not 200 modes under 128 wheelsets, whose matrix costs as much as the application, and
    /// where `D̂` was measured faster).
    fn lagged(&self) -> bool {
        4.0 * self.inverse_product <= self.apply
    }

    /// One iteration with the factor.
    fn iteration(&self) -> f64 {
        self.apply + self.inverse_product
    }
}
/// Residual of each mode, relative to the size of its own terms, at which the iteration
/// counts as exact.
const CG_TOLERANCE: f64 = 1e-14;

/// `Ψ q` of one wheelset, the modes summed in order (the reference of the block products).
#[cfg(test)]
fn psi_mul(psi: &[[f64; 3]], q: &[f64]) -> Vector3<f64> {
    let mut u = Vector3::zeros();
    for (p, qn) in psi.iter().zip(q.iter()) {
        u.x += p[0] * qn;
        u.y += p[1] * qn;
        u.z += p[2] * qn;
    }
    u
}

/// `y += Uᵀ s` for a vehicle's `U` rail DOF after rail DOF (`ut[(3l + k) N_b + n]`, its
/// wheelsets' rows of [`Monolithic::psi_t`]): the rail DOFs' columns added in order (`s`
/// finite: the zero rows of wheelsets off the deck add exact zeros).
fn block_tr_add(ut: &[f64], s: &[f64], y: &mut [f64]) {
    crate::simd::axpy_columns(y, s, ut);
}

/// `out = U x` for a mode-major block `u` ([`Monolithic::blocks`]): each value summed over
/// the modes in order, from zero (as one wheelset's `Ψ q` sums them).
fn block_mul(u: &[f64], x: &[f64], out: &mut [f64]) {
    crate::simd::mul_columns(out, x, u);
}

/// `Ψ a`, `Ψ b`, `Ψ c` in one pass over Ψ (each sum over the modes in order).
fn psi_mul3(psi: &[[f64; 3]], a: &[f64], b: &[f64], c: &[f64]) -> [Vector3<f64>; 3] {
    let mut r = [Vector3::zeros(); 3];
    for (n, p) in psi.iter().enumerate() {
        let (an, bn, cn) = (a[n], b[n], c[n]);
        for k in 0..3 {
            r[0][k] += p[k] * an;
            r[1][k] += p[k] * bn;
            r[2][k] += p[k] * cn;
        }
    }
    r
}

/// The corrections `eₖ = qₖ − M⁻¹ bₖ` of the last solves of the reduced system with one
/// preconditioner `M⁻¹`, newest first, and their extrapolation to the next solve: the
/// polynomial of degree `m − 1` through the last `m ≤ 4` of them (consecutive solves of
/// steps of one size), `ê = Σⱼ (−1)ʲ C(m, j+1) eⱼ` (with four, `4e₀ − 6e₁ + 4e₂ − e₃`). The
/// start `M⁻¹ b + ê` changes how many iterations the conjugate gradients need, not the
/// tolerance their solution meets.
#[derive(Debug, Clone, Default)]
struct Corrections {
    /// A ring of the last corrections; `newest` indexes the newest.
    ring: [DVector<f64>; CORRECTIONS],
    newest: usize,
    /// How many of them are of consecutive solves since the last [`Corrections::clear`].
    count: usize,
}

/// How many past corrections the extrapolation goes through (a cubic; the weights are
/// spelt out up to four in [`Corrections::extrapolate_into`]). Measured with the earlier renewal
/// rule, iterations per solve through none and one to six: bench case (lagged inverse)
/// 2.11, 2.14, 1.81, 1.36, 1.15, 1.11, 1.10; default case 1.28, 1.17, 1.07, 0.94, 0.81,
/// 0.77, 0.88.
const CORRECTIONS: usize = 4;

impl Corrections {
    fn new(nb: usize) -> Self {
        Corrections {
            ring: std::array::from_fn(|_| DVector::zeros(nb)),
            newest: 0,
            count: 0,
        }
    }

    /// Forgets the corrections (a new preconditioner, or a solve that did not converge).
    fn clear(&mut self) {
        self.count = 0;
    }

    /// Records the correction `x − base` of a converged solve.
    fn push(&mut self, x: &DVector<f64>, base: &DVector<f64>) {
        self.newest = (self.newest + 1) % CORRECTIONS;
        let e = &mut self.ring[self.newest];
        for ((e, x), b) in e.iter_mut().zip(x.iter()).zip(base.iter()) {
            *e = x - b;
        }
        self.count = (self.count + 1).min(CORRECTIONS);
    }

    /// `x += ê`, the extrapolated correction of the next solve; whether that moved `x` (false
    /// without corrections or with all of them zero).
    fn extrapolate_into(&self, x: &mut DVector<f64>) -> bool {
        let e = |j: usize| self.ring[(self.newest + CORRECTIONS - j) % CORRECTIONS].as_slice();
        let x = x.as_mut_slice();
        // whether any correction is non-zero (the solve at an assembly, exact from `M⁻¹ b`,
        // leaves a zero one)
        let mut moved = false;
        let mut add = |x: &mut f64, d: f64| {
            moved |= d != 0.0;
            *x += d;
        };
        match self.count {
            0 => {}
            1 => x.iter_mut().zip(e(0)).for_each(|(x, &a)| add(x, a)),
            2 => {
                for ((x, a), b) in x.iter_mut().zip(e(0)).zip(e(1)) {
                    add(x, 2.0 * a - b);
                }
            }
            3 => {
                for (((x, a), b), c) in x.iter_mut().zip(e(0)).zip(e(1)).zip(e(2)) {
                    add(x, 3.0 * (a - b) + c);
                }
            }
            _ => {
                for ((((x, a), b), c), d) in x.iter_mut().zip(e(0)).zip(e(1)).zip(e(2)).zip(e(3)) {
                    add(x, 4.0 * (a + c) - 6.0 * b - d);
                }
            }
        }
        moved
    }
}

/// The lagged preconditioner: the inverse `P = A_k⁻¹` of the reduced matrix assembled at
/// solve `k`, carried forward in time to second order.
///
/// The reduced matrix changes only as the wheelsets move along the shapes, smoothly in time:
/// `A(k + τ) = A_k + τ A₁ + τ² A₂ + O(τ³)` (τ in solves, i.e. steps), so that
///
/// ```text
/// A(k + τ)⁻¹ = P − τ P A₁ P + τ² P (A₁ P A₁ − A₂) P + O(τ³) .
/// ```
///
/// `A₁` and `A₂` are the first and half the second derivative at `k` of the parabola through
/// the last three assembled matrices (`A_k` and the two before it, whatever solves apart);
/// with only two, the secant's slope and no second-order term; with none, `P` alone. The
/// preconditioner of solve `k + τ`, `P − τ B₁ + τ² B₂`, is formed once per solve (`N_b²`
/// multiply-adds) so that each iteration still takes one product with it. It is a
/// preconditioner only: the iteration's residual is always that of the true `A`, so a poor
/// extrapolation (a jump in the matrix's history) costs iterations, never accuracy, and one
/// that is no longer positive definite hands the step to the direct solver and a new
/// assembly. On the bench case it takes 3.1 applications of `A` a step against 4.3 for `P`
/// alone (3.3 to first order), with an assembly every 38 steps against 23.5.
#[derive(Debug, Clone)]
struct Lagged {
    inverse: DMatrix<f64>,
    /// `B₁ = P A₁ P` and `B₂ = P (A₁ P A₁ − A₂) P`, per solve and per solve squared; None
    /// without enough earlier assemblies.
    slope: Option<DMatrix<f64>>,
    curvature: Option<DMatrix<f64>>,
    /// The solve `k` of the assembly.
    made_at: usize,
}

impl Lagged {
    /// From the matrix `a` assembled at solve `k` and the earlier ones `before` (oldest
    /// first, at most two used, each at a solve before `k`); None if `a` is not positive
    /// definite.
    fn new(a: &DMatrix<f64>, k: usize, before: &[(DMatrix<f64>, usize)]) -> Option<Lagged> {
        let inverse = spd_inverse(a.clone())?;
        let at = |j: usize| j as f64 - k as f64;
        // A₁ and A₂ of the interpolating polynomial in τ through the nodes (Lagrange's
        // weights' first and half their second derivatives at τ = 0)
        let (a1, a2) = match before {
            [.., (m2, k2), (m1, k1)] => {
                let (t1, t2) = (at(*k1), at(*k2));
                let d = [
                    -(1.0 / t1 + 1.0 / t2),
                    -t2 / (t1 * (t1 - t2)),
                    -t1 / (t2 * (t2 - t1)),
                ];
                let h = [
                    1.0 / (t1 * t2),
                    1.0 / (t1 * (t1 - t2)),
                    1.0 / (t2 * (t2 - t1)),
                ];
                (
                    Some(a * d[0] + m1 * d[1] + m2 * d[2]),
                    Some(a * h[0] + m1 * h[1] + m2 * h[2]),
                )
            }
            [(m1, k1)] => (Some((a - m1) / -at(*k1)), None),
            [] => (None, None),
        };
        let pa1 = a1.as_ref().map(|a1| &inverse * a1);
        let slope = pa1.as_ref().map(|x| x * &inverse);
        let curvature = match (&a1, &a2, &pa1) {
            (Some(a1), Some(a2), Some(pa1)) => Some(&inverse * (a1 * pa1 - a2) * &inverse),
            _ => None,
        };
        Some(Lagged {
            inverse,
            slope,
            curvature,
            made_at: k,
        })
    }

    /// The preconditioner of solve `k + τ`, `P − τ B₁ + τ² B₂`, into `out`.
    fn at(&self, solve: usize, out: &mut DMatrix<f64>) {
        let tau = solve.saturating_sub(self.made_at) as f64;
        let o = out.as_mut_slice();
        o.copy_from_slice(self.inverse.as_slice());
        if tau > 0.0 {
            // (P − τ B₁) + τ² B₂, each a product then a sum per entry
            if let Some(b1) = &self.slope {
                crate::simd::axpy(o, -tau, b1.as_slice());
            }
            if let Some(b2) = &self.curvature {
                crate::simd::axpy(o, tau * tau, b2.as_slice());
            }
        }
    }
}

/// The inverse of a symmetric positive definite matrix by Gauss–Jordan sweeps in place (the
/// pivots of such a matrix are positive, so none is exchanged): for each k, row k is divided
/// by the pivot `d = a_kk`, every other column j loses `a_kj` times column k, and column k
/// becomes `−a_ik / d` with `1/d` on the diagonal. Each sweep is a run of contiguous
/// multiply-adds over the columns, `N³` in all. None if a pivot is not positive and finite.
fn spd_inverse(mut a: DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = a.nrows();
    let mut ck = vec![0.0; n];
    for k in 0..n {
        let d = a[(k, k)];
        if !(d > 0.0 && d.is_finite()) {
            return None;
        }
        ck.copy_from_slice(a.column(k).as_slice());
        let data = a.as_mut_slice();
        for (j, col) in data.chunks_exact_mut(n).enumerate() {
            if j == k {
                continue;
            }
            let f = col[k] / d;
            crate::simd::axpy(col, -f, &ck);
            col[k] = f;
        }
        let col = &mut data[k * n..(k + 1) * n];
        for (o, &c) in col.iter_mut().zip(&ck) {
            *o = -c / d;
        }
        col[k] = 1.0 / d;
    }
    Some(a)
}

/// `y = A x` for a square column-major `A`, column by column.
fn dense_mul(a: &DMatrix<f64>, x: &[f64], y: &mut [f64]) {
    crate::simd::mul_columns(y, x, a.as_slice());
}

/// `out += Ψᵀ f` (one wheelset's generalised forces).
fn psi_tr_add(psi: &[[f64; 3]], f: &Vector3<f64>, out: &mut [f64]) {
    crate::simd::project_force(out, psi, [f.x, f.y, f.z]);
}

/// Preallocated buffers of one step.
#[derive(Default)]
struct Work {
    qm: DVector<f64>,
    qc: DVector<f64>,
    /// `D̂ = diag(a0 + a1 2ζω + ω²)`, set once by [`Monolithic::new`].
    dhat: DVector<f64>,
    bq: DVector<f64>,
    /// The preconditioner: the inverse of the reduced matrix of an earlier step, carried
    /// forward ([`Lagged`]; None: assemble at the next solve; a product with it is a run of
    /// independent multiply-adds, where the two triangular solves of its Cholesky factor are
    /// chains), the solves made with it since its assembly and their iterations.
    pre: Option<Lagged>,
    pre_solves: usize,
    pre_iterations: usize,
    /// The last (up to two) assembled reduced matrices, oldest first, with the solve each
    /// was assembled at; the solves so far (with the lagged preconditioner) and the
    /// preconditioner of this solve ([`Lagged::at`]).
    assembled: Vec<(DMatrix<f64>, usize)>,
    solves: usize,
    pre_now: DMatrix<f64>,
    costs: Costs,
    /// The corrections `q − M⁻¹ b` of the last solves (the initial guess of the next).
    corrections: Corrections,
    /// `M⁻¹ b` of the current solve.
    cg_base: DVector<f64>,
    /// The conjugate-gradient vectors (N_b) and rail-space scratch (3 n_w of a vehicle).
    cg_x: DVector<f64>,
    cg_r: DVector<f64>,
    cg_z: DVector<f64>,
    cg_p: DVector<f64>,
    cg_ap: DVector<f64>,
    cg_t: DVector<f64>,
    ux: Vec<f64>,
    sx: Vec<f64>,
    /// Per vehicle: a wheelset of it on the deck ([`Monolithic::live_vehicles`]).
    live: Vec<bool>,
    /// Scratch of a vehicle's `(v, v̇, v̈)` and of its wheelsets' `(r, ṙ − Ψ q_c)`.
    state: Vec<f64>,
    /// The same of a second vehicle ([`Monolithic::state_parts`] takes two at a time).
    state2: Vec<f64>,
    rails: Vec<f64>,
    /// Per vehicle (n values): the wind's share of `K̂⁻¹ b_v`, then the new state `v₁`.
    vm: Vec<DVector<f64>>,
    /// Per vehicle (n values): the damping predictor `v_c = a1 v + v̇`.
    vc: Vec<DVector<f64>>,
    /// Per vehicle (n values): `K̂⁻¹ b_v`.
    bv: Vec<DVector<f64>>,
    /// Per vehicle (3 n_w values): `H b_v`, then `U q₁`.
    z: Vec<DVector<f64>>,
    /// The deck's part of the rail motion under each wheelset at the end of the step.
    deck: Vec<[Vector3<f64>; 3]>,
    /// Per wheelset on the deck: `Ψ` times the bridge's damping and mass predictors
    /// (`Ψ q_c`, `Ψ q_m`), from which the rail's velocity and acceleration at the end of the
    /// step follow with `Ψ q₁` ([`Monolithic::deck_motion_at_end`]).
    pred: Vec<[Vector3<f64>; 2]>,
    /// One vehicle's `g_l + C_vw,lᵀ v_c`, its wheelsets' one after the other (3 n_w).
    gv: Vec<f64>,
    /// Per wheelset of a vehicle with DOFs (three values each): `g − z`, then its force on
    /// the rail at the end of the step (`− S U q₁` taken off in the back-substitution).
    gz: Vec<f64>,
    /// The wheelsets and vehicles the step visits, ascending ([`Monolithic::update_geometry`]).
    busy: Vec<usize>,
    busy_vehicles: Vec<usize>,
    /// Whether the prescribed rail motion was zero everywhere at the last geometry update.
    flat_before: bool,
    /// Per vehicle: its last step left its state bit for bit the same, off the deck of an
    /// ideal track without wind on the train (kept while it stays off the deck).
    resting: Vec<bool>,
}

impl Work {
    fn new(nb: usize, train: &Train) -> Self {
        let per = |f: &dyn Fn(&LinearVehicle) -> usize| -> Vec<DVector<f64>> {
            train
                .vehicles
                .iter()
                .map(|v| DVector::zeros(f(&v.model)))
                .collect()
        };
        let wmax = train
            .vehicles
            .iter()
            .map(|v| 3 * v.model.wheelsets.len())
            .max()
            .unwrap_or(0);
        Work {
            qm: DVector::zeros(nb),
            qc: DVector::zeros(nb),
            dhat: DVector::zeros(nb),
            bq: DVector::zeros(nb),
            pre: None,
            pre_solves: 0,
            pre_iterations: 0,
            assembled: Vec::new(),
            solves: 0,
            pre_now: DMatrix::zeros(nb, nb),
            costs: Costs::of(nb, train),
            corrections: Corrections::new(nb),
            cg_base: DVector::zeros(nb),
            cg_x: DVector::zeros(nb),
            cg_r: DVector::zeros(nb),
            cg_z: DVector::zeros(nb),
            cg_p: DVector::zeros(nb),
            cg_ap: DVector::zeros(nb),
            cg_t: DVector::zeros(nb),
            // two vehicles' rail DOFs (apply_reduced_with takes them in pairs)
            ux: vec![0.0; 2 * wmax],
            sx: vec![0.0; 2 * wmax],
            live: vec![false; train.vehicles.len()],
            state: Vec::new(),
            state2: Vec::new(),
            rails: Vec::new(),
            vm: per(&|m| m.ndof()),
            vc: per(&|m| m.ndof()),
            bv: per(&|m| m.ndof()),
            z: per(&|m| 3 * m.wheelsets.len()),
            deck: Vec::new(),
            pred: vec![[Vector3::zeros(); 2]; train.wheelsets().len()],
            gv: vec![0.0; wmax],
            gz: vec![0.0; 3 * train.wheelsets().len()],
            busy: Vec::new(),
            busy_vehicles: Vec::new(),
            flat_before: false,
            resting: vec![false; train.vehicles.len()],
        }
    }
}

fn vehicle_cache(model: &LinearVehicle, nm: &Newmark) -> VehicleCache {
    let n = model.ndof();
    let nw = model.wheelsets.len();
    let mut s = DMatrix::zeros(3 * nw, 3 * nw);
    for (l, c) in model.wheelsets.iter().enumerate() {
        let w_hat = nm.a0 * c.m_w + nm.a1 * c.c_ww + c.k_ww;
        s.view_mut((3 * l, 3 * l), (3, 3)).copy_from(&w_hat);
    }
    let mut cvw = DMatrix::zeros(n, 3 * nw);
    for (l, c) in model.wheelsets.iter().enumerate() {
        cvw.columns_mut(3 * l, 3).copy_from(&c.c_vw);
    }
    let cvw_t = cvw.transpose().as_slice().to_vec();
    if n == 0 {
        return VehicleCache {
            wind: Vec::new(),
            cvw_t,
            s_dense: structural(&s),
            h_neg_t: Vec::new(),
            e_state: Vec::new(),
            e_rail: Vec::new(),
            g_tr: Vec::new(),
        };
    }
    let khat = nm.a0 * &model.m + nm.a1 * &model.c + &model.k;
    let chol = khat
        .cholesky()
        .expect("a0 M + a1 C + K of a vehicle is positive definite");
    let ghat: Vec<DMatrix<f64>> = model
        .wheelsets
        .iter()
        .map(|c| &c.k_vw + nm.a1 * &c.c_vw)
        .collect();
    let mut g = DMatrix::zeros(n, 3 * nw);
    for (l, gl) in ghat.iter().enumerate() {
        g.view_mut((0, 3 * l), (n, 3)).copy_from(gl);
    }
    let kinv_g = chol.solve(&g); // n × 3nw
    s -= g.tr_mul(&kinv_g);
    let h_neg_t = (-&kinv_g).as_slice().to_vec();
    let mut state = DMatrix::zeros(n, 3 * n);
    state
        .columns_mut(0, n)
        .copy_from(&(nm.a0 * &model.m + nm.a1 * &model.c));
    state
        .columns_mut(n, n)
        .copy_from(&(nm.a2 * &model.m + &model.c));
    state.columns_mut(2 * n, n).copy_from(&model.m);
    let mut rail = DMatrix::zeros(n, 6 * nw);
    for (l, c) in model.wheelsets.iter().enumerate() {
        rail.columns_mut(6 * l, 3).copy_from(&(-&c.k_vw));
        rail.columns_mut(6 * l + 3, 3).copy_from(&(-&c.c_vw));
    }
    let e_state = chol.solve(&state).as_slice().to_vec();
    let e_rail = chol.solve(&rail).as_slice().to_vec();
    let g_tr = g.transpose().as_slice().to_vec();
    let wind = WindBody::unit_responses(model, |e| {
        let x = chol.solve(&DVector::from_column_slice(e));
        e.copy_from_slice(x.as_slice());
    });
    VehicleCache {
        wind,
        cvw_t,
        s_dense: structural(&s),
        h_neg_t,
        e_state,
        e_rail,
        g_tr,
    }
}

/// A small matrix, column after column, with the entries below 1e-14 of the largest set to
/// exact zeros (structural zeros of the suspension layout, e.g. between lateral and vertical
/// rail DOFs, left as round-off by the Schur complement); empty when it is zero.
fn structural(s: &DMatrix<f64>) -> Vec<f64> {
    let max = s.amax();
    if max == 0.0 {
        return Vec::new();
    }
    let tol = 1e-14 * max;
    s.iter()
        .map(|&v| if v.abs() > tol { v } else { 0.0 })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The extrapolation through the last m corrections is exact on polynomials of degree
    /// m − 1 (to round-off), takes the last four once there are more, starts from nothing,
    /// and forgets on `clear`; a correction is the solution less the base.
    #[test]
    fn corrections_extrapolate_polynomials_of_their_degree() {
        let nb = 3;
        // per component a polynomial in the solve number k: constant, linear, quadratic
        // and cubic parts scaled differently
        let p = |k: f64, c: usize| {
            let s = [1.0, -2.5e-3, 7.0e4][c];
            s * (0.3 + 1.7 * k - 0.45 * k * k + 0.021 * k * k * k)
        };
        let lower = |k: f64, c: usize, degree: usize| {
            let s = [1.0, -2.5e-3, 7.0e4][c];
            let terms = [0.3, 1.7 * k, -0.45 * k * k, 0.021 * k * k * k];
            s * terms[..=degree].iter().sum::<f64>()
        };
        let base = DVector::from_vec(vec![0.25, -4.0, 1.0e3]);
        // with m = 1, 2, 3 pushed values of a polynomial of degree m − 1: exact
        for degree in 0..3 {
            let mut c = Corrections::new(nb);
            let mut x = base.clone();
            assert!(!c.extrapolate_into(&mut x), "nothing to extrapolate from");
            assert_eq!(x, base);
            for k in 0..=degree {
                let e = DVector::from_fn(nb, |i, _| lower(k as f64, i, degree));
                c.push(&(&base + &e), &base);
            }
            let mut got = DVector::zeros(nb);
            assert!(c.extrapolate_into(&mut got));
            for i in 0..nb {
                let want = lower((degree + 1) as f64, i, degree);
                assert!(
                    (got[i] - want).abs() <= 1e-12 * want.abs().max(1e-300),
                    "degree {degree}, component {i}: {} against {want}",
                    got[i]
                );
            }
        }
        // a cubic through more than four values: the last four, exactly
        let mut c = Corrections::new(nb);
        for k in 0..9 {
            let e = DVector::from_fn(nb, |i, _| p(k as f64, i));
            c.push(&(&base + &e), &base);
        }
        let mut got = DVector::zeros(nb);
        assert!(c.extrapolate_into(&mut got));
        for i in 0..nb {
            let want = p(9.0, i);
            assert!(
                (got[i] - want).abs() <= 1e-11 * want.abs(),
                "cubic, component {i}: {} against {want}",
                got[i]
            );
        }
        // a polynomial of degree four is not: the cubic's error is the fourth difference
        let q = |k: f64| k.powi(4);
        let mut c = Corrections::new(1);
        for k in 0..4 {
            c.push(&DVector::from_element(1, q(k as f64)), &DVector::zeros(1));
        }
        let mut got = DVector::zeros(1);
        c.extrapolate_into(&mut got);
        assert_eq!(q(4.0) - got[0], 24.0, "Δ⁴ k⁴ = 4!");
        c.clear();
        let mut x = DVector::from_element(1, 2.0);
        assert!(!c.extrapolate_into(&mut x));
        assert_eq!(x[0], 2.0);
    }

    /// A vehicle's mode-major block gives each wheelset's `Ψ q` bit for bit as one
    /// [`psi_mul`] per wheelset does, for one to nine wheelsets, and zeros for a wheelset off
    /// the deck; its rows rail DOF after rail DOF (a zero row for a wheelset off the deck)
    /// give `Σ Ψᵀ f` of the wheelsets on the deck as one projection per wheelset does, to
    /// round-off of the terms' magnitudes.
    #[test]
    fn a_vehicles_blocks_give_each_wheelsets_products() {
        let nb = 23;
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let q: Vec<f64> = (0..nb)
            .map(|n| next() * 10f64.powi(n as i32 % 7 - 3))
            .collect();
        for nw in 1..=9 {
            let psi: Vec<[f64; 3]> = (0..nw * nb).map(|_| [next(), next(), next()]).collect();
            // the block as the step keeps it, mode after mode; wheelset 1 is off the deck
            let r = 3 * nw;
            let mut u = vec![0.0; nb * r];
            for l in (0..nw).filter(|&l| l != 1) {
                for n in 0..nb {
                    u[n * r + 3 * l..n * r + 3 * l + 3].copy_from_slice(&psi[l * nb + n]);
                }
            }
            let mut out = vec![f64::NAN; 3 * nw];
            block_mul(&u, &q, &mut out);
            for l in 0..nw {
                let one = if l == 1 {
                    Vector3::zeros()
                } else {
                    psi_mul(&psi[l * nb..(l + 1) * nb], &q)
                };
                for k in 0..3 {
                    assert_eq!(out[3 * l + k].to_bits(), one[k].to_bits(), "{nw} wheelsets");
                }
            }
            let mut ut = vec![0.0; 3 * nw * nb];
            for l in (0..nw).filter(|&l| l != 1) {
                for k in 0..3 {
                    for n in 0..nb {
                        ut[(3 * l + k) * nb + n] = psi[l * nb + n][k];
                    }
                }
            }
            let f: Vec<f64> = (0..3 * nw).map(|_| next() * 1e5).collect();
            let y0: Vec<f64> = (0..nb).map(|_| next()).collect();
            let mut got = y0.clone();
            block_tr_add(&ut, &f, &mut got);
            let (mut want, mut scale) =
                (y0.clone(), y0.iter().map(|v| v.abs()).collect::<Vec<_>>());
            for l in (0..nw).filter(|&l| l != 1) {
                let shapes = &psi[l * nb..(l + 1) * nb];
                crate::simd::project_force(
                    &mut want,
                    shapes,
                    [f[3 * l], f[3 * l + 1], f[3 * l + 2]],
                );
                for (s, p) in scale.iter_mut().zip(shapes) {
                    *s += (0..3).map(|k| (p[k] * f[3 * l + k]).abs()).sum::<f64>();
                }
            }
            for n in 0..nb {
                let tol = 4.0 * f64::EPSILON * scale[n];
                assert!((got[n] - want[n]).abs() <= tol, "{nw} wheelsets, mode {n}");
            }
            // and nothing but the wheelsets on the deck: with all of them off, y is unchanged
            ut.fill(0.0);
            let mut none = y0.clone();
            block_tr_add(&ut, &f, &mut none);
            assert_eq!(none, y0);
        }
    }

    /// The carried-forward preconditioner of a reduced matrix that moves as a parabola in
    /// time, `A(τ) = A₀ + τ A₁ + τ² A₂`, assembled at three solves unevenly apart: the
    /// parabola through three assemblies is `A(τ)` itself, so its terms are `P A₁ P` and
    /// `P (A₁ P A₁ − A₂) P`, and with `M₁ = P A₁`, `M₂ = P A₂` the preconditioner's defect
    /// `(P − τ P A₁ P + τ² P (A₁ P A₁ − A₂) P) A(τ) − I` is the closed form
    /// `τ³ (M₁³ − M₁ M₂ − M₂ M₁) + τ⁴ (M₁² M₂ − M₂²)` to round-off: third order in τ where
    /// `P` alone leaves `P A(τ) − I`, first order. With one earlier assembly the slope is the
    /// secant's and there is no second-order term; with none, `P` alone.
    #[test]
    fn the_lagged_inverse_is_carried_forward_to_second_order() {
        let n = 20;
        let sym = |seed: usize, scale: f64| {
            let b = DMatrix::from_fn(n, n, |i, j| {
                (((i * 7 + j * 13 + seed) % 11) as f64 - 5.0) / 5.0
            });
            (&b + b.transpose()) * scale
        };
        // modal scales over two decades, the matrix moving by ~1e-4 of itself a solve
        let d = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                10f64.powf(i as f64 / 10.0)
            } else {
                0.0
            }
        });
        let b = DMatrix::from_fn(n, n, |i, j| ((i * 3 + j * 5) % 7) as f64 - 3.0);
        let a0 = &d * (b.transpose() * &b + DMatrix::identity(n, n) * n as f64) * &d;
        let (a1, a2) = (&d * sym(1, 1e-4) * &d, &d * sym(4, 1e-6) * &d);
        let at = |tau: f64| &a0 + &a1 * tau + &a2 * (tau * tau);
        // assembled at solves 3, 17 and 30; A₀ is the matrix of solve 30
        let before = [(at(-27.0), 3), (at(-13.0), 17)];
        let lagged = Lagged::new(&a0, 30, &before).expect("positive definite");
        let p = &lagged.inverse;
        let (m1, m2) = (p * &a1, p * &a2);
        let close = |got: &DMatrix<f64>, want: &DMatrix<f64>, what: &str| {
            let err = (got - want).amax();
            assert!(
                err <= 1e-9 * want.amax(),
                "{what}: off by {err:e} of {:e}",
                want.amax()
            );
        };
        let slope = lagged.slope.as_ref().expect("two earlier assemblies");
        close(slope, &(&m1 * p), "B₁");
        let curvature = lagged.curvature.as_ref().expect("two earlier assemblies");
        close(curvature, &((&m1 * &m1 - &m2) * p), "B₂");
        let mut now = DMatrix::zeros(n, n);
        let id = DMatrix::<f64>::identity(n, n);
        for tau in [1.0, 4.0, 11.0, 25.0] {
            lagged.at(30 + tau as usize, &mut now);
            let defect = &now * at(tau) - &id;
            let closed = (&m1 * &m1 * &m1 - &m1 * &m2 - &m2 * &m1) * tau.powi(3)
                + (&m1 * &m1 * &m2 - &m2 * &m2) * tau.powi(4);
            let err = (&defect - &closed).amax();
            assert!(
                err <= 1e-3 * closed.amax(),
                "τ = {tau}: defect off the closed form by {err:e} of {:e}",
                closed.amax()
            );
            let plain = p * at(tau) - &id;
            assert!(
                defect.amax() < 1e-3 * plain.amax(),
                "τ = {tau}: {:e} against {:e}",
                defect.amax(),
                plain.amax()
            );
        }
        // one earlier assembly: the secant, no second-order term; none: P alone
        let one = Lagged::new(&a0, 30, &before[1..]).expect("positive definite");
        let secant = p * ((&a0 - &before[1].0) / 13.0) * p;
        close(
            one.slope.as_ref().expect("one earlier assembly"),
            &secant,
            "secant",
        );
        assert!(one.curvature.is_none());
        let none = Lagged::new(&a0, 30, &[]).expect("positive definite");
        assert!(none.slope.is_none());
        none.at(41, &mut now);
        assert_eq!(now, none.inverse);
    }

    /// The sweeps give the inverse: `A A⁻¹ = I` to round-off on a symmetric positive
    /// definite matrix with a wide range of scales (a reduced matrix's diagonal spans ω² of
    /// the first and last modes), and None for an indefinite one.
    #[test]
    fn gauss_jordan_sweeps_invert_a_positive_definite_matrix() {
        let n = 20;
        let b = DMatrix::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 11) as f64 - 5.0);
        let scale = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                10f64.powf(i as f64 / 4.0)
            } else {
                0.0
            }
        });
        let a = &scale * (b.transpose() * &b + DMatrix::identity(n, n)) * &scale;
        let inv = spd_inverse(a.clone()).expect("positive definite");
        let err = (&a * &inv - DMatrix::<f64>::identity(n, n)).amax();
        let cond = {
            let e = a.clone().symmetric_eigenvalues();
            e.max() / e.min()
        };
        assert!(
            err <= 1e-15 * cond,
            "|A A⁻¹ − I| = {err:e}, condition {cond:e}"
        );
        let mut x = vec![0.0; n];
        let v: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        dense_mul(&inv, &v, &mut x);
        let direct = a.cholesky().unwrap().solve(&DVector::from_vec(v));
        for (p, q) in x.iter().zip(direct.iter()) {
            assert!((p - q).abs() <= 1e-15 * cond * q.abs().max(direct.amax()));
        }
        let indefinite = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
        assert!(spd_inverse(indefinite).is_none());
    }
}
