//! A dense reference for the monolithic solver: the full matrices of eq. (14) assembled
//! explicitly and one Newmark step solved by LU. Built from the public API only (the bridge's
//! frequencies, damping and rail shapes, the train's wheelset positions, the prescribed rail
//! motion), so it shares no geometry cache and no reduction with `Monolithic::step`.
use nalgebra::{DMatrix, DVector, Vector3};
use tbi_dynamics::newmark::Newmark;
use tbi_dynamics::solver::{rail_prescribed, Monolithic};

/// `(x, ẋ, ẍ)` stacked over `(v_1, …, v_Nv, q)`.
pub fn stacked_state(sol: &Monolithic) -> (DVector<f64>, DVector<f64>, DVector<f64>) {
    let mut x = Vec::new();
    let mut xd = Vec::new();
    let mut xdd = Vec::new();
    for v in &sol.vehicles {
        x.extend(v.v.iter());
        xd.extend(v.vd.iter());
        xdd.extend(v.vdd.iter());
    }
    x.extend(sol.q.iter());
    xd.extend(sol.qd.iter());
    xdd.extend(sol.qdd.iter());
    (
        DVector::from_vec(x),
        DVector::from_vec(xd),
        DVector::from_vec(xdd),
    )
}

/// The full matrices of eq. (14) at time `t`: `(M, C, K, F)` over `(v_1, …, v_Nv, q)`, with
/// the wheelset positions, rail shapes Ψ_w and prescribed rail motion r_w evaluated at `t`.
pub fn assemble_eq14(
    sol: &Monolithic,
    t: f64,
) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, DVector<f64>) {
    let nb = sol.q.len();
    let omega = sol.bridge.omegas();
    let zeta = &sol.bridge.damping;
    let nv: usize = sol.train.vehicles.iter().map(|v| v.model.ndof()).sum();
    let dim = nv + nb;
    let mut m = DMatrix::zeros(dim, dim);
    let mut c = DMatrix::zeros(dim, dim);
    let mut k = DMatrix::zeros(dim, dim);
    let mut f = DVector::zeros(dim);
    let mut off = Vec::new();
    let mut o = 0;
    for tv in &sol.train.vehicles {
        let n = tv.model.ndof();
        off.push(o);
        m.view_mut((o, o), (n, n)).copy_from(&tv.model.m);
        c.view_mut((o, o), (n, n)).copy_from(&tv.model.c);
        k.view_mut((o, o), (n, n)).copy_from(&tv.model.k);
        o += n;
    }
    for n in 0..nb {
        m[(nv + n, nv + n)] = 1.0;
        c[(nv + n, nv + n)] = 2.0 * zeta[n] * omega[n];
        k[(nv + n, nv + n)] = omega[n].powi(2);
    }
    let mut shapes = vec![[0.0; 3]; nb];
    for ws in sol.train.wheelsets().iter() {
        let model = &sol.train.vehicles[ws.vehicle].model;
        let cw = &model.wheelsets[ws.local];
        let n = model.ndof();
        let ov = off[ws.vehicle];
        let x = sol.train.x_of(ws, t);
        // Ψ = 0 off the deck (rail_shapes zeroes it).
        sol.bridge.rail_shapes(x, &mut shapes);
        let psi = DMatrix::from_fn(3, nb, |r, j| shapes[j][r]);
        let [r, rd, rdd]: [Vector3<f64>; 3] =
            rail_prescribed(&*sol.track, &sol.train.runs[ws.run], ws.in_run, x, t);
        let mw = DMatrix::from_iterator(3, 3, cw.m_w.iter().copied());
        let kww = DMatrix::from_iterator(3, 3, cw.k_ww.iter().copied());
        let cww = DMatrix::from_iterator(3, 3, cw.c_ww.iter().copied());
        let bridge = |mat: &mut DMatrix<f64>, blk: &DMatrix<f64>| {
            let add = psi.transpose() * blk * &psi;
            let mut v = mat.view_mut((nv, nv), (nb, nb));
            v += add;
        };
        bridge(&mut m, &mw);
        bridge(&mut k, &kww);
        bridge(&mut c, &cww);
        if n > 0 {
            let kvb = &cw.k_vw * &psi;
            let cvb = &cw.c_vw * &psi;
            let mut v = k.view_mut((ov, nv), (n, nb));
            v += &kvb;
            let mut v = k.view_mut((nv, ov), (nb, n));
            v += kvb.transpose();
            let mut v = c.view_mut((ov, nv), (n, nb));
            v += &cvb;
            let mut v = c.view_mut((nv, ov), (nb, n));
            v += cvb.transpose();
            let fv = -(&cw.k_vw * r + &cw.c_vw * rd);
            let mut v = f.rows_mut(ov, n);
            v += fv;
        }
        let fb = cw.p0 - cw.m_w * rdd - cw.c_ww * rd - cw.k_ww * r;
        let add = psi.transpose() * DVector::from_column_slice(fb.as_slice());
        let mut v = f.rows_mut(nv, nb);
        v += add;
    }
    (m, c, k, f)
}

/// One Newmark step of the full eq. (14) with a dense solve: the new `x` over `(v, q)` from
/// the solver's current state, with the matrices evaluated at `t + dt`. The solver is not
/// changed.
pub fn dense_reference_step(sol: &Monolithic) -> DVector<f64> {
    let nm = Newmark::new(sol.dt());
    let (x0, xd0, xdd0) = stacked_state(sol);
    let (m, c, k, f) = assemble_eq14(sol, sol.t + nm.h);
    let khat = nm.a0 * &m + nm.a1 * &c + &k;
    let rhs = f + &m * (nm.a0 * &x0 + nm.a2 * &xd0 + &xdd0) + &c * (nm.a1 * &x0 + &xd0);
    khat.lu()
        .solve(&rhs)
        .expect("eq. (14) Newmark matrix is regular")
}
