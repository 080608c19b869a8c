//! Vehicles as linear systems driven by the rail motion under their wheelsets.
//!
//! Every vehicle kind (moving force, sprung mass, the paper's 27-DOF coach) is reduced to
//! one [`LinearVehicle`]: `n` free degrees of freedom `v` (car body, bogies, masses —
//! measured from static equilibrium on a rigid, smooth, level track), and wheelsets whose
//! three rail DOFs `u = (Y_w, θ_w, Z_w)` (lateral, roll, vertical) are *prescribed*: a wheelset
//! follows the rail (deck motion plus irregularity plus hunting, eqs. 8 and 13 of Xia, Xu &
//! Chan 2000), so it carries no DOF of its own.
//!
//! The potential and dissipation of all springs and dampers give, for the stacked vector
//! `(v, u_1, …, u_nw)`, symmetric block matrices
//!
//! ```text
//! K_full = | K_vv   K_vw |      C_full likewise,   M_full = | M_vv  0   |
//!          | K_wv   K_ww |                                  | 0     M_w |
//! ```
//!
//! with `K_wv = K_vwᵀ`. The vehicle equations are
//! `M_vv v̈ + C_vv v̇ + K_vv v = −Σ_w (K_vw,w u_w + C_vw,w u̇_w)`, and the force that wheelset
//! `w` exerts on the rail (= on the deck) at its reference point is
//!
//! ```text
//! f_w = P0_w − M_w ü_w − K_ww,w u_w − C_ww,w u̇_w − K_wv,w v − C_wv,w v̇ ,        (eq. 6)
//! ```
//!
//! `f_w = (F_y, M_x, F_z)`: lateral force (+y), roll moment about +x, vertical force (+z,
//! down). `P0_w` is the static load (wheelset weight plus the spring forces of the static
//! equilibrium), computed by a static solve so that it holds for any geometry.
//!
//! The matrices are assembled from one list of spring–damper elements ([`assembly`]): each
//! element's elongation is a linear form in the DOFs of the rigid bodies it joins, built
//! from the small-rotation kinematics of the attachment points (see ARCHITECTURE.md for the
//! axes). Symmetry follows by construction and is tested.

pub mod aero;
pub mod assembly;
pub mod coach;
pub mod simple;

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// Standard gravity, m/s².
pub const GRAVITY: f64 = 9.81;

/// The coupling of one wheelset to its vehicle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WheelsetCoupling {
    /// Distance of the wheelset behind the vehicle's reference (its first wheelset), m.
    pub offset_m: f64,
    /// `K_vw` block (n × 3): vehicle DOFs × rail DOFs (Y_w, θ_w, Z_w).
    pub k_vw: DMatrix<f64>,
    /// `C_vw` block (n × 3).
    pub c_vw: DMatrix<f64>,
    /// `K_ww` (3 × 3).
    pub k_ww: Matrix3<f64>,
    /// `C_ww` (3 × 3).
    pub c_ww: Matrix3<f64>,
    /// Wheelset inertia `diag(m_w, J_w, m_w)` in kg, kg·m², kg.
    pub m_w: Matrix3<f64>,
    /// Static force on the rail `(F_y, M_x, F_z)` in N, N·m, N (F_z > 0 downward).
    pub p0: Vector3<f64>,
    /// The static vertical load in still air, N, when steady body loads (crosswind) have
    /// changed `p0` ([`LinearVehicle::with_body_loads`]); None: `p0.z`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub still_air_load_n: Option<f64>,
}

impl WheelsetCoupling {
    /// The reference load Q₀ of the offload factors and of ΔQ/Q₀: the static vertical load in
    /// still air, N.
    pub fn reference_load_n(&self) -> f64 {
        self.still_air_load_n.unwrap_or(self.p0.z)
    }
}

/// What to report as the vehicle's car-body acceleration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BodyDofs {
    /// DOF index of the car-body lateral displacement, if modelled.
    pub lateral: Option<usize>,
    /// DOF index of the car-body vertical displacement, if modelled.
    pub vertical: Option<usize>,
    /// DOF index of the car-body roll, if modelled (crosswind loads need it).
    #[serde(default)]
    pub roll: Option<usize>,
    /// DOF index of the car-body yaw ψ (nose right), if modelled.
    #[serde(default)]
    pub yaw: Option<usize>,
    /// DOF index of the car-body pitch φ (nose up), if modelled.
    #[serde(default)]
    pub pitch: Option<usize>,
    /// Height of the car body's centre of gravity above the wheelset reference points, m.
    #[serde(default)]
    pub cg_height_m: f64,
}

/// A vehicle reduced to constant matrices (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearVehicle {
    /// Kind name for reports (`moving_force`, `sprung_mass`, `coach_27dof`).
    pub kind: String,
    /// Names of the free DOFs (e.g. `car.Y`, `bogie1.Z`).
    pub dof_names: Vec<String>,
    /// Mass matrix `M_vv` (n × n).
    pub m: DMatrix<f64>,
    /// Damping matrix `C_vv` (n × n).
    pub c: DMatrix<f64>,
    /// Stiffness matrix `K_vv` (n × n).
    pub k: DMatrix<f64>,
    /// The wheelsets, front to back.
    pub wheelsets: Vec<WheelsetCoupling>,
    /// Car-body DOFs reported as vehicle accelerations.
    pub body: BodyDofs,
    /// Lateral distance between the two wheel–rail contact points, m (splits the roll
    /// moment into left and right wheel loads).
    pub contact_distance_m: f64,
    /// The generalised forces of a longitudinal acceleration: `(d, g_d)`, DOF `d` loaded by
    /// `g_d a` when the vehicle's speed changes at `a` m/s² (the pitching moments of its
    /// bodies' inertia, N·m per m/s²; empty: none modelled). See
    /// [`coach::CoachParams::build`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub inertia: Vec<(usize, f64)>,
}

impl LinearVehicle {
    /// The generalised forces of a longitudinal acceleration `a`, m/s² ([`Self::inertia`]),
    /// added to `f`.
    pub fn add_inertia(&self, a: f64, f: &mut [f64]) {
        for &(d, g) in &self.inertia {
            f[d] += g * a;
        }
    }

    /// The vehicle turned end for end on the track (facing −x): its rail degrees of freedom
    /// (Y, θ, Z) seen through S = diag(−1, −1, 1), so `K_vw S`, `C_vw S`, `S K_ww S`,
    /// `S C_ww S`, `S p0` (the wheelset inertia is diagonal and stays). Its own degrees of
    /// freedom, and what is reported of them, are unchanged.
    pub fn mirrored(&self) -> LinearVehicle {
        let s = Matrix3::from_diagonal(&Vector3::new(-1.0, -1.0, 1.0));
        let mut v = self.clone();
        for w in &mut v.wheelsets {
            for col in 0..2 {
                w.k_vw.column_mut(col).neg_mut();
                w.c_vw.column_mut(col).neg_mut();
            }
            w.k_ww = s * w.k_ww * s;
            w.c_ww = s * w.c_ww * s;
            w.m_w = s * w.m_w * s;
            w.p0 = s * w.p0;
        }
        v
    }

    /// Number of free DOFs.
    pub fn ndof(&self) -> usize {
        self.m.nrows()
    }

    /// Total mass carried by the rails, kg (Σ static vertical wheelset loads / g).
    pub fn total_weight_n(&self) -> f64 {
        self.wheelsets.iter().map(|w| w.p0.z).sum()
    }

    /// Length from the first to the last wheelset, m.
    pub fn wheelbase_m(&self) -> f64 {
        self.wheelsets.last().map(|w| w.offset_m).unwrap_or(0.0)
    }

    /// The force on the rail of wheelset `w` (eq. 6) for given vehicle state and rail motion.
    #[allow(clippy::too_many_arguments)]
    pub fn wheel_force(
        &self,
        w: usize,
        v: &DVector<f64>,
        vd: &DVector<f64>,
        u: &Vector3<f64>,
        ud: &Vector3<f64>,
        udd: &Vector3<f64>,
    ) -> Vector3<f64> {
        let ws = &self.wheelsets[w];
        let mut f = ws.p0 - ws.m_w * udd - ws.k_ww * u - ws.c_ww * ud;
        // f -= K_wv v + C_wv v̇ (columns of K_vw, C_vw are contiguous), without temporaries
        let n = v.len();
        let (kv, cv) = (ws.k_vw.as_slice(), ws.c_vw.as_slice());
        let (v, vd) = (v.as_slice(), vd.as_slice());
        for k in 0..3 {
            let mut acc = 0.0;
            for i in 0..n {
                acc += kv[k * n + i] * v[i] + cv[k * n + i] * vd[i];
            }
            f[k] -= acc;
        }
        f
    }
}

/// Per-wheel quantities of one wheelset derived from its rail force.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct WheelLoads {
    /// Lateral wheelset force Q = F_y, N.
    pub q: f64,
    /// Vertical wheelset force P = F_z, N.
    pub p: f64,
    /// Left wheel (−y side) vertical load, N.
    pub p_left: f64,
    /// Right wheel (+y side) vertical load, N.
    pub p_right: f64,
    /// Derail factor, wheelset form Q/P (signed).
    pub derail: f64,
    /// Offload factor, wheelset form (P0 − P)/P0.
    pub offload: f64,
    /// Derail factor, per-wheel form: |Q| over the vertical load of the wheel Q pushes toward.
    pub derail_wheel: f64,
    /// Offload factor, per-wheel form: max over both wheels of (P0/2 − P_wheel)/(P0/2).
    pub offload_wheel: f64,
}

impl WheelLoads {
    /// Split the rail force `f = (F_y, M_x, F_z)` of a wheelset with static vertical load
    /// `p0` (N) and contact distance `b` (m): `P_R = P/2 + M_x/b`, `P_L = P/2 − M_x/b`.
    pub fn from_force(f: &Vector3<f64>, p0: f64, b: f64) -> Self {
        let q = f.x;
        let p = f.z;
        let p_right = 0.5 * p + f.y / b;
        let p_left = 0.5 * p - f.y / b;
        let derail = if p.abs() > 0.0 { q / p } else { 0.0 };
        let offload = if p0 > 0.0 { (p0 - p) / p0 } else { 0.0 };
        let flange = if q >= 0.0 { p_right } else { p_left };
        let derail_wheel = if flange.abs() > 0.0 {
            q.abs() / flange
        } else {
            0.0
        };
        let half = 0.5 * p0;
        let offload_wheel = if half > 0.0 {
            ((half - p_left) / half).max((half - p_right) / half)
        } else {
            0.0
        };
        WheelLoads {
            q,
            p,
            p_left,
            p_right,
            derail,
            offload,
            derail_wheel,
            offload_wheel,
        }
    }

    /// [`WheelLoads::from_force`] of four wheelsets (lane `j`: the force
    /// `(F_y, M_x, F_z) = (q[j], m[j], p[j])`, static load `p0[j]`, contact distance `b[j]`),
    /// the divisions four at a time with AVX2 where the processor has it: the same operations
    /// in the same order per lane, bit for bit the values of `from_force`.
    pub fn from_forces4(
        q: [f64; 4],
        m: [f64; 4],
        p: [f64; 4],
        p0: [f64; 4],
        b: [f64; 4],
    ) -> [WheelLoads; 4] {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above).
            return unsafe { from_forces4_avx2(q, m, p, p0, b) };
        }
        std::array::from_fn(|j| Self::from_force(&Vector3::new(q[j], m[j], p[j]), p0[j], b[j]))
    }
}

/// [`WheelLoads::from_forces4`] with the four lanes in one vector: each of `from_force`'s
/// quotients as one division of four, its conditions as masks (a quotient whose condition
/// fails is computed and replaced by zero, as `from_force` never computes it); the larger of
/// the two wheels' offload taken lane by lane with `f64::max`.
///
/// # Safety
/// AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn from_forces4_avx2(
    q: [f64; 4],
    m: [f64; 4],
    p: [f64; 4],
    p0: [f64; 4],
    b: [f64; 4],
) -> [WheelLoads; 4] {
    use std::arch::x86_64::*;
    // SAFETY: unaligned loads and stores of four f64 from and into arrays of four.
    let ld = |a: &[f64; 4]| unsafe { _mm256_loadu_pd(a.as_ptr()) };
    let st = |v: __m256d| {
        let mut a = [0.0; 4];
        // SAFETY: as above.
        unsafe { _mm256_storeu_pd(a.as_mut_ptr(), v) };
        a
    };
    let (vq, vm, vp, vp0, vb) = (ld(&q), ld(&m), ld(&p), ld(&p0), ld(&b));
    let zero = _mm256_setzero_pd();
    let half = _mm256_set1_pd(0.5);
    let abs = |v: __m256d| _mm256_andnot_pd(_mm256_set1_pd(-0.0), v);
    // lanes where a condition holds keep the quotient, the others zero
    let keep = |ok: __m256d, v: __m256d| _mm256_blendv_pd(zero, v, ok);
    let gt = |a: __m256d, b: __m256d| _mm256_cmp_pd::<_CMP_GT_OQ>(a, b);
    let mb = _mm256_div_pd(vm, vb);
    let hp = _mm256_mul_pd(half, vp);
    let p_right = _mm256_add_pd(hp, mb);
    let p_left = _mm256_sub_pd(hp, mb);
    let derail = keep(gt(abs(vp), zero), _mm256_div_pd(vq, vp));
    let offload = keep(gt(vp0, zero), _mm256_div_pd(_mm256_sub_pd(vp0, vp), vp0));
    let flange = _mm256_blendv_pd(p_left, p_right, _mm256_cmp_pd::<_CMP_GE_OQ>(vq, zero));
    let derail_wheel = keep(gt(abs(flange), zero), _mm256_div_pd(abs(vq), flange));
    let h = _mm256_mul_pd(half, vp0);
    let left = _mm256_div_pd(_mm256_sub_pd(h, p_left), h);
    let right = _mm256_div_pd(_mm256_sub_pd(h, p_right), h);
    let (p_right, p_left, derail, offload, derail_wheel) = (
        st(p_right),
        st(p_left),
        st(derail),
        st(offload),
        st(derail_wheel),
    );
    let (left, right, h) = (st(left), st(right), st(h));
    std::array::from_fn(|j| WheelLoads {
        q: q[j],
        p: p[j],
        p_left: p_left[j],
        p_right: p_right[j],
        derail: derail[j],
        offload: offload[j],
        derail_wheel: derail_wheel[j],
        offload_wheel: if h[j] > 0.0 {
            left[j].max(right[j])
        } else {
            0.0
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every field of every lane equal to `from_force`'s bit for bit, over forces with
    /// each sign, zero vertical load, zero lateral force of either sign, no static load,
    /// a wheel lifted and one pressed past the other.
    #[test]
    fn four_wheelsets_load_as_one_each() {
        let qs = [0.0, -0.0, 3.1e4, -2.7e4, 1e-300];
        let ms = [0.0, 5.5e4, -8.0e4, 1.2e6];
        let ps = [0.0, -0.0, 1.3e5, 7.0e4, -2.0e4, 2.2e5];
        let p0s = [0.0, 1.4e5];
        let mut lanes = Vec::new();
        for &q in &qs {
            for &m in &ms {
                for &p in &ps {
                    for &p0 in &p0s {
                        lanes.push((q, m, p, p0, 1.5));
                    }
                }
            }
        }
        let bits = |l: &WheelLoads| {
            [
                l.q,
                l.p,
                l.p_left,
                l.p_right,
                l.derail,
                l.offload,
                l.derail_wheel,
                l.offload_wheel,
            ]
            .map(f64::to_bits)
        };
        for c in lanes.chunks_exact(4) {
            let four = WheelLoads::from_forces4(
                std::array::from_fn(|j| c[j].0),
                std::array::from_fn(|j| c[j].1),
                std::array::from_fn(|j| c[j].2),
                std::array::from_fn(|j| c[j].3),
                std::array::from_fn(|j| c[j].4),
            );
            for (l, &(q, m, p, p0, b)) in four.iter().zip(c) {
                let one = WheelLoads::from_force(&Vector3::new(q, m, p), p0, b);
                assert_eq!(bits(l), bits(&one), "q {q}, m {m}, p {p}, p0 {p0}");
            }
        }
    }
}
