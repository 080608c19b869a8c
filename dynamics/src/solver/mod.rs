//! Time integration: the monolithic solver of eq. (14) and the two partitions (bridge with
//! track, train) that the FMUs wrap.

mod ahead;
pub use ahead::MAX_LAG;
pub mod monolithic;
pub mod partitioned;
pub mod sample;

use crate::newmark::Newmark;
use crate::track::{rail_motion, RailProfile};
use crate::train::TrainRun;
use crate::vehicle::LinearVehicle;
use nalgebra::{DVector, Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

pub use monolithic::Monolithic;

/// Displacement, velocity and acceleration of a vehicle's free DOFs.
#[derive(Debug, PartialEq, Serialize, Deserialize)]
pub struct VehicleState {
    pub v: DVector<f64>,
    pub vd: DVector<f64>,
    pub vdd: DVector<f64>,
}

impl Clone for VehicleState {
    fn clone(&self) -> Self {
        VehicleState {
            v: self.v.clone(),
            vd: self.vd.clone(),
            vdd: self.vdd.clone(),
        }
    }

    /// Copies into the existing vectors when the sizes agree.
    fn clone_from(&mut self, source: &Self) {
        for (to, from) in [
            (&mut self.v, &source.v),
            (&mut self.vd, &source.vd),
            (&mut self.vdd, &source.vdd),
        ] {
            if to.len() == from.len() {
                to.as_mut_slice().copy_from_slice(from.as_slice());
            } else {
                *to = from.clone();
            }
        }
    }
}

impl VehicleState {
    /// Static equilibrium on the rail under the wheelsets (`rails[l] = (u, u̇, ü)`):
    /// `K v = −Σ K_vw u`, quasi-static velocity `K v̇ = −Σ K_vw u̇`, and the acceleration from
    /// the equations of motion.
    pub fn initial(model: &LinearVehicle, rails: &[[Vector3<f64>; 3]]) -> Self {
        Self::initial_loaded(model, rails, None)
    }

    /// As [`Self::initial`], with the external forces `f` (one per DOF, beyond the static
    /// loads: the wind's) in the initial acceleration.
    pub fn initial_loaded(
        model: &LinearVehicle,
        rails: &[[Vector3<f64>; 3]],
        f: Option<&DVector<f64>>,
    ) -> Self {
        let n = model.ndof();
        if n == 0 {
            return VehicleState {
                v: DVector::zeros(0),
                vd: DVector::zeros(0),
                vdd: DVector::zeros(0),
            };
        }
        let chol = model
            .k
            .clone()
            .cholesky()
            .expect("vehicle stiffness is positive definite");
        let mut fu = DVector::zeros(n);
        let mut fud = DVector::zeros(n);
        for (c, r) in model.wheelsets.iter().zip(rails) {
            fu -= &c.k_vw * r[0];
            fud -= &c.k_vw * r[1];
        }
        let v = chol.solve(&fu);
        let vd = chol.solve(&fud);
        let mut rhs = -(&model.c * &vd) - &model.k * &v;
        for (c, r) in model.wheelsets.iter().zip(rails) {
            rhs -= &c.k_vw * r[0] + &c.c_vw * r[1];
        }
        if let Some(f) = f {
            rhs += f;
        }
        let vdd = model
            .m
            .clone()
            .cholesky()
            .expect("vehicle mass matrix is positive definite")
            .solve(&rhs);
        VehicleState { v, vd, vdd }
    }

    /// Newmark update to the new displacement `v1`.
    ///
    /// Returns whether any of `v`, `v̇`, `v̈` changed (bit for bit).
    pub fn newmark_update(&mut self, nm: &Newmark, v1: &DVector<f64>) -> bool {
        assert_eq!(v1.len(), self.v.len(), "one new displacement per DOF");
        // the bits that differ, of every value (one pass without a branch per DOF)
        let mut differ = 0u64;
        let (v, vd, vdd) = (
            self.v.as_mut_slice(),
            self.vd.as_mut_slice(),
            self.vdd.as_mut_slice(),
        );
        let states = v.iter_mut().zip(vd.iter_mut()).zip(vdd.iter_mut());
        for (&x1, ((x, xd), xdd)) in v1.as_slice().iter().zip(states) {
            let (d, a) = nm.update(x1, *x, *xd, *xdd);
            differ |= (x1.to_bits() ^ x.to_bits())
                | (d.to_bits() ^ xd.to_bits())
                | (a.to_bits() ^ xdd.to_bits());
            (*x, *xd, *xdd) = (x1, d, a);
        }
        differ != 0
    }
}

/// Prescribed (non-deck) rail motion of wheelset `w` of the train running as `run` (numbered
/// within it) at position `x` and time `t`: track irregularity plus hunting, as
/// `(r, ṙ, r̈)` in rail-DOF order, `(r, v r′, v² r″)` at the train's velocity along x at `t`.
/// With a changing speed the term `a r′` of `r̈` is left out (in both solvers alike; the
/// bridge FMU takes positions and speeds): on a wavelength λ it is `a λ / (2π v²)` of
/// `v² r″`, at 1 m/s² on 80 m 1.4 % at 30 m/s and more at lower speeds (see
/// `docs/scenario.md`).
pub fn rail_prescribed(
    track: &dyn RailProfile,
    run: &TrainRun,
    w: usize,
    x: f64,
    t: f64,
) -> [Vector3<f64>; 3] {
    let h = run.hunting_at(w, t);
    add_hunting(&rail_motion(&track.at(x), run.vx(t)), &h)
}

/// `to` made to share `from`'s allocation, without touching the reference counts when it
/// already does: a rollback copies a model's `Arc`s of constant data on every restore, and
/// `Arc::clone_from` would otherwise increment one count and decrement another each time.
#[inline]
pub fn share<T: ?Sized>(to: &mut Arc<T>, from: &Arc<T>) {
    if !Arc::ptr_eq(to, from) {
        *to = from.clone();
    }
}

/// `rail` with the lateral hunting motion `h = (Y_h, Ẏ_h, Ÿ_h)` added.
pub(crate) fn add_hunting(rail: &[Vector3<f64>; 3], h: &[f64; 3]) -> [Vector3<f64>; 3] {
    let mut r = *rail;
    r[0].x += h[0];
    r[1].x += h[1];
    r[2].x += h[2];
    r
}

/// What the force of one wheelset on the rail (eq. 6) needs, in one place: its own blocks
/// and the non-zero entries of `K_wv = K_vwᵀ`, `C_wv = C_vwᵀ` (3 rows each).
#[derive(Debug, Clone)]
pub(crate) struct WheelForce {
    p0: Vector3<f64>,
    /// The diagonals of `M_w`, `K_ww`, `C_ww` (all a coach has of them).
    m_w: Vector3<f64>,
    k_ww: Vector3<f64>,
    c_ww: Vector3<f64>,
    /// Their entries off the diagonal where any is non-zero.
    off_diagonal: Vec<RailEntry>,
    entries: Vec<WheelEntry>,
    /// No mass, stiffness or damping between the wheelset and the rail or its vehicle: the
    /// force is `p0` whatever the motion (a moving force).
    constant: bool,
}

impl WheelForce {
    /// Per wheelset of `train` (`wheelsets`, [`Train::wheelsets`]), what its force needs;
    /// the wheelsets at the same place of vehicles of one model (the same `Arc`, as the
    /// coaches of one train) share one copy, so a step reads one copy of it.
    pub(crate) fn of_train(
        train: &crate::train::Train,
        wheelsets: &[crate::train::WheelsetRef],
    ) -> Vec<Arc<WheelForce>> {
        let first_of = train.first_of_same_model();
        // where each vehicle's wheelsets start in `wheelsets` (front to back, by vehicle)
        let mut start = vec![0; train.vehicles.len()];
        for (w, ws) in wheelsets.iter().enumerate().rev() {
            start[ws.vehicle] = w;
        }
        let mut out: Vec<Arc<WheelForce>> = Vec::with_capacity(wheelsets.len());
        for ws in wheelsets {
            let same = start[first_of[ws.vehicle]] + ws.local;
            let f = match out.get(same) {
                Some(first) => first.clone(),
                None => {
                    let model = &train.vehicles[ws.vehicle].model;
                    Arc::new(WheelForce::of(&model.wheelsets[ws.local]))
                }
            };
            out.push(f);
        }
        out
    }

    pub(crate) fn of(c: &crate::vehicle::WheelsetCoupling) -> Self {
        let mut entries = Vec::new();
        for row in 0..3 {
            for dof in 0..c.k_vw.nrows() {
                let (k, cv) = (c.k_vw[(dof, row)], c.c_vw[(dof, row)]);
                if k != 0.0 || cv != 0.0 {
                    entries.push(WheelEntry { row, dof, k, c: cv });
                }
            }
        }
        let mut off_diagonal = Vec::new();
        for row in 0..3 {
            for col in (0..3).filter(|&col| col != row) {
                let (m, k, cw) = (c.m_w[(row, col)], c.k_ww[(row, col)], c.c_ww[(row, col)]);
                if m != 0.0 || k != 0.0 || cw != 0.0 {
                    off_diagonal.push(RailEntry {
                        row,
                        col,
                        m,
                        k,
                        c: cw,
                    });
                }
            }
        }
        let zero = |m: &Matrix3<f64>| m.iter().all(|&v| v == 0.0);
        WheelForce {
            p0: c.p0,
            m_w: c.m_w.diagonal(),
            k_ww: c.k_ww.diagonal(),
            c_ww: c.c_ww.diagonal(),
            off_diagonal,
            constant: entries.is_empty() && zero(&c.m_w) && zero(&c.k_ww) && zero(&c.c_ww),
            entries,
        }
    }

    /// The force on the rail of the wheelset with rail motion `(u, u̇, ü)` under vehicle state
    /// `s`: eq. (6) as [`LinearVehicle::wheel_force`], with `K_wv v + C_wv v̇` from the
    /// non-zero entries of `K_wv`, `C_wv` (a wheelset couples to a few of its vehicle's DOFs).
    #[inline]
    pub(crate) fn force(&self, s: &VehicleState, rail: &[Vector3<f64>; 3]) -> Vector3<f64> {
        if self.constant {
            // p0 − 0·ü − 0·u − 0·u̇ for a finite motion, without the products
            return self.p0;
        }
        let [u, ud, udd] = rail;
        // the diagonal products, then those off it (a coach has none)
        let mut f = Vector3::from_fn(|i, _| {
            self.p0[i] - self.m_w[i] * udd[i] - self.k_ww[i] * u[i] - self.c_ww[i] * ud[i]
        });
        for e in &self.off_diagonal {
            f[e.row] -= e.m * udd[e.col] + e.k * u[e.col] + e.c * ud[e.col];
        }
        let (v, vd) = (s.v.as_slice(), s.vd.as_slice());
        for e in &self.entries {
            f[e.row] -= e.k * v[e.dof] + e.c * vd[e.dof];
        }
        f
    }
}

/// Row `row` (force component), column `col` (rail DOF) off the diagonal of a wheelset's
/// `M_w`, `K_ww` and `C_ww`, where any is non-zero.
#[derive(Debug, Clone, Copy)]
struct RailEntry {
    row: usize,
    col: usize,
    m: f64,
    k: f64,
    c: f64,
}

/// Row `row` (force component), column `dof` (vehicle DOF) of a wheelset's `K_wv` and `C_wv`,
/// where either is non-zero.
#[derive(Debug, Clone, Copy)]
struct WheelEntry {
    row: usize,
    dof: usize,
    k: f64,
    c: f64,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vehicle::WheelsetCoupling;
    use nalgebra::DMatrix;

    /// The wheelsets at the same place of vehicles of one model (one `Arc`) share their
    /// force data; a vehicle of an equal model built apart keeps its own (its own `Arc`); and
    /// the shared data gives each wheelset the force its own would.
    /// `share` leaves an `Arc` that already shares the allocation alone (no count moves) and
    /// otherwise makes it share the other's, releasing its own.
    #[test]
    fn share_moves_no_count_when_already_shared() {
        let a = Arc::new(1.0);
        let mut b = a.clone();
        share(&mut b, &a);
        assert_eq!(Arc::strong_count(&a), 2);
        let c = Arc::new(2.0);
        share(&mut b, &c);
        assert!(Arc::ptr_eq(&b, &c));
        assert_eq!((Arc::strong_count(&a), Arc::strong_count(&c)), (1, 2));
    }

    /// A vehicle state of `n` DOFs and a rail motion `(u, u̇, ü)`, all components non-zero.
    fn state_and_rail(n: usize) -> (VehicleState, [Vector3<f64>; 3]) {
        let state = VehicleState {
            v: DVector::from_fn(n, |i, _| (i as f64 * 0.37).sin() * 1e-3),
            vd: DVector::from_fn(n, |i, _| (i as f64 * 0.71).cos() * 1e-2),
            vdd: DVector::zeros(n),
        };
        let rail = [
            Vector3::new(-1e-3, 2e-4, -3e-3),
            Vector3::new(4e-2, -5e-3, 6e-2),
            Vector3::new(-0.7, 0.8, -0.9),
        ];
        (state, rail)
    }

    /// The force from the blocks' diagonals and non-zero entries equals eq. (6) with the full
    /// matrices ([`LinearVehicle::wheel_force`]): on the coach, whose `M_w`, `K_ww`, `C_ww`
    /// are diagonal, and with entries added off their diagonals.
    #[test]
    fn the_wheel_force_equals_eq_6_with_the_full_blocks() {
        let mut coach = crate::vehicle::coach::CoachParams::xia2000()
            .build()
            .unwrap();
        let (state, rail) = state_and_rail(coach.ndof());
        for off_diagonal in [false, true] {
            if off_diagonal {
                let ws = &mut coach.wheelsets[1];
                ws.k_ww[(0, 1)] = 3.0e5;
                ws.k_ww[(1, 0)] = 3.0e5;
                ws.c_ww[(2, 1)] = -40.0;
                ws.m_w[(1, 2)] = 7.0;
            }
            for w in 0..coach.wheelsets.len() {
                let f = WheelForce::of(&coach.wheelsets[w]);
                assert_eq!(
                    f.off_diagonal.len(),
                    if off_diagonal && w == 1 { 4 } else { 0 }
                );
                let got = f.force(&state, &rail);
                let [u, ud, udd] = &rail;
                let want = coach.wheel_force(w, &state.v, &state.vd, u, ud, udd);
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() <= 1e-12 * want.amax(),
                        "wheelset {w}, component {k}: {} against {}",
                        got[k],
                        want[k]
                    );
                }
            }
        }
    }

    #[test]
    fn wheelsets_of_one_model_share_their_force_data() {
        use crate::train::{Train, TrainVehicle};
        use std::sync::Arc;
        let build = || {
            Arc::new(
                crate::vehicle::coach::CoachParams::xia2000()
                    .build()
                    .unwrap(),
            )
        };
        let (coach, apart) = (build(), build());
        let vehicle = |model: &Arc<LinearVehicle>, k: f64| TrainVehicle {
            model: model.clone(),
            offset_m: 25.0 * k,
            run: 0,
        };
        let vehicles = vec![
            vehicle(&coach, 0.0),
            vehicle(&coach, 1.0),
            vehicle(&apart, 2.0),
        ];
        let hunting = tbi_track::WheelHunting::new(&Default::default(), 12).unwrap();
        let run = crate::train::TrainRun::steady(20.0, 0.0, Default::default(), hunting);
        let train = Train::single(vehicles, run);
        let wheelsets = train.wheelsets();
        let forces = WheelForce::of_train(&train, &wheelsets);
        assert_eq!(forces.len(), 12);
        for (w, ws) in wheelsets.iter().enumerate() {
            let first = [ws.local, ws.local, 8 + ws.local][ws.vehicle];
            assert!(Arc::ptr_eq(&forces[w], &forces[first]), "wheelset {w}");
            if first != w {
                assert!(ws.vehicle == 1, "wheelset {w}");
            }
            let own = WheelForce::of(&train.vehicles[ws.vehicle].model.wheelsets[ws.local]);
            let (state, rail) = state_and_rail(train.vehicles[ws.vehicle].model.ndof());
            assert_eq!(forces[w].force(&state, &rail), own.force(&state, &rail));
        }
        assert!(!Arc::ptr_eq(&forces[0], &forces[8]));
    }

    /// A moving force (no mass, stiffness or damping) gives `p0` bit for bit as the full
    /// formula does for a finite motion of either sign; a wheelset with mass does not.
    #[test]
    fn a_moving_force_is_its_static_load_as_the_full_formula_gives() {
        let coupling = |m: f64| WheelsetCoupling {
            offset_m: 0.0,
            k_vw: DMatrix::zeros(0, 3),
            c_vw: DMatrix::zeros(0, 3),
            k_ww: Matrix3::zeros(),
            c_ww: Matrix3::zeros(),
            m_w: Matrix3::from_diagonal(&Vector3::new(m, 0.0, m)),
            p0: Vector3::new(0.0, 0.0, 1.7e5),
            still_air_load_n: None,
        };
        let state = VehicleState {
            v: DVector::zeros(0),
            vd: DVector::zeros(0),
            vdd: DVector::zeros(0),
        };
        let rail = [
            Vector3::new(-1e-3, 2e-4, -3e-3),
            Vector3::new(4e-2, -5e-3, 6e-2),
            Vector3::new(-0.7, 0.8, -0.9),
        ];
        let full = |c: &WheelsetCoupling| {
            let [u, ud, udd] = &rail;
            c.p0 - c.m_w * udd - c.k_ww * u - c.c_ww * ud
        };
        let moving = coupling(0.0);
        let f = WheelForce::of(&moving).force(&state, &rail);
        assert!(WheelForce::of(&moving).constant);
        assert_eq!(f.map(f64::to_bits), full(&moving).map(f64::to_bits));
        let massive = coupling(1200.0);
        assert!(!WheelForce::of(&massive).constant);
        let f = WheelForce::of(&massive).force(&state, &rail);
        assert_eq!(f.map(f64::to_bits), full(&massive).map(f64::to_bits));
        assert_ne!(f, massive.p0);
    }
}
