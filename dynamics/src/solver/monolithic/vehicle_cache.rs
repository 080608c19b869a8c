//! The constant blocks of each vehicle by which the step eliminates its unknowns exactly
//! (Schur complement, see [`super`]): with `K̂_v = a0 M + a1 C + K` (factorised once),
//! `Ĝ = [K_vw,w + a1 C_vw,w]_w` and `Ŵ = blockdiag(a0 M_w + a1 C_ww + K_ww)`, the rail-space
//! matrix `S = Ŵ − Ĝᵀ K̂_v⁻¹ Ĝ` and the products with `K̂_v⁻¹` that a step takes, so that a
//! step solves nothing per vehicle.

use crate::newmark::Newmark;
use crate::solver::VehicleState;
use crate::train::Train;
use crate::vehicle::aero::WindBody;
use crate::vehicle::LinearVehicle;
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// A vehicle's constant blocks for one step size (shared by the vehicles of one model).
pub(super) struct VehicleCache {
    /// `K̂⁻¹ e_d` of each DOF `d` the wind loads (the car body's, [`WindBody::of`]; none for
    /// vehicles without DOFs or body): the wind's share of `K̂⁻¹ b_v` is `Σ_d F_d K̂⁻¹ e_d`,
    /// five products of n values instead of a solve with the factor.
    pub(super) wind: Vec<(usize, Vec<f64>)>,
    /// `K̂⁻¹ g` of the vehicle's inertia loads per unit longitudinal acceleration
    /// ([`LinearVehicle::inertia`]; empty without them): their share of `K̂⁻¹ b_v` is `a`
    /// times this.
    pub(super) inertia: Vec<f64>,
    /// `[C_vw,0 … C_vw,l …]ᵀ` (3n_w × n, column after column; the structural zeros exact):
    /// `C_vw,lᵀ v_c` of every wheelset in the bridge's right-hand side as one product.
    pub(super) cvw_t: Vec<f64>,
    /// S = Ŵ − Ĝᵀ K̂⁻¹ Ĝ (3n_w × 3n_w), column after column, its structural zeros exact
    /// ([`structural`]; empty when S = 0).
    pub(super) s_dense: Vec<f64>,
    /// `−Hᵀ = −K̂⁻¹ Ĝ` (n × 3n_w, column after column): the back-substitution
    /// `v₁ = K̂⁻¹ b_v − Hᵀ U q₁` adds this times `U q₁`.
    pub(super) h_neg_t: Vec<f64>,
    /// `K̂⁻¹ [a0 M + a1 C   a2 M + C   M]` (n × 3n, column after column): `K̂⁻¹ (M v_m + C v_c)`
    /// of the Newmark predictors `v_m = a0 v + a2 v̇ + v̈`, `v_c = a1 v + v̇` is this times
    /// `(v, v̇, v̈)`.
    pub(super) e_state: Vec<f64>,
    /// `−K̂⁻¹ [K_vw,l  C_vw,l]` of each wheelset `l` (n × 6n_w, column after column): the rail
    /// terms of `K̂⁻¹ b_v` are this times `(r_l, ṙ_l − Ψ_l q_c)` of each wheelset.
    pub(super) e_rail: Vec<f64>,
    /// `Ĝᵀ` (3n_w × n, column after column): `H b_v = Ĝᵀ (K̂⁻¹ b_v)`.
    pub(super) g_tr: Vec<f64>,
}

/// Per vehicle of `train`, its constant blocks for the step of `nm`. Vehicles of one model
/// (the same `Arc`, as the coaches of one train) share their constant blocks, so a step
/// reads one copy of them.
pub(super) fn of_train(train: &Train, nm: &Newmark) -> Vec<Arc<VehicleCache>> {
    let mut cache: Vec<Arc<VehicleCache>> = Vec::with_capacity(train.vehicles.len());
    for (tv, j) in train.vehicles.iter().zip(train.first_of_same_model()) {
        let c = match cache.get(j) {
            Some(first) => first.clone(),
            None => Arc::new(vehicle_cache(&tv.model, nm)),
        };
        cache.push(c);
    }
    cache
}

/// The constant blocks of `model` for the step of `nm` ([`VehicleCache`]).
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
            inertia: Vec::new(),
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
    let inertia = match model.inertia.is_empty() {
        true => Vec::new(),
        false => {
            let mut g = DVector::zeros(n);
            model.add_inertia(1.0, g.as_mut_slice());
            chol.solve(&g).as_slice().to_vec()
        }
    };
    VehicleCache {
        wind,
        inertia,
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

/// `y = K̂⁻¹ (M v_m + C v_c)` of each of `vehicles` with DOFs into `bv`, as the product of
/// [`VehicleCache::e_state`] with its `(v, v̇, v̈)` (of `states`), two vehicles at a time
/// ([`crate::simd::mul_columns_pair`], the same values bit for bit as one by one); `state`
/// and `state2` are the scratch of the two vehicles' states.
pub(super) fn state_parts(
    vehicles: &[usize],
    train: &Train,
    states: &[VehicleState],
    cache: &[Arc<VehicleCache>],
    bv: &mut [DVector<f64>],
    [state, state2]: [&mut Vec<f64>; 2],
) {
    let mut with_dofs = vehicles
        .iter()
        .copied()
        .filter(|&i| train.vehicles[i].model.ndof() > 0);
    let fill = |s: &mut Vec<f64>, i: usize| {
        let vs = &states[i];
        s.clear();
        for part in [&vs.v, &vs.vd, &vs.vdd] {
            s.extend_from_slice(part.as_slice());
        }
    };
    while let Some(i) = with_dofs.next() {
        fill(state, i);
        let Some(k) = with_dofs.next() else {
            crate::simd::mul_columns(bv[i].as_mut_slice(), state, &cache[i].e_state);
            break;
        };
        fill(state2, k);
        // i < k: the vehicles ascend
        let (head, tail) = bv.split_at_mut(k);
        crate::simd::mul_columns_pair(
            head[i].as_mut_slice(),
            state,
            &cache[i].e_state,
            tail[0].as_mut_slice(),
            state2,
            &cache[k].e_state,
        );
    }
}
