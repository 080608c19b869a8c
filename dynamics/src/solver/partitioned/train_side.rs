//! The train partition ([`TrainSide`], see [`super`]): every vehicle stepped by its own
//! Newmark step on the rail motion of the end of the step, with wheel hunting added, and the
//! wheel forces of eq. (6). A vehicle's step is dense products with its factor's responses
//! ([`Factor`]), the part that depends on the state alone kept while the state is the same
//! ([`StepBase`]).

use crate::newmark::Newmark;
use crate::solver::{add_hunting, share, VehicleState, WheelForce};
use crate::sparse::{Csr, SparseCholesky};
use crate::train::{Train, WheelsetRef};
use crate::vehicle::aero::WindBody;
use crate::vehicle::LinearVehicle;
use nalgebra::{DVector, Vector3};
use std::sync::Arc;

/// Newmark factor of one vehicle for one step size, and the response of its new
/// acceleration to the rail motion.
#[derive(Debug, Clone)]
struct Factor {
    h: f64,
    /// `K̂⁻¹ e_d` of each DOF `d` the wind loads (the car body's, [`WindBody::of`]; none
    /// without one): the wind's share of the new acceleration, `a0 K̂⁻¹ F₁ = Σ_d (a0 F₁)_d
    /// K̂⁻¹ e_d`, five products of n values instead of a solve with the factor.
    wind: Vec<(usize, Vec<f64>)>,
    /// `K̂⁻¹ g` of the inertia loads per unit longitudinal acceleration
    /// ([`LinearVehicle::inertia`]; empty without them): their share of the new
    /// acceleration is `a0 a` times this.
    inertia: Vec<f64>,
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
        let mut inertia = Vec::new();
        if !model.inertia.is_empty() {
            inertia = vec![0.0; model.ndof()];
            model.add_inertia(1.0, &mut inertia);
            chol.solve_mut(&mut inertia);
        }
        Factor {
            h,
            wind,
            inertia,
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
    /// The hunting motion of each of the `n` wheelsets of `train` (its `wheelsets`) at time `t`.
    fn at(
        &mut self,
        train: &Arc<Train>,
        wheelsets: &[WheelsetRef],
        n: usize,
        t: f64,
    ) -> &[[f64; 3]] {
        let key = (t.to_bits(), Arc::as_ptr(train) as usize);
        if self.key != Some(key) || self.values.len() != n {
            self.values.clear();
            (self.values).extend(
                wheelsets[..n]
                    .iter()
                    .map(|w| train.runs[w.run].hunting_at(w.in_run, t)),
            );
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
        share(&mut self.train, &source.train);
        share(&mut self.wheelsets, &source.wheelsets);
        self.states.clone_from(&source.states);
        self.rails.clone_from(&source.rails);
        self.t = source.t;
        self.body_wind.clone_from(&source.body_wind);
        share(&mut self.factors, &source.factors);
        share(&mut self.sparse, &source.sparse);
        share(&mut self.model_of, &source.model_of);
        share(&mut self.forces, &source.forces);
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
                    inertia: Vec::new(),
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
        self.train.x_of(&self.wheelsets[w], t)
    }

    /// Static equilibrium at time `t` on the given rail motion (deck plus irregularity).
    pub fn initialize(&mut self, t: f64, rails: &[[Vector3<f64>; 3]]) {
        self.t = t;
        let hunting = (self.hunting).at(&self.train, &self.wheelsets, rails.len(), t);
        self.rails = (rails.iter().zip(hunting))
            .map(|(r, h)| add_hunting(r, h))
            .collect();
        let mut first = 0;
        for (i, tv) in self.train.vehicles.iter().enumerate() {
            let nw = tv.model.wheelsets.len();
            let f = self.train.body_force(i, t, self.body_wind[i]);
            self.states[i] =
                VehicleState::initial_loaded(&tv.model, &self.rails[first..first + nw], f.as_ref());
            first += nw;
        }
    }

    /// One Newmark step from `self.t` to `self.t + h` with the end-of-step rail motion.
    pub fn step(&mut self, h: f64, rails: &[[Vector3<f64>; 3]]) {
        let t1 = self.t + h;
        let nm = Newmark::new(h);
        let hunting = (self.hunting).at(&self.train, &self.wheelsets, rails.len(), t1);
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
                // the inertia of a changing speed, a0 K̂⁻¹ g a
                let acc = self.train.acceleration_of(i, t1);
                if acc != 0.0 && !factor.inertia.is_empty() {
                    crate::simd::axpy(a, nm.a0 * acc, &factor.inertia);
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
