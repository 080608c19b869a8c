//! The 27-DOF coach: matrices against an independent hand derivation (the paper's
//! Appendix A with its typos corrected), symmetry, static wheel loads, and natural
//! frequencies by an independent eigenvalue method (bisection with Sylvester's inertia).
#![allow(clippy::needless_range_loop)]
use nalgebra::{DMatrix, Vector3};
use tbi_dynamics::vehicle::coach::CoachParams;
use tbi_dynamics::vehicle::{WheelLoads, GRAVITY};

/// K (or C with the dampers) written out by hand. DOFs per body: Y, θ, ψ, Z, φ;
/// bodies: car, bogie 1 (front, x = +s), bogie 2 (rear).
fn hand_matrix(p: &CoachParams, damping: bool) -> DMatrix<f64> {
    let (k1v, k1h, k2v, k2h) = if damping {
        (p.c1v_ns_m, p.c1h_ns_m, p.c2v_ns_m, p.c2h_ns_m)
    } else {
        (p.k1v_n_m, p.k1h_n_m, p.k2v_n_m, p.k2h_n_m)
    };
    let (h1, h2, h3, a, b, s, d) = (p.h1_m, p.h2_m, p.h3_m, p.a_m, p.b_m, p.s_m, p.d_m);
    let mut k = DMatrix::zeros(15, 15);
    let (y, th, ps, z, ph) = (0, 1, 2, 3, 4);
    // car body (A3, with the missing h1 restored in (Y, θ))
    k[(y, y)] = 2.0 * k2h;
    k[(y, th)] = -2.0 * h1 * k2h;
    k[(th, y)] = -2.0 * h1 * k2h;
    k[(th, th)] = 2.0 * h1 * h1 * k2h + 2.0 * b * b * k2v;
    k[(ps, ps)] = 2.0 * s * s * k2h;
    k[(z, z)] = 2.0 * k2v;
    k[(ph, ph)] = 2.0 * s * s * k2v;
    for j in 0..2 {
        let o = 5 + 5 * j;
        let eta = if j == 0 { 1.0 } else { -1.0 };
        // bogie (A4)
        k[(o + y, o + y)] = k2h + 2.0 * k1h;
        k[(o + y, o + th)] = h2 * k2h - 2.0 * h3 * k1h;
        k[(o + th, o + y)] = h2 * k2h - 2.0 * h3 * k1h;
        k[(o + th, o + th)] = h2 * h2 * k2h + b * b * k2v + 2.0 * h3 * h3 * k1h + 2.0 * a * a * k1v;
        k[(o + ps, o + ps)] = 2.0 * d * d * k1h;
        k[(o + z, o + z)] = 2.0 * k1v + k2v;
        k[(o + ph, o + ph)] = 2.0 * d * d * k1v;
        // car–bogie (A5/A6, transposed consistently; pitch positive nose-up)
        let pairs = [
            (y, y, -k2h),
            (y, th, -h2 * k2h),
            (th, y, h1 * k2h),
            (th, th, h1 * h2 * k2h - b * b * k2v),
            (ps, y, -eta * s * k2h),
            (ps, th, -eta * s * h2 * k2h),
            (z, z, -k2v),
            (ph, z, eta * s * k2v),
        ];
        for (r, c, v) in pairs {
            k[(r, o + c)] = v;
            k[(o + c, r)] = v;
        }
    }
    k
}

#[test]
fn matrices_match_hand_derivation_and_are_symmetric() {
    let p = CoachParams::xia2000();
    let v = p.build().unwrap();
    assert_eq!(v.ndof(), 15);
    assert_eq!(v.wheelsets.len(), 4);
    for (mat, hand, name) in [
        (&v.k, hand_matrix(&p, false), "K"),
        (&v.c, hand_matrix(&p, true), "C"),
    ] {
        let scale = hand.amax();
        for i in 0..15 {
            for j in 0..15 {
                assert!(
                    (mat[(i, j)] - hand[(i, j)]).abs() <= 1e-12 * scale,
                    "{name}[{} , {}] = {} but hand derivation gives {}",
                    v.dof_names[i],
                    v.dof_names[j],
                    mat[(i, j)],
                    hand[(i, j)]
                );
                assert_eq!(
                    mat[(i, j)],
                    mat[(j, i)],
                    "{name} not symmetric at ({i},{j})"
                );
            }
        }
    }
    let m_expected = [
        p.car_mass_kg,
        p.car_roll_inertia_kg_m2,
        p.car_yaw_inertia_kg_m2,
        p.car_mass_kg,
        p.car_pitch_inertia_kg_m2,
    ];
    for i in 0..5 {
        assert_eq!(v.m[(i, i)], m_expected[i]);
    }
    // Coupling to the wheelsets: the primary suspension of wheelset 0 acts on bogie 1 only,
    // with K_vw(bogie1.Z, Z_w) = −k1v and K_ww = diag(k1h, a² k1v, k1v).
    let w0 = &v.wheelsets[0];
    assert_eq!(w0.k_vw[(5 + 3, 2)], -p.k1v_n_m);
    assert_eq!(w0.k_vw[(5, 0)], -p.k1h_n_m);
    assert!((w0.k_vw[(5 + 1, 0)] - p.h3_m * p.k1h_n_m).abs() < 1e-6);
    assert!(
        (w0.k_vw[(5 + 4, 2)] - p.d_m * p.k1v_n_m).abs() < 1e-6,
        "front wheelset lifts the bogie nose"
    );
    assert!((w0.k_ww[(0, 0)] - p.k1h_n_m).abs() < 1e-6);
    assert!((w0.k_ww[(1, 1)] - p.a_m * p.a_m * p.k1v_n_m).abs() < 1e-6);
    assert!((w0.k_ww[(2, 2)] - p.k1v_n_m).abs() < 1e-6);
    for r in 0..5 {
        assert_eq!(w0.k_vw[(r, 0)], 0.0);
        assert_eq!(w0.k_vw[(10 + r, 2)], 0.0);
    }
    for (w, expected) in v.wheelsets.iter().zip([0.0, 2.5, 15.6, 18.1]) {
        assert!(
            (w.offset_m - expected).abs() < 1e-12,
            "offset {} vs {expected}",
            w.offset_m
        );
    }
}

#[test]
fn static_wheel_loads_equal_weight_shares() {
    let p = CoachParams::xia2000();
    let v = p.build().unwrap();
    let share = (p.wheelset_mass_kg + p.bogie_mass_kg / 2.0 + p.car_mass_kg / 4.0) * GRAVITY;
    for w in &v.wheelsets {
        assert!(
            (w.p0.z - share).abs() < 1e-6 * share,
            "{} vs {share}",
            w.p0.z
        );
        assert!(w.p0.x.abs() < 1e-6 && w.p0.y.abs() < 1e-6);
        let loads = WheelLoads::from_force(&w.p0, w.p0.z, p.contact_distance_m);
        assert!(
            (loads.p_left - share / 2.0).abs() < 1e-6 && (loads.p_right - share / 2.0).abs() < 1e-6
        );
        assert_eq!(loads.offload, 0.0);
    }
    // Table 1 masses give 16.70 t per axle (the paper's text quotes an average crush axle
    // load of 13 250 kg, which its own Table 1 does not reproduce; see the docs).
    assert!((share / GRAVITY - 16_697.5).abs() < 1e-6);
    // An asymmetric coach (bogies off-centre) still carries its weight in total.
    let mut q = p.clone();
    q.car_pitch_inertia_kg_m2 *= 1.3;
    let v2 = q.build().unwrap();
    let total: f64 = v2.wheelsets.iter().map(|w| w.p0.z).sum();
    let weight = (q.car_mass_kg + 2.0 * q.bogie_mass_kg + 4.0 * q.wheelset_mass_kg) * GRAVITY;
    assert!((total - weight).abs() < 1e-6 * weight);
    // roll moment splits wheel loads
    let f = Vector3::new(1000.0, 1435.0, 100_000.0);
    let l = WheelLoads::from_force(&f, 100_000.0, 1.435);
    assert!((l.p_right - 51_000.0).abs() < 1e-9 && (l.p_left - 49_000.0).abs() < 1e-9);
}

/// Number of eigenvalues of (K, M) below λ: the negative pivots of K − λM (Sylvester).
fn count_below(k: &DMatrix<f64>, m: &DMatrix<f64>, lambda: f64) -> usize {
    let n = k.nrows();
    let mut a = k - m * lambda;
    let mut neg = 0;
    for i in 0..n {
        let piv = a[(i, i)];
        if piv < 0.0 {
            neg += 1;
        }
        for r in i + 1..n {
            let f = a[(r, i)] / piv;
            for c in i..n {
                a[(r, c)] -= f * a[(i, c)];
            }
        }
    }
    neg
}

fn eig_bisection(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let n = k.nrows();
    (0..n)
        .map(|idx| {
            let (mut lo, mut hi) = (0.0, 1.0e7);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if count_below(k, m, mid) > idx {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            (0.5 * (lo + hi)).sqrt() / (2.0 * std::f64::consts::PI)
        })
        .collect()
}

#[test]
fn natural_frequencies_by_two_methods() {
    let p = CoachParams::xia2000();
    let v = p.build().unwrap();
    let minv_sqrt = DMatrix::from_diagonal(&v.m.diagonal().map(|x| 1.0 / x.sqrt()));
    let a = &minv_sqrt * &v.k * &minv_sqrt;
    let mut f_eig: Vec<f64> = a
        .symmetric_eigen()
        .eigenvalues
        .iter()
        .map(|l| l.sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    f_eig.sort_by(f64::total_cmp);
    let f_bis = eig_bisection(&v.k, &v.m);
    for (a, b) in f_eig.iter().zip(&f_bis) {
        assert!((a - b).abs() < 1e-9 * b.max(1.0), "{a} vs {b}");
    }
    println!("coach frequencies (Hz): {f_bis:.4?}");
    // Closed forms for modes that decouple exactly in a symmetric coach:
    // (1) bounce — car Z with both bogies in phase: 2-DOF chain M_c, 2M_t, springs 2k2v, 4k1v;
    let (mc, mt) = (p.car_mass_kg, p.bogie_mass_kg);
    let (ks, kp) = (2.0 * p.k2v_n_m, 4.0 * p.k1v_n_m);
    // det([ks − λmc, −ks; −ks, ks + kp − 2λmt]) = 0
    let (qa, qb, qc) = (2.0 * mc * mt, -(mc * (ks + kp) + 2.0 * mt * ks), ks * kp);
    let disc = (qb * qb - 4.0 * qa * qc).sqrt();
    let bounce = ((-qb - disc) / (2.0 * qa)).sqrt() / (2.0 * std::f64::consts::PI);
    // (2) bogie pitch on its two wheelsets: 2 d² k1v / J_tφ (double: two bogies).
    let pitch = (2.0 * p.d_m * p.d_m * p.k1v_n_m / p.bogie_pitch_inertia_kg_m2).sqrt()
        / (2.0 * std::f64::consts::PI);
    let has = |f: f64| f_bis.iter().filter(|g| (*g - f).abs() < 1e-7 * f).count();
    assert_eq!(has(bounce), 1, "bounce {bounce} Hz not among {f_bis:?}");
    assert_eq!(
        has(pitch),
        2,
        "bogie pitch {pitch} Hz not a double eigenvalue of {f_bis:?}"
    );
    assert!((vertical_bounce(&v) - bounce).abs() < 1e-9);
}

/// Frequency of the mode with the largest car-body vertical participation.
fn vertical_bounce(v: &tbi_dynamics::vehicle::LinearVehicle) -> f64 {
    let minv_sqrt = DMatrix::from_diagonal(&v.m.diagonal().map(|x| 1.0 / x.sqrt()));
    let e = (&minv_sqrt * &v.k * &minv_sqrt).symmetric_eigen();
    let mut best = (0.0, 0.0);
    for i in 0..e.eigenvalues.len() {
        let share = e.eigenvectors[(3, i)].powi(2);
        if share > best.0 {
            best = (
                share,
                e.eigenvalues[i].sqrt() / (2.0 * std::f64::consts::PI),
            );
        }
    }
    best.1
}

/// Quasi-static limit (train speed → 0): the car body and bogies settle in static
/// equilibrium over wheelsets displaced by the rail, `K v = −Σ K_vw u_l`. Each bogie follows
/// its two wheelsets in lateral, yaw, vertical and pitch, and the car body follows the two
/// bogies, so the primary and secondary springs stay undeformed whatever the lateral and
/// vertical rail irregularity: every wheelset carries exactly its static load (F_y = 0,
/// F_z = P0), and the wheelset-form derail and offload factors vanish. Only a cross-level
/// difference between the wheelsets of one bogie (track twist) deforms the springs: it
/// changes the wheelset roll moment M_x and so the left/right wheel loads.
#[test]
fn wheelset_forces_are_static_in_the_quasi_static_limit() {
    let p = CoachParams::xia2000();
    let v = p.build().unwrap();
    // Arbitrary rail displacements (Y, θ, Z) under the four wheelsets, m and rad.
    let ys = [3.1e-3, -1.7e-3, 2.2e-3, 0.4e-3];
    let zs = [-2.5e-3, 1.9e-3, 0.7e-3, -3.3e-3];
    let run = |thetas: [f64; 4]| -> Vec<Vector3<f64>> {
        let rails: Vec<[Vector3<f64>; 3]> = (0..4)
            .map(|l| {
                [
                    Vector3::new(ys[l], thetas[l], zs[l]),
                    Vector3::zeros(),
                    Vector3::zeros(),
                ]
            })
            .collect();
        let st = tbi_dynamics::solver::VehicleState::initial(&v, &rails);
        (0..4)
            .map(|l| {
                v.wheel_force(l, &st.v, &st.vd, &rails[l][0], &rails[l][1], &rails[l][2])
                    - v.wheelsets[l].p0
            })
            .collect()
    };
    // Common cross-level: the whole vehicle rolls with the track, no force changes at all.
    for df in run([1.2e-3; 4]) {
        assert!(df.norm() < 1e-9 * v.wheelsets[0].p0.z, "ΔF = {df:?}");
    }
    // Track twist: F_y and F_z stay static, M_x does not.
    let thetas = [1.2e-3, -0.8e-3, 0.3e-3, 0.9e-3];
    let dfs = run(thetas);
    for df in &dfs {
        assert!(df.x.abs() < 1e-9 * v.wheelsets[0].p0.z, "ΔF_y = {}", df.x);
        assert!(df.z.abs() < 1e-9 * v.wheelsets[0].p0.z, "ΔF_z = {}", df.z);
    }
    // Each wheelset hangs on its two primary vertical springs 0.5·k1v at y = ±a, so its roll
    // moment on the rail is M_x,l = −k1v a² (θ_l − θ_bogie): in the difference of a bogie's
    // two wheelsets θ_bogie cancels, whatever the bogie and car body do.
    let roll = p.k1v_n_m * p.a_m * p.a_m;
    for (front, rear) in [(0, 1), (2, 3)] {
        let got = dfs[front].y - dfs[rear].y;
        let want = -roll * (thetas[front] - thetas[rear]);
        println!("ΔM_x{front} − ΔM_x{rear} = {got:.6} N·m, −k1v a² Δθ = {want:.6} N·m");
        assert!(
            (got - want).abs() <= 1e-9 * want.abs(),
            "ΔM_x{front} − ΔM_x{rear} = {got} N·m vs −k1v a² Δθ = {want} N·m"
        );
    }
    // Roll equilibrium of the whole vehicle (ΔF_y = ΔF_z = 0 above, and every spring acts
    // between coincident points): the moment changes cancel.
    let sum: f64 = dfs.iter().map(|df| df.y).sum();
    let scale = roll * (thetas[0] - thetas[1]).abs();
    println!("Σ ΔM_x = {sum:e} N·m");
    assert!(sum.abs() <= 1e-9 * scale, "Σ ΔM_x = {sum} N·m");
}
