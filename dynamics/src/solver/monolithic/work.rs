//! The preallocated buffers of a step ([`Work`]): a step takes them out of the solver, fills
//! and reads them, and puts them back, so that it allocates nothing.

use super::iterative::ReducedSolver;
use crate::train::Train;
use crate::vehicle::LinearVehicle;
use nalgebra::{DVector, Vector3};

/// Preallocated buffers of one step.
#[derive(Default)]
pub(super) struct Work {
    pub(super) qm: DVector<f64>,
    pub(super) qc: DVector<f64>,
    /// `D̂ = diag(a0 + a1 2ζω + ω²)`, set once by [`super::Monolithic::new`].
    pub(super) dhat: DVector<f64>,
    pub(super) bq: DVector<f64>,
    /// The iterative solve of the reduced system: its preconditioner, its corrections and
    /// its vectors, the solution among them.
    pub(super) solver: ReducedSolver,
    /// Rail-space scratch (3 n_w of a vehicle, two vehicles' room).
    pub(super) ux: Vec<f64>,
    pub(super) sx: Vec<f64>,
    /// Per vehicle: a wheelset of it on the deck ([`super::Monolithic::live_vehicles`]).
    pub(super) live: Vec<bool>,
    /// Scratch of a vehicle's `(v, v̇, v̈)` and of its wheelsets' `(r, ṙ − Ψ q_c)`.
    pub(super) state: Vec<f64>,
    /// The same of a second vehicle ([`super::vehicle_cache::state_parts`] takes two at a time).
    pub(super) state2: Vec<f64>,
    pub(super) rails: Vec<f64>,
    /// Per vehicle (n values): the wind's share of `K̂⁻¹ b_v`, then the new state `v₁`.
    pub(super) vm: Vec<DVector<f64>>,
    /// Per vehicle (n values): the damping predictor `v_c = a1 v + v̇`.
    pub(super) vc: Vec<DVector<f64>>,
    /// Per vehicle (n values): `K̂⁻¹ b_v`.
    pub(super) bv: Vec<DVector<f64>>,
    /// Per vehicle (3 n_w values): `H b_v`, then `U q₁`.
    pub(super) z: Vec<DVector<f64>>,
    /// The deck's part of the rail motion under each wheelset at the end of the step.
    pub(super) deck: Vec<[Vector3<f64>; 3]>,
    /// Per wheelset on the deck: `Ψ` times the bridge's damping and mass predictors
    /// (`Ψ q_c`, `Ψ q_m`), from which the rail's velocity and acceleration at the end of the
    /// step follow with `Ψ q₁` ([`super::Monolithic::deck_motion_at_end`]).
    pub(super) pred: Vec<[Vector3<f64>; 2]>,
    /// One vehicle's `g_l + C_vw,lᵀ v_c`, its wheelsets' one after the other (3 n_w).
    pub(super) gv: Vec<f64>,
    /// Per wheelset of a vehicle with DOFs (three values each): `g − z`, then its force on
    /// the rail at the end of the step (`− S U q₁` taken off in the back-substitution).
    pub(super) gz: Vec<f64>,
    /// The wheelsets and vehicles the step visits, ascending
    /// ([`super::Monolithic::update_geometry`]).
    pub(super) busy: Vec<usize>,
    pub(super) busy_vehicles: Vec<usize>,
    /// Whether the prescribed rail motion was zero everywhere at the last geometry update.
    pub(super) flat_before: bool,
    /// Per vehicle: its last step left its state bit for bit the same, off the deck of an
    /// ideal track without wind on the train (kept while it stays off the deck).
    pub(super) resting: Vec<bool>,
}

impl Work {
    pub(super) fn new(nb: usize, train: &Train) -> Self {
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
            solver: ReducedSolver::new(nb, train),
            // two vehicles' rail DOFs (Reduced::apply takes them in pairs)
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
